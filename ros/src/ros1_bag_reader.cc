// The ROS 1 bag v2.0 reader (OpenRos1Bag), written from the format (docs/ros.md, "Bag formats"):
// the bag header, then chunks (each followed by its index data records), then the index section
// at index_pos (connection and chunk info records).
//
// Log-time order with bounded memory: the chunks are taken in order of their start time; a chunk
// is decompressed when its start time is not after the earliest pending message of the chunks
// already held, its messages sorted by (time, position), and the held chunks merged. Chunks that
// do not overlap in time (rosbag's normal output) are thus held one at a time; overlapping ones
// together, up to kOverlapFactor x max_chunk_bytes. A bag without an index (index_pos 0, as left
// by an interrupted `rosbag record`) is scanned once at Open to build the same chunk list.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <map>
#include <optional>
#include <unordered_map>
#include <utility>

#include "ros1_bag_format.h"
#include "ros1_chunk_decompression.h"
#include "semgraph/ros/bag_reader.h"

namespace semgraph::ros {
namespace {

using ros1::RecordHeader;

// Record headers are small (a chunk's header names its compression and size); a longer one is
// refused before it is read.
constexpr std::uint32_t kMaxRecordHeader = 1u << 20;
// Chunks overlapping in log time are held together, up to this many max_chunk_bytes.
constexpr std::uint64_t kOverlapFactor = 4;

// A file read with pread, every short read reported as the truncation of what was being read.
class File {
 public:
  ~File() {
    if (fd_ >= 0) ::close(fd_);
  }
  std::optional<BagError> Open(const std::string& path) {
    path_ = path;
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) return Error(BagErrorCode::kIo, 0, "cannot open: " + ErrnoText());
    const off_t end = ::lseek(fd_, 0, SEEK_END);
    if (end < 0) return Error(BagErrorCode::kIo, 0, "cannot seek: " + ErrnoText());
    size_ = static_cast<std::uint64_t>(end);
    return std::nullopt;
  }
  [[nodiscard]] std::uint64_t size() const noexcept { return size_; }
  [[nodiscard]] BagError Error(BagErrorCode code, std::uint64_t offset, std::string text) const {
    return BagError{code, path_, offset, std::move(text)};
  }
  // Reads n bytes at offset; `what` names the thing read for the truncation message.
  std::optional<BagError> ReadAt(std::uint64_t offset, std::size_t n, std::uint8_t* dst,
                                 const char* what) const {
    if (offset > size_ || n > size_ - offset) {
      return Error(BagErrorCode::kTruncated, offset,
                   std::string("the file ends inside ") + what + " (" + std::to_string(n) +
                       " bytes needed, " + std::to_string(offset > size_ ? 0 : size_ - offset) +
                       " left)");
    }
    std::size_t done = 0;
    while (done < n) {
      const ssize_t got = ::pread(fd_, dst + done, n - done, static_cast<off_t>(offset + done));
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) {
        return Error(BagErrorCode::kIo, offset + done,
                     std::string("cannot read ") + what + ": " + ErrnoText());
      }
      done += static_cast<std::size_t>(got);
    }
    return std::nullopt;
  }

 private:
  static std::string ErrnoText() { return errno == 0 ? "end of file" : std::strerror(errno); }
  int fd_ = -1;
  std::uint64_t size_ = 0;
  std::string path_;
};

// One top-level record: its header (views into header_bytes) and where its data is.
struct TopRecord {
  std::uint64_t pos = 0;
  RecordHeader header;
  std::uint64_t data_pos = 0;
  std::uint32_t data_len = 0;
  [[nodiscard]] std::uint64_t end() const noexcept { return data_pos + data_len; }
};

struct ChunkInfo {
  std::uint64_t pos = 0;
  std::uint64_t start_ns = 0, end_ns = 0;
  std::uint64_t message_count = 0;
  bool from_index = false;  // times and counts declared by a chunk info record
};

struct PendingMessage {
  std::uint64_t time_ns = 0;
  std::uint32_t order = 0;  // position in the chunk (ties keep file order)
  std::uint32_t topic = 0;  // index into topics_
  std::uint32_t data_pos = 0, data_len = 0;
};

struct HeldChunk {
  std::uint64_t pos = 0;
  std::vector<std::uint8_t> bytes;
  std::vector<PendingMessage> messages;
  std::size_t head = 0;
};

