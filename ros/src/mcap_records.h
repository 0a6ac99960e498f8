// MCAP records (the MCAP specification, "Records" and "Serialization"): a bounds-checked
// little-endian cursor, and the parsed forms of the records the reader uses. Internal to ros/.
//
// Invariants: a Cursor never reads outside its span; a read past the end sets the failure, with
// the file offset of the field and what was being read, and every later read is a no-op.
// Costs: O(bytes read); parsing allocates only the strings it returns.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace semgraph::ros::detail {

/// MCAP opcodes.
enum class McapOp : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

inline constexpr std::uint8_t kMcapMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
inline constexpr std::size_t kRecordPrefix = 9;  ///< opcode (1) + content length (8)
inline constexpr std::size_t kFooterRecord = kRecordPrefix + 8 + 8 + 4;

/// A little-endian reader over bytes that lie at `base` in the file (for error offsets).
class Cursor {
 public:
  Cursor(std::span<const std::uint8_t> bytes, std::uint64_t base) : bytes_(bytes), base_(base) {}

  std::uint8_t U8(const char* what);
  std::uint16_t U16(const char* what);
  std::uint32_t U32(const char* what);
  std::uint64_t U64(const char* what);
  /// uint32 length + bytes.
  std::string_view Str(const char* what);
  /// `n` bytes as they are.
  std::span<const std::uint8_t> Bytes(std::uint64_t n, const char* what);
  /// Skips a uint32-length-prefixed map or array.
  void SkipPrefixed(const char* what);

  [[nodiscard]] bool failed() const { return failed_; }
  [[nodiscard]] std::size_t pos() const { return pos_; }
  [[nodiscard]] std::size_t left() const { return bytes_.size() - pos_; }
  [[nodiscard]] std::uint64_t file_offset() const { return base_ + pos_; }
  /// The failure: file offset and message ("... past the end of the record").
  [[nodiscard]] std::uint64_t error_offset() const { return error_offset_; }
  [[nodiscard]] const std::string& error() const { return error_; }
  void Fail(std::uint64_t file_offset, std::string message);

 private:
  bool Need(std::uint64_t n, const char* what);

  std::span<const std::uint8_t> bytes_;
  std::uint64_t base_;
  std::size_t pos_ = 0;
  bool failed_ = false;
  std::uint64_t error_offset_ = 0;
  std::string error_;
};

struct McapSchema {
  std::uint16_t id = 0;
  std::string name;
};

struct McapChannel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;
  std::string topic;
  std::string message_encoding;
};

/// The fixed fields of a Chunk record; `records` is the offset and size of its payload inside
/// the record's content (the caller checks that they lie inside the record).
struct McapChunkHeader {
  std::uint64_t start_time = 0;
  std::uint64_t end_time = 0;
  std::uint64_t uncompressed_size = 0;
  std::uint32_t uncompressed_crc = 0;
  std::string compression;
  std::uint64_t records_offset = 0;  ///< from the start of the record's content
  std::uint64_t records_size = 0;
};

struct McapChunkIndex {
  std::uint64_t start_time = 0;
  std::uint64_t end_time = 0;
  std::uint64_t chunk_offset = 0;
  std::uint64_t chunk_length = 0;
};

/// The fixed header of a Message record (its data follows: content length − 22 bytes).
struct McapMessageHeader {
  std::uint16_t channel_id = 0;
  std::uint64_t log_time = 0;
};
inline constexpr std::size_t kMessageHeaderBytes = 2 + 4 + 8 + 8;

/// Each parser reads the record's content (after opcode and length); on a short or bad field
/// the cursor holds the failure.
void ParseSchema(Cursor& c, McapSchema& out);
void ParseChannel(Cursor& c, McapChannel& out);
void ParseChunkHeader(Cursor& c, McapChunkHeader& out);
void ParseChunkIndex(Cursor& c, McapChunkIndex& out);
void ParseMessageHeader(Cursor& c, McapMessageHeader& out);
/// Statistics: the channel_message_counts map as (channel id, count) pairs.
void ParseStatistics(Cursor& c, std::vector<std::pair<std::uint16_t, std::uint64_t>>& counts);

}  // namespace semgraph::ros::detail
