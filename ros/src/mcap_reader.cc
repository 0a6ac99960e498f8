// The MCAP bag reader, written from the MCAP specification (no MCAP library is packaged in
// Debian). Plan:
//  1. Open: magic at both ends, the Header, the Footer; the summary section when there is one
//     (its CRC, schemas, channels, statistics, chunk indexes); then one scan of the data
//     section's record headers (chunk bodies are skipped), which checks the structure, registers
//     schemas and channels, and lists the blocks to read: each Chunk, and each run of Message
//     records outside chunks, with its log-time range. The chunk indexes, when present, must
//     agree with the scan. When the DataEnd record carries a CRC, the data section is read once
//     more through the CRC (so a corrupt file fails at Open).
//  2. Next: a merge in log-time order. Blocks are opened (read, CRC-checked, decompressed, their
//     messages stably sorted by log time) in order of their first log time, only when the
//     smallest pending message is not earlier than that time; so only the blocks overlapping
//     in time are in memory, and ties keep file order.
#include <algorithm>
#include <limits>
#include <optional>
#include <unordered_map>

#include "bag_file.h"
#include "crc32.h"
#include "decompress.h"
#include "mcap_records.h"
#include "semgraph/ros/bag_reader.h"

namespace semgraph::ros {
namespace {

using detail::BagFile;
using detail::Cursor;
using detail::McapOp;

// A chunk or a run of loose messages, in the order of the file.
struct Block {
  std::uint64_t offset = 0;  // first byte of the Chunk record, or of the run's first record
  std::uint64_t length = 0;  // bytes from offset (a chunk: the whole record)
  std::uint64_t start_time = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t end_time = 0;
  bool chunk = false;
};

struct Entry {
  std::uint64_t log_time;
  std::size_t data_offset;
  std::size_t data_size;
  std::uint32_t topic;
};

struct OpenBlock {
  std::size_t order = 0;  // index of the block in file order
  std::vector<std::uint8_t> bytes;
  std::vector<Entry> entries;
  std::size_t next = 0;
};

class McapReader final : public BagReader {
 public:
  McapReader(std::string path, BagReaderOptions options)
      : path_(std::move(path)), options_(options) {}

  [[nodiscard]] BagFormat format() const noexcept override { return BagFormat::kMcap; }
  [[nodiscard]] const std::string& path() const noexcept override { return path_; }
  [[nodiscard]] const std::vector<BagTopic>& topics() const noexcept override { return topics_; }

  std::optional<BagError> Open();
  Expected<bool, BagError> Next(BagRecord& out) override;

 private:
  BagError Error(BagErrorCode code, std::uint64_t offset, std::string message) const {
    return BagError{code, path_, offset, std::move(message)};
  }
  std::optional<BagError> IoError(const std::string& message) const {
    return Error(message.find("passes the end") != std::string::npos ? BagErrorCode::kTruncated
                                                                     : BagErrorCode::kIo,
                 0, message);
  }
  std::optional<BagError> ReadFooter();
  std::optional<BagError> ReadSummary();
  std::optional<BagError> ScanData(std::uint64_t from, std::uint64_t to);
  std::optional<BagError> ScanChunk(std::uint64_t at, std::uint64_t length);
  std::optional<BagError> ScanAttachment(std::uint64_t at, std::uint64_t length);
  std::optional<BagError> CheckIndex() const;
  std::optional<BagError> CheckDataCrc(std::uint64_t data_end, std::uint32_t expected);
  std::optional<BagError> Register(McapOp op, Cursor& c, std::uint64_t at, bool summary);
  std::optional<BagError> LoadBlock(std::size_t order, OpenBlock& out);
  std::optional<BagError> ParseRecords(std::size_t body, std::uint64_t base, bool exact_offsets,
                                       const Block& block, OpenBlock& out);
  std::optional<BagError> OpenDueBlocks();