class Ros1BagReader final : public BagReader {
 public:
  explicit Ros1BagReader(const BagReaderOptions& options) : options_(options) {}

  std::optional<BagError> Open(const std::string& path);

  [[nodiscard]] BagFormat format() const noexcept override { return BagFormat::kRos1; }
  [[nodiscard]] const std::string& path() const noexcept override { return path_; }
  [[nodiscard]] const std::vector<BagTopic>& topics() const noexcept override { return topics_; }
  [[nodiscard]] Expected<bool, BagError> Next(BagRecord& out) override;

 private:
  std::optional<BagError> ReadTopRecord(std::uint64_t pos, TopRecord& out);
  std::optional<BagError> ReadData(const TopRecord& record, std::vector<std::uint8_t>& out,
                                   const char* what);
  std::optional<BagError> ReadIndex(std::uint64_t index_pos, const RecordHeader& bag_header);
  std::optional<BagError> ScanChunks(std::uint64_t first_record);
  std::optional<BagError> AddConnection(std::uint32_t conn, std::span<const std::uint8_t> data,
                                        std::uint64_t at);
  std::optional<BagError> AddChunkInfo(const TopRecord& record);
  std::optional<BagError> LoadChunk(const ChunkInfo& info, HeldChunk& out);
  std::optional<BagError> ParseChunk(const ChunkInfo& info, const TopRecord& record,
                                     HeldChunk& out);
  Expected<bool, BagError> Fail(BagError error) {
    failed_ = std::move(error);
    return Unexpected{*failed_};
  }

  BagReaderOptions options_;
  std::string path_;
  File file_;
  std::vector<BagTopic> topics_;
  std::map<std::pair<std::string, std::string>, std::uint32_t> topic_index_;
  std::unordered_map<std::uint32_t, std::uint32_t> conn_topic_;  // conn id -> topics_ index
  std::vector<ChunkInfo> chunks_;                                // by (start time, position)
  std::size_t next_chunk_ = 0;
  std::vector<HeldChunk> held_;
  HeldChunk spare_;  // a drained chunk's buffers, reused by the next LoadChunk
  std::uint64_t held_bytes_ = 0;
  std::vector<std::uint8_t> header_bytes_, record_bytes_;
  std::optional<BagError> failed_;
};

std::optional<BagError> Ros1BagReader::ReadTopRecord(std::uint64_t pos, TopRecord& out) {
  std::uint8_t len[4];
  if (auto e = file_.ReadAt(pos, 4, len, "a record's header length")) return e;
  const std::uint32_t header_len = ros1::LoadU32(len);
  const std::uint64_t left = file_.size() - pos - 4;
  if (header_len > left) {
    return file_.Error(BagErrorCode::kTruncated, pos,
                       "record header length " + std::to_string(header_len) +
                           " past the end of the file (" + std::to_string(left) + " bytes left)");
  }
  if (header_len > kMaxRecordHeader) {
    return file_.Error(BagErrorCode::kOverLimit, pos,
                       "record header length " + std::to_string(header_len) +
                           " over the limit of " + std::to_string(kMaxRecordHeader) + " bytes");
  }
  header_bytes_.resize(header_len);
  if (auto e = file_.ReadAt(pos + 4, header_len, header_bytes_.data(), "a record header")) return e;
  if (auto e = ros1::ParseRecordHeader(header_bytes_, out.header)) {
    return file_.Error(BagErrorCode::kMalformed, pos + 4 + e->offset, e->message);
  }
  const std::uint64_t data_len_pos = pos + 4 + header_len;
  if (auto e = file_.ReadAt(data_len_pos, 4, len, "a record's data length")) return e;
  out.pos = pos;
  out.data_pos = data_len_pos + 4;
  out.data_len = ros1::LoadU32(len);
  if (out.data_len > file_.size() - out.data_pos) {
    return file_.Error(BagErrorCode::kTruncated, data_len_pos,
                       "record data length " + std::to_string(out.data_len) +
                           " past the end of the file (" +
                           std::to_string(file_.size() - out.data_pos) + " bytes left)");
  }
  return std::nullopt;
}

std::optional<BagError> Ros1BagReader::ReadData(const TopRecord& record,
                                                std::vector<std::uint8_t>& out, const char* what) {
  if (record.data_len > options_.max_chunk_bytes) {
    return file_.Error(BagErrorCode::kOverLimit, record.pos,
                       std::string(what) + " data length " + std::to_string(record.data_len) +
                           " over the limit of " + std::to_string(options_.max_chunk_bytes) +
                           " bytes");
  }
  out.resize(record.data_len);
  return file_.ReadAt(record.data_pos, record.data_len, out.data(), what);
}

