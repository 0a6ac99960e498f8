// File: semgraph/ros/bag_reader.h
//
// The common interface of semgraph's bag readers (docs/ros.md, "Bag formats"): MCAP, rosbag2
// sqlite3 and ROS 1 bag v2.0 each implement BagReader, a streaming reader that yields the bag's
// messages one record at a time in log-time order, with bounded memory (never the whole file).
//
// Invariants:
//  - Records come in non-decreasing log_time_ns; records with equal log times keep the order of
//    the file (MCAP: chunk order, then position in the chunk).
//  - A BagRecord's views (topic, type_name, data) stay valid until the next call of Next() or the
//    reader's destruction; copy what must outlive that.
//  - A corrupt file (bad magic, a record or string longer than the bytes left, a CRC that does
//    not match, a chunk that does not decompress to its declared size, a declared size over the
//    limit) makes Open or Next fail with a BagError naming the file, the byte offset and what is
//    wrong. After an error the reader is finished: every later Next() returns the same error.
//    Callers that must apply nothing of a corrupt file read it to the end first (two passes).
//  - Formats are chosen by content (DetectBagFormat), never by file name.
// Costs: Open reads the header and what the format keeps up front (MCAP: the summary, and one
// scan of the data section's record headers, plus one CRC pass over the data section when the
// file stores that CRC). Next is amortized O(1) per record plus the decompression of the
// chunks; memory is bounded by the chunks open at once (BagReaderOptions) plus the index.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "semgraph/base/expected.h"
#include "semgraph/ros/export.h"

namespace semgraph::ros {

using base::Expected;
using base::Unexpected;

/// The storage formats of spec §3.
enum class BagFormat : std::uint8_t {
  kMcap,            ///< MCAP (rosbag2's default storage; one .mcap file)
  kRosbag2Sqlite3,  ///< rosbag2 sqlite3 (.db3, or a bag folder with metadata.yaml)
  kRos1,            ///< ROS 1 bag v2.0 (#ROSBAG V2.0)
};

/// How a record's bytes are serialized.
enum class MessageEncoding : std::uint8_t {
  kCdr,    ///< ROS 2 CDR with its 4-byte encapsulation header (messages.h: DecodeCdr)
  kRos1,   ///< ROS 1 serialization (messages.h: DecodeRos1)
  kOther,  ///< anything else (e.g. MCAP "json", "protobuf"); such records are yielded, not decoded
};

/// The message types semgraph decodes, recognised by type name (spec §3).
enum class MessageKind : std::uint8_t {
  kOther,       ///< any other type: the record is yielded with kind kOther (callers skip, count)
  kTfMessage,   ///< tf2_msgs/msg/TFMessage, tf2_msgs/TFMessage, tf/tfMessage
  kJointState,  ///< sensor_msgs/msg/JointState, sensor_msgs/JointState
  kString,      ///< std_msgs/msg/String, std_msgs/String (the URDF on /robot_description)
  kPoseWithCovarianceStamped,  ///< geometry_msgs/msg/PoseWithCovarianceStamped, ROS 1's name
  kOdometry,                   ///< nav_msgs/msg/Odometry, nav_msgs/Odometry
};

/// The kind of a type name (exact match, as listed above); kOther for any other name.
/// O(|name|), allocation-free.
[[nodiscard]] SEMGRAPH_ROS_EXPORT MessageKind MessageKindOf(std::string_view type_name) noexcept;

/// "cdr" -> kCdr, "ros1" -> kRos1, anything else -> kOther (MCAP's message_encoding names).
[[nodiscard]] SEMGRAPH_ROS_EXPORT MessageEncoding MessageEncodingOf(std::string_view name) noexcept;

/// "mcap", "rosbag2_sqlite3", "ros1".
[[nodiscard]] SEMGRAPH_ROS_EXPORT std::string_view ToString(BagFormat format) noexcept;
/// "cdr", "ros1", "other".
[[nodiscard]] SEMGRAPH_ROS_EXPORT std::string_view ToString(MessageEncoding encoding) noexcept;

/// One message of a bag. Views valid until the next Next() (see the invariants above).
struct BagRecord {
  std::string_view topic;      ///< e.g. "/tf"
  std::string_view type_name;  ///< as the bag spells it, e.g. "tf2_msgs/msg/TFMessage"
  MessageEncoding encoding = MessageEncoding::kOther;
  MessageKind kind = MessageKind::kOther;  ///< MessageKindOf(type_name)
  std::int64_t log_time_ns = 0;            ///< when the recorder received it (not the header stamp)
  std::span<const std::uint8_t> data;      ///< the serialized message (CDR: with its 4-byte header)
};

/// A topic (MCAP channel, sqlite3 topics row, ROS 1 connection) of the bag.
struct BagTopic {
  std::string name;
  std::string type_name;
  MessageEncoding encoding = MessageEncoding::kOther;
  MessageKind kind = MessageKind::kOther;
  /// Messages on the topic when the file says so up front (MCAP statistics, ROS 1 index);
  /// -1 when unknown before reading (sqlite3: counting would read the whole messages table).
  std::int64_t message_count = -1;
};

/// What is wrong with a bag (the message says it precisely).
enum class BagErrorCode : std::uint8_t {
  kIo,             ///< cannot open or read the file (errno text in the message)
  kUnknownFormat,  ///< not a bag of any supported format (wrong magic)
  kTruncated,      ///< the file ends inside a record, a chunk or before its footer/trailer
  kMalformed,      ///< a length, count, opcode or field that cannot be right
  kCrcMismatch,    ///< a CRC32 stored in the file does not match the bytes
  kOverLimit,      ///< a declared size over the reader's limit (BagReaderOptions)
  kDecompression,  ///< a chunk that fails to decompress, or not to its declared size
  kUnsupported,    ///< a valid file using something not supported (e.g. unknown compression)
};

/// "io", "unknown_format", "truncated", "malformed", "crc_mismatch", "over_limit",
/// "decompression", "unsupported".
[[nodiscard]] SEMGRAPH_ROS_EXPORT std::string_view ToString(BagErrorCode code) noexcept;

struct BagError {
  BagErrorCode code = BagErrorCode::kIo;
  std::string file;          ///< the path as given to Open
  std::uint64_t offset = 0;  ///< byte offset in the file where the problem is (0 for kIo)
  std::string message;       ///< what is wrong, e.g. "record length 9999 past the end (120 left)"
};

/// "FILE: byte OFFSET: MESSAGE (CODE)", one line, for users and logs.
[[nodiscard]] SEMGRAPH_ROS_EXPORT std::string Describe(const BagError& error);

struct BagReaderOptions {
  /// Largest decompressed chunk (or record) accepted: a chunk that declares more is kOverLimit,
  /// so that memory stays bounded and a decompression bomb is refused before inflating it.
  /// Also bounds a summary section, a schema or channel record, and a run of messages outside
  /// chunks. An MCAP reader keeps the chunks that overlap in log time open together (one or two
  /// for a recorder's bag) and refuses more than 4 × max_chunk_bytes of them (kOverLimit).
  std::uint64_t max_chunk_bytes = std::uint64_t{256} << 20;
  /// Check the CRC32s stored in the file (MCAP chunk, data-section and summary CRCs).
  bool verify_crc = true;
};

/// A streaming reader of one bag. Not copyable; not thread-safe (one reader per thread).
class SEMGRAPH_ROS_EXPORT BagReader {
 public:
  virtual ~BagReader();
  BagReader(const BagReader&) = delete;
  BagReader& operator=(const BagReader&) = delete;