  std::string path_;
  BagReaderOptions options_;
  BagFile file_;
  std::vector<BagTopic> topics_;
  std::unordered_map<std::uint16_t, std::string> schemas_;     // id -> type name
  std::unordered_map<std::uint16_t, std::uint32_t> channels_;  // id -> topics_ index
  std::unordered_map<std::uint16_t, detail::McapChannel> channel_defs_;
  std::vector<detail::McapChunkIndex> chunk_index_;
  std::vector<Block> blocks_;          // file order
  std::vector<std::size_t> by_start_;  // block indices by (start_time, file order)
  std::size_t next_start_ = 0;         // next entry of by_start_ to open
  std::vector<OpenBlock> open_;
  std::uint64_t open_bytes_ = 0;
  std::uint64_t footer_at_ = 0;
  std::uint64_t summary_start_ = 0;
  std::uint64_t summary_offset_start_ = 0;
  std::uint32_t summary_crc_ = 0;
  std::optional<BagError> failed_;
};

// ---- Open ----

std::optional<BagError> McapReader::Open() {
  std::string io;
  if (!file_.Open(path_, io)) return Error(BagErrorCode::kIo, 0, io);
  const std::uint64_t size = file_.size();
  std::span<const std::uint8_t> head;
  if (!file_.Peek(0, std::min<std::uint64_t>(size, 8), head, io)) return IoError(io);
  if (head.size() < 8 || !std::equal(head.begin(), head.end(), detail::kMcapMagic)) {
    return Error(BagErrorCode::kUnknownFormat, 0, "not an MCAP file: wrong magic bytes");
  }
  if (auto e = ReadFooter()) return e;
  // The Header record follows the magic.
  if (!file_.Peek(8, detail::kRecordPrefix, head, io)) return IoError(io);
  Cursor c(head, 8);
  const std::uint8_t op = c.U8("opcode");
  const std::uint64_t len = c.U64("record length");
  if (op != static_cast<std::uint8_t>(McapOp::kHeader)) {
    return Error(BagErrorCode::kMalformed, 8,
                 "the first record is opcode " + std::to_string(op) + ", not a Header (1)");
  }
  const std::uint64_t data_start = 8 + detail::kRecordPrefix + len;
  const std::uint64_t data_limit =
      summary_start_ != 0 ? summary_start_
                          : (summary_offset_start_ != 0 ? summary_offset_start_ : footer_at_);
  if (len > footer_at_ || data_start > data_limit) {
    return Error(BagErrorCode::kMalformed, 9,
                 "Header record length " + std::to_string(len) + " past the data section");
  }
  if (auto e = ReadSummary()) return e;
  if (auto e = ScanData(data_start, data_limit)) return e;
  if (auto e = CheckIndex()) return e;
  by_start_.resize(blocks_.size());
  for (std::size_t i = 0; i < by_start_.size(); ++i) by_start_[i] = i;
  std::stable_sort(by_start_.begin(), by_start_.end(), [this](std::size_t a, std::size_t b) {
    return blocks_[a].start_time < blocks_[b].start_time;
  });
  return std::nullopt;
}

std::optional<BagError> McapReader::ReadFooter() {
  const std::uint64_t size = file_.size();
  constexpr std::uint64_t kMin = 8 + detail::kRecordPrefix + detail::kFooterRecord + 8;
  std::string io;
  std::span<const std::uint8_t> tail;
  if (size < kMin) {
    return Error(BagErrorCode::kTruncated, size,
                 "file of " + std::to_string(size) + " bytes is shorter than the smallest MCAP (" +
                     std::to_string(kMin) + ")");
  }
  if (!file_.Peek(size - 8, 8, tail, io)) return IoError(io);
  if (!std::equal(tail.begin(), tail.end(), detail::kMcapMagic)) {
    return Error(BagErrorCode::kTruncated, size - 8,
                 "the file does not end with the MCAP magic: truncated, or still being written");
  }
  footer_at_ = size - 8 - detail::kFooterRecord;
  if (!file_.Peek(footer_at_, detail::kFooterRecord, tail, io)) return IoError(io);
  Cursor c(tail, footer_at_);
  const std::uint8_t op = c.U8("opcode");
  const std::uint64_t len = c.U64("record length");
  summary_start_ = c.U64("footer summary_start");
  summary_offset_start_ = c.U64("footer summary_offset_start");
  summary_crc_ = c.U32("footer summary_crc");
  if (op != static_cast<std::uint8_t>(McapOp::kFooter) || len != 20) {
    return Error(BagErrorCode::kMalformed, footer_at_,
                 "no Footer record (opcode 2, length 20) before the closing magic");
  }
  if (summary_start_ > footer_at_ || summary_offset_start_ > footer_at_ ||
      (summary_start_ != 0 && summary_offset_start_ != 0 &&
       summary_offset_start_ < summary_start_)) {
    return Error(BagErrorCode::kMalformed, footer_at_ + detail::kRecordPrefix,
                 "footer summary offsets " + std::to_string(summary_start_) + ", " +
                     std::to_string(summary_offset_start_) + " lie outside the file");
  }
  return std::nullopt;
}

std::optional<BagError> McapReader::ReadSummary() {
  if (summary_start_ == 0) return std::nullopt;
  const std::uint64_t end = summary_offset_start_ != 0 ? summary_offset_start_ : footer_at_;
  // The CRC covers the summary through the footer's summary_offset_start field.
  const std::uint64_t crc_end = footer_at_ + detail::kRecordPrefix + 16;
  if (crc_end - summary_start_ > options_.max_chunk_bytes) {
    return Error(BagErrorCode::kOverLimit, summary_start_,
                 "summary section of " + std::to_string(crc_end - summary_start_) +
                     " bytes over the reader's limit of " +
                     std::to_string(options_.max_chunk_bytes));
  }
  std::vector<std::uint8_t> bytes;
  std::string io;
  if (!file_.Read(summary_start_, crc_end - summary_start_, bytes, io)) return IoError(io);
  if (options_.verify_crc && summary_crc_ != 0) {
    const std::uint32_t crc = detail::Crc32Update(0, bytes);
    if (crc != summary_crc_) {
      return Error(BagErrorCode::kCrcMismatch, summary_start_,
                   "summary section CRC32 " + std::to_string(crc) + " does not match the " +
                       "footer's " + std::to_string(summary_crc_));
    }
  }
  Cursor c(std::span<const std::uint8_t>(bytes).first(end - summary_start_), summary_start_);
  while (!c.failed() && c.left() > 0) {
    const std::uint64_t at = c.file_offset();
    const auto op = static_cast<McapOp>(c.U8("opcode"));
    const auto content = c.Bytes(c.U64("record length"), "summary record");
    if (c.failed()) break;
    Cursor r(content, at + detail::kRecordPrefix);
    if (op == McapOp::kChunkIndex) {
      detail::ParseChunkIndex(r, chunk_index_.emplace_back());
    } else if (op == McapOp::kStatistics) {
      std::vector<std::pair<std::uint16_t, std::uint64_t>> counts;
      detail::ParseStatistics(r, counts);
      for (const auto& [id, n] : counts) {
        if (auto it = channels_.find(id); it != channels_.end()) {
          topics_[it->second].message_count = static_cast<std::int64_t>(n);
        }
      }
    } else if (auto e = Register(op, r, at, true)) {
      return e;
    }
    if (r.failed()) return Error(BagErrorCode::kMalformed, r.error_offset(), r.error());
  }
  if (c.failed()) return Error(BagErrorCode::kMalformed, c.error_offset(), c.error());
  return std::nullopt;
}

// Schema and Channel records (others: nothing to do). A redefinition must be identical.
std::optional<BagError> McapReader::Register(McapOp op, Cursor& c, std::uint64_t at,
                                             bool /*summary*/) {
  if (op == McapOp::kSchema) {
    detail::McapSchema s;
    detail::ParseSchema(c, s);
    if (c.failed()) return std::nullopt;  // the caller reports the cursor's failure
    auto [it, added] = schemas_.emplace(s.id, s.name);
    if (!added && it->second != s.name) {
      return Error(BagErrorCode::kMalformed, at,
                   "schema " + std::to_string(s.id) + " redefined with another name");
    }
  } else if (op == McapOp::kChannel) {
    detail::McapChannel ch;
    detail::ParseChannel(c, ch);
    if (c.failed()) return std::nullopt;
    if (auto it = channel_defs_.find(ch.id); it != channel_defs_.end()) {
      const auto& old = it->second;
      if (old.topic != ch.topic || old.schema_id != ch.schema_id ||
          old.message_encoding != ch.message_encoding) {
        return Error(BagErrorCode::kMalformed, at,
                     "channel " + std::to_string(ch.id) + " redefined differently");
      }
      return std::nullopt;
    }
    std::string type;
    if (ch.schema_id != 0) {
      const auto s = schemas_.find(ch.schema_id);
      if (s == schemas_.end()) {
        return Error(BagErrorCode::kMalformed, at,
                     "channel " + std::to_string(ch.id) + " refers to schema " +
                         std::to_string(ch.schema_id) + ", which no earlier record defines");
      }
      type = s->second;
    }
    BagTopic t;
    t.name = ch.topic;
    t.type_name = std::move(type);
    t.encoding = MessageEncodingOf(ch.message_encoding);
    t.kind = MessageKindOf(t.type_name);
    channels_.emplace(ch.id, static_cast<std::uint32_t>(topics_.size()));
    topics_.push_back(std::move(t));
    channel_defs_.emplace(ch.id, std::move(ch));
  }
  return std::nullopt;
}

// ---- The scan of the data section ----

std::optional<BagError> McapReader::ScanData(std::uint64_t from, std::uint64_t to) {
  std::string io;
  std::span<const std::uint8_t> b;
  std::optional<Block> run;  // the current run of loose messages
  const auto close_run = [&] {
    if (run) blocks_.push_back(*run);
    run.reset();
  };
  std::uint64_t pos = from;
  while (pos < to) {
    if (to - pos < detail::kRecordPrefix) {
      return Error(BagErrorCode::kMalformed, pos,
                   std::to_string(to - pos) + " stray bytes at the end of the data section");
    }
    if (!file_.Peek(pos, detail::kRecordPrefix, b, io)) return IoError(io);
    Cursor c(b, pos);
    const std::uint8_t opcode = c.U8("opcode");
    const std::uint64_t len = c.U64("record length");
    const auto op = static_cast<McapOp>(opcode);
    const std::uint64_t content = pos + detail::kRecordPrefix;
    if (len > to - content) {
      const bool past_file = len > file_.size() - content;
      return Error(past_file ? BagErrorCode::kTruncated : BagErrorCode::kMalformed, pos + 1,
                   "record (opcode " + std::to_string(opcode) + ") of " + std::to_string(len) +
                       " bytes runs past the end of the " + (past_file ? "file" : "data section") +
                       " (" + std::to_string(to - content) + " bytes left)");
    }
    const std::uint64_t next = content + len;
    if (opcode == 0 || op == McapOp::kHeader || op == McapOp::kFooter) {
      return Error(BagErrorCode::kMalformed, pos,
                   "opcode " + std::to_string(opcode) + " cannot appear in the data section");
    }
    if (op == McapOp::kMessage) {
      if (len < detail::kMessageHeaderBytes) {
        return Error(BagErrorCode::kMalformed, pos, "Message record shorter than its header");
      }
      if (!file_.Peek(content, detail::kMessageHeaderBytes, b, io)) return IoError(io);
      Cursor m(b, content);
      detail::McapMessageHeader h;
      detail::ParseMessageHeader(m, h);
      const std::uint64_t bytes = detail::kRecordPrefix + len;
      if (bytes > options_.max_chunk_bytes) {
        return Error(BagErrorCode::kOverLimit, pos,
                     "Message record of " + std::to_string(len) + " bytes over the reader's limit");
      }
      if (run && run->length + bytes > options_.max_chunk_bytes) close_run();
      if (!run) run = Block{pos, 0, std::numeric_limits<std::uint64_t>::max(), 0, false};
      run->length += bytes;
      run->start_time = std::min(run->start_time, h.log_time);
      run->end_time = std::max(run->end_time, h.log_time);
    } else {
      close_run();
      if (op == McapOp::kSchema || op == McapOp::kChannel) {
        if (len > options_.max_chunk_bytes) {
          return Error(BagErrorCode::kOverLimit, pos,
                       "record of " + std::to_string(len) + " bytes over the reader's limit");
        }
        std::vector<std::uint8_t> rec;
        if (!file_.Read(content, len, rec, io)) return IoError(io);
        Cursor r(rec, content);
        if (auto e = Register(op, r, pos, false)) return e;
        if (r.failed()) return Error(BagErrorCode::kMalformed, r.error_offset(), r.error());
      } else if (op == McapOp::kChunk) {
        if (auto e = ScanChunk(pos, len)) return e;
      } else if (op == McapOp::kAttachment) {
        if (auto e = ScanAttachment(pos, len)) return e;
      } else if (op == McapOp::kDataEnd) {
        if (!file_.Peek(content, std::min<std::uint64_t>(len, 4), b, io)) return IoError(io);
        Cursor d(b, content);
        const std::uint32_t crc = d.U32("DataEnd data_section_crc");
        if (d.failed()) return Error(BagErrorCode::kMalformed, d.error_offset(), d.error());
        close_run();
        return CheckDataCrc(pos, crc);  // the records after DataEnd are the summary's
      }
      // Message indexes, metadata and private records: nothing to read.
    }
    pos = next;
  }
  close_run();
  return std::nullopt;
}

std::optional<BagError> McapReader::ScanChunk(std::uint64_t at, std::uint64_t length) {
  std::string io;
  std::span<const std::uint8_t> b;
  const std::uint64_t content = at + detail::kRecordPrefix;
  // The fixed fields and the compression name; a name over 4 KiB is not a compression.
  if (!file_.Peek(content, std::min<std::uint64_t>(length, 4096), b, io)) return IoError(io);
  Cursor c(b, content);
  detail::McapChunkHeader h;
  detail::ParseChunkHeader(c, h);
  if (c.failed() && length > 4096) {
    return Error(BagErrorCode::kMalformed, at, "chunk compression name longer than 4 KiB");
  }
  if (c.failed()) return Error(BagErrorCode::kMalformed, c.error_offset(), c.error());
  // ParseChunkHeader compared the records length with the peeked bytes only.
  if (h.records_size > length - h.records_offset) {
    return Error(BagErrorCode::kMalformed, content + h.records_offset - 8,
                 "chunk records length " + std::to_string(h.records_size) +
                     " past the end of the chunk record");
  }
  const auto limit = options_.max_chunk_bytes;
  if (h.uncompressed_size > limit || h.records_size > limit) {
    return Error(BagErrorCode::kOverLimit, at,
                 "chunk declares " + std::to_string(h.uncompressed_size) + " bytes (" +
                     std::to_string(h.records_size) + " compressed), over the reader's limit of " +
                     std::to_string(limit));
  }
  if (h.compression != "" && h.compression != "zstd" && h.compression != "lz4") {
    return Error(BagErrorCode::kUnsupported, at,
                 "chunk compression \"" + h.compression + "\" (supported: none, zstd, lz4)");
  }
  if (h.compression.empty() && h.records_size != h.uncompressed_size) {
    return Error(BagErrorCode::kMalformed, at,
                 "uncompressed chunk of " + std::to_string(h.records_size) + " bytes declares " +
                     std::to_string(h.uncompressed_size));
  }
  if (h.start_time > h.end_time) {
    return Error(BagErrorCode::kMalformed, at, "chunk message_start_time after its end time");
  }
  blocks_.push_back(Block{at, detail::kRecordPrefix + length, h.start_time, h.end_time, true});
  return std::nullopt;
}

std::optional<BagError> McapReader::ScanAttachment(std::uint64_t at, std::uint64_t length) {
  if (!options_.verify_crc) return std::nullopt;
  std::string io;
  std::span<const std::uint8_t> b;
  const std::uint64_t content = at + detail::kRecordPrefix;
  if (!file_.Peek(content, std::min<std::uint64_t>(length, 4096), b, io)) return IoError(io);
  Cursor c(b, content);
  (void)c.U64("attachment log_time");
  (void)c.U64("attachment create_time");
  (void)c.Str("attachment name");
  (void)c.Str("attachment media_type");
  const std::uint64_t data_size = c.U64("attachment data length");
  if (c.failed()) return Error(BagErrorCode::kMalformed, c.error_offset(), c.error());
  const std::uint64_t crc_at = c.pos() + data_size;  // within the content
  if (data_size > length || crc_at > length - 4) {
    return Error(
        BagErrorCode::kMalformed, c.file_offset() - 8,
        "attachment data length " + std::to_string(data_size) + " past the end of its record");
  }
  if (!file_.Peek(content + crc_at, 4, b, io)) return IoError(io);
  Cursor t(b, content + crc_at);
  const std::uint32_t expected = t.U32("attachment crc");
  if (expected == 0) return std::nullopt;
  std::uint32_t crc = 0;
  for (std::uint64_t off = 0; off < crc_at;) {
    const auto n =
        static_cast<std::size_t>(std::min<std::uint64_t>(crc_at - off, detail::kPeekMax));
    if (!file_.Peek(content + off, n, b, io)) return IoError(io);
    crc = detail::Crc32Update(crc, b);
    off += n;
  }
  if (crc != expected) {
    return Error(BagErrorCode::kCrcMismatch, at,
                 "attachment CRC32 " + std::to_string(crc) + " does not match the stored " +
                     std::to_string(expected));
  }
  return std::nullopt;
}

std::optional<BagError> McapReader::CheckDataCrc(std::uint64_t data_end, std::uint32_t expected) {
  if (!options_.verify_crc || expected == 0) return std::nullopt;
  std::string io;
  std::span<const std::uint8_t> b;
  std::uint32_t crc = 0;
  for (std::uint64_t off = 0; off < data_end;) {
    const auto n =
        static_cast<std::size_t>(std::min<std::uint64_t>(data_end - off, detail::kPeekMax));
    if (!file_.Peek(off, n, b, io)) return IoError(io);
    crc = detail::Crc32Update(crc, b);
    off += n;
  }
  if (crc != expected) {
    return Error(BagErrorCode::kCrcMismatch, data_end,
                 "data section CRC32 " + std::to_string(crc) + " does not match the DataEnd's " +
                     std::to_string(expected));
  }
  return std::nullopt;
}

// The summary's chunk indexes, when present, list exactly the chunks of the data section.
std::optional<BagError> McapReader::CheckIndex() const {
  if (chunk_index_.empty()) return std::nullopt;
  std::vector<const Block*> chunks;
  for (const Block& b : blocks_) {
    if (b.chunk) chunks.push_back(&b);
  }
  if (chunks.size() != chunk_index_.size()) {
    return Error(BagErrorCode::kMalformed, summary_start_,
                 "the summary indexes " + std::to_string(chunk_index_.size()) +
                     " chunks, the data section holds " + std::to_string(chunks.size()));
  }
  auto index = chunk_index_;
  std::sort(index.begin(), index.end(),
            [](const auto& a, const auto& b) { return a.chunk_offset < b.chunk_offset; });
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    const Block& b = *chunks[i];
    const auto& x = index[i];
    if (x.chunk_offset != b.offset || x.chunk_length != b.length || x.start_time != b.start_time ||
        x.end_time != b.end_time) {
      return Error(BagErrorCode::kMalformed, b.offset,
                   "the summary's chunk index disagrees with the chunk at this offset (offset, "
                   "length or time range)");
    }
  }
  return std::nullopt;
}

// ---- Reading blocks ----

// Reads a block into memory: a chunk is CRC-checked and decompressed to its declared size; the
// block's messages are then listed and stably sorted by log time.
std::optional<BagError> McapReader::LoadBlock(std::size_t order, OpenBlock& out) {
  const Block& block = blocks_[order];
  out.order = order;
  out.next = 0;
  out.entries.clear();
  std::string io;
  std::vector<std::uint8_t> raw;
  if (!file_.Read(block.offset, block.length, raw, io)) return IoError(io);
  if (!block.chunk) {
    out.bytes = std::move(raw);
    return ParseRecords(0, block.offset, true, block, out);
  }
  Cursor c(std::span<const std::uint8_t>(raw).subspan(detail::kRecordPrefix),
           block.offset + detail::kRecordPrefix);
  detail::McapChunkHeader h;
  detail::ParseChunkHeader(c, h);  // checked by the scan; the file may have changed since
  if (c.failed()) return Error(BagErrorCode::kMalformed, c.error_offset(), c.error());
  if (h.records_size > c.left() || h.uncompressed_size > options_.max_chunk_bytes) {
    return Error(BagErrorCode::kMalformed, block.offset, "chunk changed since the file was opened");
  }
  const auto records = std::span<const std::uint8_t>(raw).subspan(
      detail::kRecordPrefix + h.records_offset, h.records_size);
  const std::uint64_t records_at = block.offset + detail::kRecordPrefix + h.records_offset;
  detail::DecompressResult d;
  if (h.compression == "zstd") {
    d = detail::DecompressZstd(records, h.uncompressed_size, out.bytes);
  } else if (h.compression == "lz4") {
    d = detail::DecompressLz4Frame(records, h.uncompressed_size, out.bytes);
  } else {  // keep the bytes read: the records start after the chunk's header
    out.bytes = std::move(raw);
  }
  const std::size_t body =
      h.compression.empty() ? detail::kRecordPrefix + h.records_offset : std::size_t{0};
  if (!d.ok) {
    return Error(
        BagErrorCode::kDecompression, block.offset,
        "chunk (" + h.compression + ", " + std::to_string(h.records_size) + " bytes) " + d.message);
  }
  if (options_.verify_crc && h.uncompressed_crc != 0) {
    const std::uint32_t crc =
        detail::Crc32Update(0, std::span<const std::uint8_t>(out.bytes).subspan(body));
    if (crc != h.uncompressed_crc) {
      return Error(BagErrorCode::kCrcMismatch, block.offset,
                   "chunk CRC32 " + std::to_string(crc) + " does not match the stored " +
                       std::to_string(h.uncompressed_crc));
    }
  }
  return ParseRecords(body, h.compression.empty() ? records_at : block.offset,
                      h.compression.empty(), block, out);
}

// The records of a block: out.bytes from `body` on. `exact_offsets`: `base` is the file offset
// of the first record (else the bytes are decompressed, and errors name the chunk's offset and
// the position inside).
std::optional<BagError> McapReader::ParseRecords(std::size_t body, std::uint64_t base,
                                                 bool exact_offsets, const Block& block,
                                                 OpenBlock& out) {
  const auto records = std::span<const std::uint8_t>(out.bytes).subspan(body);
  const auto where = [&](std::uint64_t pos, const std::string& what) {
    return exact_offsets ? Error(BagErrorCode::kMalformed, base + pos, what)
                         : Error(BagErrorCode::kMalformed, base,
                                 "in the chunk, at byte " + std::to_string(pos) +
                                     " of its decompressed records: " + what);
  };
  Cursor c(records, 0);
  while (!c.failed() && c.left() > 0) {
    const std::uint64_t at = c.pos();
    const auto op = static_cast<McapOp>(c.U8("opcode"));
    const auto content = c.Bytes(c.U64("record length"), "record");
    if (c.failed()) break;
    Cursor r(content, at + detail::kRecordPrefix);
    if (op == McapOp::kMessage) {
      detail::McapMessageHeader h;
      detail::ParseMessageHeader(r, h);
      if (r.failed()) return where(r.error_offset(), r.error());
      const auto ch = channels_.find(h.channel_id);
      if (ch == channels_.end()) {
        return where(at, "message on channel " + std::to_string(h.channel_id) +
                             ", which no earlier record defines");
      }
      if (h.log_time < block.start_time || h.log_time > block.end_time) {
        return where(at, "message log_time " + std::to_string(h.log_time) +
                             " outside its chunk's range [" + std::to_string(block.start_time) +
                             ", " + std::to_string(block.end_time) + "]");
      }
      if (h.log_time > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
        return where(at, "message log_time " + std::to_string(h.log_time) + " past 2^63 ns");
      }
      out.entries.push_back(Entry{h.log_time, body + static_cast<std::size_t>(r.file_offset()),
                                  r.left(), ch->second});
    } else if (op == McapOp::kSchema || op == McapOp::kChannel) {
      if (auto e = Register(op, r, exact_offsets ? base + at : base, false)) return e;
      if (r.failed()) return where(r.error_offset(), r.error());
    } else if (static_cast<std::uint8_t>(op) == 0) {
      return where(at, "opcode 0 is not a record");
    }
  }
  if (c.failed()) return where(c.error_offset(), c.error());
  std::stable_sort(out.entries.begin(), out.entries.end(),
                   [](const Entry& a, const Entry& b) { return a.log_time < b.log_time; });
  return std::nullopt;
}

// Opens every block that may hold a message not later than the smallest pending one.
std::optional<BagError> McapReader::OpenDueBlocks() {
  while (next_start_ < by_start_.size()) {
    const Block& candidate = blocks_[by_start_[next_start_]];
    bool due = open_.empty();
    for (const OpenBlock& b : open_) {
      if (candidate.start_time <= b.entries[b.next].log_time) due = true;
    }
    if (!due) break;
    OpenBlock block;
    if (auto e = LoadBlock(by_start_[next_start_], block)) return e;
    ++next_start_;
    if (block.entries.empty()) continue;
    open_bytes_ += block.bytes.size();
    if (open_bytes_ > 4 * options_.max_chunk_bytes) {
      return Error(BagErrorCode::kOverLimit, candidate.offset,
                   std::to_string(open_.size() + 1) + " chunks overlap in log time, " +
                       std::to_string(open_bytes_) + " bytes together, over the reader's limit");
    }
    open_.push_back(std::move(block));
  }
  return std::nullopt;
}

Expected<bool, BagError> McapReader::Next(BagRecord& out) {
  if (failed_) return Unexpected{*failed_};
  // Release the block whose last message was yielded by the previous call.
  for (std::size_t i = 0; i < open_.size(); ++i) {
    if (open_[i].next == open_[i].entries.size()) {
      open_bytes_ -= open_[i].bytes.size();
      open_.erase(open_.begin() + static_cast<std::ptrdiff_t>(i));
      break;
    }
  }
  if (auto e = OpenDueBlocks()) {
    failed_ = std::move(e);
    open_.clear();
    return Unexpected{*failed_};
  }
  if (open_.empty()) return false;
  OpenBlock* best = &open_[0];
  for (OpenBlock& b : open_) {  // smallest (log time, file order); few blocks are open
    const auto& e = b.entries[b.next];
    const auto& m = best->entries[best->next];
    if (e.log_time < m.log_time || (e.log_time == m.log_time && b.order < best->order)) best = &b;
  }
  const Entry& e = best->entries[best->next++];
  const BagTopic& topic = topics_[e.topic];
  out.topic = topic.name;
  out.type_name = topic.type_name;
  out.encoding = topic.encoding;
  out.kind = topic.kind;
  out.log_time_ns = static_cast<std::int64_t>(e.log_time);
  out.data = std::span<const std::uint8_t>(best->bytes).subspan(e.data_offset, e.data_size);
  return true;
}

}  // namespace

Expected<BagReaderPtr, BagError> OpenMcapBag(const std::string& path,
                                             const BagReaderOptions& options) {
  auto reader = std::make_unique<McapReader>(path, options);
  if (auto e = reader->Open()) return Unexpected{std::move(*e)};
  return BagReaderPtr(std::move(reader));
}

}  // namespace semgraph::ros