std::optional<BagError> Ros1BagReader::AddConnection(std::uint32_t conn,
                                                     std::span<const std::uint8_t> data,
                                                     std::uint64_t at) {
  ros1::ConnectionFields fields;
  if (auto e = ros1::ParseConnectionData(data, fields)) {
    return file_.Error(BagErrorCode::kMalformed, at,
                       "connection " + std::to_string(conn) + ": " + e->message);
  }
  if (conn_topic_.contains(conn)) return std::nullopt;  // rosbag repeats it in chunk and index
  auto key = std::make_pair(std::string(fields.topic), std::string(fields.type));
  auto [it, added] = topic_index_.try_emplace(key, static_cast<std::uint32_t>(topics_.size()));
  if (added) {
    BagTopic topic;
    topic.name = key.first;
    topic.type_name = key.second;
    topic.encoding = MessageEncoding::kRos1;
    topic.kind = MessageKindOf(topic.type_name);
    topics_.push_back(std::move(topic));
  }
  conn_topic_.emplace(conn, it->second);
  return std::nullopt;
}

std::optional<BagError> Ros1BagReader::AddChunkInfo(const TopRecord& record) {
  const RecordHeader& h = record.header;
  if (!h.ver || !h.chunk_pos || !h.start_time_ns || !h.end_time_ns || !h.count) {
    return file_.Error(BagErrorCode::kMalformed, record.pos,
                       "chunk info record without ver, chunk_pos, start_time, end_time or count");
  }
  if (*h.ver != 1) {
    return file_.Error(BagErrorCode::kUnsupported, record.pos,
                       "chunk info version " + std::to_string(*h.ver) + " (only 1 is known)");
  }
  if (std::uint64_t{*h.count} * 8 != record.data_len) {
    return file_.Error(BagErrorCode::kMalformed, record.pos,
                       "chunk info lists " + std::to_string(*h.count) + " connections in " +
                           std::to_string(record.data_len) + " bytes (8 each)");
  }
  if (*h.start_time_ns > *h.end_time_ns) {
    return file_.Error(BagErrorCode::kMalformed, record.pos,
                       "chunk info start_time after its end_time");
  }
  if (auto e = ReadData(record, record_bytes_, "a chunk info")) return e;
  ChunkInfo info{*h.chunk_pos, *h.start_time_ns, *h.end_time_ns, 0, true};
  for (std::uint32_t i = 0; i < *h.count; ++i) {
    const std::uint32_t conn = ros1::LoadU32(record_bytes_.data() + 8 * i);
    const auto it = conn_topic_.find(conn);
    if (it == conn_topic_.end()) {
      return file_.Error(BagErrorCode::kMalformed, record.data_pos + 8 * i,
                         "chunk info refers to connection " + std::to_string(conn) +
                             ", which no connection record defines");
    }
    const std::uint32_t n = ros1::LoadU32(record_bytes_.data() + 8 * i + 4);
    info.message_count += n;
    BagTopic& topic = topics_[it->second];
    topic.message_count = std::max<std::int64_t>(topic.message_count, 0) + n;
  }
  chunks_.push_back(info);
  return std::nullopt;
}