  [[nodiscard]] virtual BagFormat format() const noexcept = 0;
  /// The path as given to Open.
  [[nodiscard]] virtual const std::string& path() const noexcept = 0;
  /// The topics known so far: all of them after Open when the format lists them up front
  /// (sqlite3, ROS 1 with index, MCAP with summary), otherwise they grow while reading.
  [[nodiscard]] virtual const std::vector<BagTopic>& topics() const noexcept = 0;

  /// The next record in log-time order into `out`: true when one was read, false at the end of
  /// the bag, or the error (then the reader is finished).
  [[nodiscard]] virtual Expected<bool, BagError> Next(BagRecord& out) = 0;

 protected:
  BagReader() = default;
};

using BagReaderPtr = std::unique_ptr<BagReader>;

/// The format of a file by its first bytes: MCAP magic, "SQLite format 3\0", "#ROSBAG V2.0\n".
/// A folder (a rosbag2 bag folder with metadata.yaml) has the format of the first of its files,
/// in name order, that is an MCAP or sqlite3 file. kIo when it cannot be read, kUnknownFormat
/// when it is none of them. Reads at most 16 bytes of a file.
[[nodiscard]] SEMGRAPH_ROS_EXPORT Expected<BagFormat, BagError> DetectBagFormat(
    const std::string& path);

/// The readers of each format (each in its own translation unit: mcap_reader.cc,
/// sqlite3_bag_reader.cc, ros1_bag_reader.cc).
[[nodiscard]] SEMGRAPH_ROS_EXPORT Expected<BagReaderPtr, BagError> OpenMcapBag(
    const std::string& path, const BagReaderOptions& options = {});
[[nodiscard]] SEMGRAPH_ROS_EXPORT Expected<BagReaderPtr, BagError> OpenRosbag2Sqlite3Bag(
    const std::string& path, const BagReaderOptions& options = {});
[[nodiscard]] SEMGRAPH_ROS_EXPORT Expected<BagReaderPtr, BagError> OpenRos1Bag(
    const std::string& path, const BagReaderOptions& options = {});

/// Detects the format and opens the matching reader; a folder opens its storage file (defined in
/// open_bag.cc beside the three readers). Each Open* takes a file path.
[[nodiscard]] SEMGRAPH_ROS_EXPORT Expected<BagReaderPtr, BagError> OpenBag(
    const std::string& path, const BagReaderOptions& options = {});

}  // namespace semgraph::ros