std::optional<BagError> Ros1BagReader::ReadIndex(std::uint64_t index_pos,
                                                 const RecordHeader& bag_header) {
  // Connections first (chunk infos refer to them), then the chunk infos: two walks.
  for (int walk = 0; walk < 2; ++walk) {
    for (std::uint64_t pos = index_pos; pos < file_.size();) {
      TopRecord record;
      if (auto e = ReadTopRecord(pos, record)) return e;
      const std::uint8_t op = record.header.op;
      if (walk == 0 && op == ros1::kOpConnection) {
        if (!record.header.conn) {
          return file_.Error(BagErrorCode::kMalformed, pos, "connection record without conn");
        }
        if (auto e = ReadData(record, record_bytes_, "a connection record")) return e;
        if (auto e = AddConnection(*record.header.conn, record_bytes_, record.data_pos)) return e;
      } else if (walk == 1 && op == ros1::kOpChunkInfo) {
        if (auto e = AddChunkInfo(record)) return e;
      } else if (op != ros1::kOpConnection && op != ros1::kOpChunkInfo) {
        return file_.Error(BagErrorCode::kMalformed, pos,
                           "record op " + std::to_string(op) + " in the index section");
      }
      pos = record.end();
    }
  }
  const std::uint64_t connections = conn_topic_.size();
  if (connections != bag_header.conn_count.value_or(0) ||
      chunks_.size() != bag_header.chunk_count.value_or(0)) {
    return file_.Error(BagErrorCode::kMalformed, index_pos,
                       "the index holds " + std::to_string(connections) + " connections and " +
                           std::to_string(chunks_.size()) + " chunk infos; the bag header says " +
                           std::to_string(bag_header.conn_count.value_or(0)) + " and " +
                           std::to_string(bag_header.chunk_count.value_or(0)));
  }
  for (const ChunkInfo& info : chunks_) {
    if (info.pos >= index_pos) {
      return file_.Error(BagErrorCode::kMalformed, index_pos,
                         "a chunk info points at byte " + std::to_string(info.pos) +
                             ", not before the index section");
    }
  }
  return std::nullopt;
}

// No index: one walk over the records, each chunk decompressed once for its time range.
std::optional<BagError> Ros1BagReader::ScanChunks(std::uint64_t first_record) {
  for (std::uint64_t pos = first_record; pos < file_.size();) {
    TopRecord record;
    if (auto e = ReadTopRecord(pos, record)) return e;
    if (record.header.op == ros1::kOpChunk) {
      ChunkInfo info{pos, 0, 0, 0, false};
      HeldChunk chunk;
      if (auto e = ParseChunk(info, record, chunk)) return e;
      if (!chunk.messages.empty()) {
        info.start_ns = chunk.messages.front().time_ns;
        info.end_ns = chunk.messages.back().time_ns;
        info.message_count = chunk.messages.size();
        for (const PendingMessage& m : chunk.messages) {
          BagTopic& topic = topics_[m.topic];
          topic.message_count = std::max<std::int64_t>(topic.message_count, 0) + 1;
        }
        chunks_.push_back(info);
      }
    } else if (record.header.op == ros1::kOpConnection) {
      if (!record.header.conn) {
        return file_.Error(BagErrorCode::kMalformed, pos, "connection record without conn");
      }
      if (auto e = ReadData(record, record_bytes_, "a connection record")) return e;
      if (auto e = AddConnection(*record.header.conn, record_bytes_, record.data_pos)) return e;
    } else if (record.header.op != ros1::kOpIndexData && record.header.op != ros1::kOpChunkInfo) {
      return file_.Error(BagErrorCode::kMalformed, pos,
                         "record op " + std::to_string(record.header.op) +
                             " where a chunk, index data or connection record belongs");
    }
    pos = record.end();
  }
  return std::nullopt;
}

std::optional<BagError> Ros1BagReader::Open(const std::string& path) {
  path_ = path;
  if (auto e = file_.Open(path)) return e;
  std::uint8_t magic[ros1::kMagic.size()];
  const std::size_t have = std::min<std::uint64_t>(file_.size(), sizeof magic);
  if (auto e = file_.ReadAt(0, have, magic, "the magic")) return e;
  const std::string_view got(reinterpret_cast<const char*>(magic), have);
  if (got != ros1::kMagic) {
    if (!got.empty() && ros1::kMagic.starts_with(got)) {
      return file_.Error(BagErrorCode::kTruncated, 0, "the file ends inside the magic");
    }
    const bool other_version = got.starts_with(ros1::kMagicPrefix);
    return file_.Error(other_version ? BagErrorCode::kUnsupported : BagErrorCode::kUnknownFormat, 0,
                       other_version ? "a ROS bag of a version other than 2.0"
                                     : "not a ROS 1 bag: no '#ROSBAG V2.0' magic");
  }
  TopRecord bag_header;
  if (auto e = ReadTopRecord(ros1::kMagic.size(), bag_header)) return e;
  const RecordHeader& h = bag_header.header;
  if (h.op != ros1::kOpBagHeader || !h.index_pos || !h.conn_count || !h.chunk_count) {
    return file_.Error(BagErrorCode::kMalformed, ros1::kMagic.size(),
                       "the first record is not a bag header with index_pos, conn_count and "
                       "chunk_count");
  }
  if (*h.index_pos > file_.size() || (*h.index_pos != 0 && *h.index_pos < bag_header.end())) {
    return file_.Error(
        *h.index_pos > file_.size() ? BagErrorCode::kTruncated : BagErrorCode::kMalformed,
        bag_header.pos,
        "index_pos " + std::to_string(*h.index_pos) + " outside the file's records (size " +
            std::to_string(file_.size()) + ")");
  }
  auto error = *h.index_pos == 0 ? ScanChunks(bag_header.end()) : ReadIndex(*h.index_pos, h);
  if (error) return error;
  std::stable_sort(chunks_.begin(), chunks_.end(), [](const ChunkInfo& a, const ChunkInfo& b) {
    return a.start_ns != b.start_ns ? a.start_ns < b.start_ns : a.pos < b.pos;
  });
  return std::nullopt;
}

std::optional<BagError> Ros1BagReader::LoadChunk(const ChunkInfo& info, HeldChunk& out) {
  TopRecord record;
  if (auto e = ReadTopRecord(info.pos, record)) return e;
  if (auto e = ParseChunk(info, record, out)) return e;
  if (out.messages.size() != info.message_count) {
    return file_.Error(BagErrorCode::kMalformed, info.pos,
                       "the chunk holds " + std::to_string(out.messages.size()) +
                           " messages; its chunk info says " + std::to_string(info.message_count));
  }
  return std::nullopt;
}

std::optional<BagError> Ros1BagReader::ParseChunk(const ChunkInfo& info, const TopRecord& record,
                                                  HeldChunk& out) {
  const RecordHeader& h = record.header;
  if (h.op != ros1::kOpChunk || !h.size || !h.compression) {
    return file_.Error(BagErrorCode::kMalformed, record.pos,
                       "no chunk record (with compression and size) at this position");
  }
  const auto compression = ros1::ChunkCompressionOf(*h.compression);
  if (!compression) {
    return file_.Error(BagErrorCode::kUnsupported, record.pos,
                       "chunk compression '" + std::string(*h.compression) + "'");
  }
  if (*h.size > options_.max_chunk_bytes ||
      held_bytes_ + *h.size > kOverlapFactor * options_.max_chunk_bytes) {
    return file_.Error(BagErrorCode::kOverLimit, record.pos,
                       "chunk declares " + std::to_string(*h.size) +
                           " uncompressed bytes, over the limit of " +
                           std::to_string(options_.max_chunk_bytes) + " bytes" +
                           (held_bytes_ > 0 ? " (with the chunks overlapping it in time)" : ""));
  }
  if (*compression == ros1::ChunkCompression::kNone && record.data_len == *h.size) {
    out.bytes.resize(*h.size);  // read in place: no copy
    if (auto e = file_.ReadAt(record.data_pos, *h.size, out.bytes.data(), "a chunk")) return e;
  } else {
    if (auto e = ReadData(record, record_bytes_, "a chunk")) return e;
    if (auto e = ros1::DecompressChunk(*compression, record_bytes_, *h.size, out.bytes)) {
      return file_.Error(e->unsupported ? BagErrorCode::kUnsupported : BagErrorCode::kDecompression,
                         record.pos, "chunk: " + e->message);
    }
  }
  out.pos = info.pos;
  out.messages.clear();
  out.head = 0;
  // In an uncompressed chunk an inner offset is a file offset; otherwise name the chunk.
  const bool plain = *compression == ros1::ChunkCompression::kNone;
  auto error = [&](std::uint64_t inner, const std::string& text) {
    return file_.Error(
        BagErrorCode::kMalformed, plain ? record.data_pos + inner : record.pos,
        (plain ? std::string("in a chunk: ")
               : "at byte " + std::to_string(inner) + " of the chunk's decompressed data: ") +
            text);
  };
  const std::span<const std::uint8_t> bytes(out.bytes);
  RecordHeader inner;
  for (std::size_t pos = 0; pos < bytes.size();) {
    if (bytes.size() - pos < 4) return error(pos, "record header length cut off");
    const std::uint32_t header_len = ros1::LoadU32(&bytes[pos]);
    if (header_len > bytes.size() - pos - 4) {
      return error(
          pos, "record header length " + std::to_string(header_len) + " past the end of the chunk");
    }
    if (auto e = ros1::ParseRecordHeader(bytes.subspan(pos + 4, header_len), inner)) {
      return error(pos + 4 + e->offset, e->message);
    }
    const std::size_t data_len_pos = pos + 4 + header_len;
    if (bytes.size() - data_len_pos < 4) return error(data_len_pos, "data length cut off");
    const std::uint32_t data_len = ros1::LoadU32(&bytes[data_len_pos]);
    const std::size_t data_pos = data_len_pos + 4;
    if (data_len > bytes.size() - data_pos) {
      return error(data_len_pos,
                   "record data length " + std::to_string(data_len) + " past the end of the chunk");
    }
    if (inner.op == ros1::kOpConnection) {
      if (!inner.conn) return error(pos, "connection record without conn");
      if (auto e = AddConnection(*inner.conn, bytes.subspan(data_pos, data_len), record.pos)) {
        return e;
      }
    } else if (inner.op == ros1::kOpMessageData) {
      if (!inner.conn || !inner.time_ns) return error(pos, "message data without conn or time");
      const auto it = conn_topic_.find(*inner.conn);
      if (it == conn_topic_.end()) {
        return error(pos, "message data refers to connection " + std::to_string(*inner.conn) +
                              ", which no connection record defines");
      }
      if (info.from_index && (*inner.time_ns < info.start_ns || *inner.time_ns > info.end_ns)) {
        return error(pos, "message time outside its chunk info's [start_time, end_time]");
      }
      out.messages.push_back({*inner.time_ns, static_cast<std::uint32_t>(out.messages.size()),
                              it->second, static_cast<std::uint32_t>(data_pos), data_len});
    } else {
      return error(pos, "record op " + std::to_string(inner.op) + " inside a chunk");
    }
    pos = data_pos + data_len;
  }
  std::stable_sort(
      out.messages.begin(), out.messages.end(),
      [](const PendingMessage& a, const PendingMessage& b) { return a.time_ns < b.time_ns; });
  return std::nullopt;
}

Expected<bool, BagError> Ros1BagReader::Next(BagRecord& out) {
  if (failed_) return Unexpected{*failed_};
  // Chunks drained by the previous call are released now (its record pointed into them).
  // Their buffers are kept for the next chunk (no new allocation, no zero-filling).
  for (std::size_t i = held_.size(); i-- > 0;) {
    if (held_[i].head == held_[i].messages.size()) {
      held_bytes_ -= held_[i].bytes.size();
      spare_ = std::move(held_[i]);
      held_.erase(held_.begin() + static_cast<std::ptrdiff_t>(i));
    }
  }
  for (;;) {
    std::size_t best = held_.size();
    for (std::size_t i = 0; i < held_.size(); ++i) {
      const PendingMessage& m = held_[i].messages[held_[i].head];
      if (best == held_.size()) {
        best = i;
        continue;
      }
      const PendingMessage& b = held_[best].messages[held_[best].head];
      if (m.time_ns < b.time_ns || (m.time_ns == b.time_ns && held_[i].pos < held_[best].pos)) {
        best = i;
      }
    }
    const bool take_chunk =
        next_chunk_ < chunks_.size() &&
        (best == held_.size() ||
         chunks_[next_chunk_].start_ns <= held_[best].messages[held_[best].head].time_ns);
    if (!take_chunk) {
      if (best == held_.size()) return false;
      HeldChunk& chunk = held_[best];
      const PendingMessage& m = chunk.messages[chunk.head++];
      const BagTopic& topic = topics_[m.topic];
      out.topic = topic.name;
      out.type_name = topic.type_name;
      out.encoding = topic.encoding;
      out.kind = topic.kind;
      out.log_time_ns = static_cast<std::int64_t>(m.time_ns);
      out.data = std::span<const std::uint8_t>(chunk.bytes).subspan(m.data_pos, m.data_len);
      return true;
    }
    HeldChunk chunk = std::move(spare_);
    if (auto e = LoadChunk(chunks_[next_chunk_], chunk)) return Fail(std::move(*e));
    ++next_chunk_;
    if (!chunk.messages.empty()) {
      held_bytes_ += chunk.bytes.size();
      held_.push_back(std::move(chunk));
    }
  }
}

}  // namespace

Expected<BagReaderPtr, BagError> OpenRos1Bag(const std::string& path,
                                             const BagReaderOptions& options) {
  auto reader = std::make_unique<Ros1BagReader>(options);
  if (auto error = reader->Open(path)) return Unexpected{std::move(*error)};
  return BagReaderPtr(std::move(reader));
}

}  // namespace semgraph::ros
