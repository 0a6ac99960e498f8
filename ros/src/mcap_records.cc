#include "mcap_records.h"

#include <cstring>

namespace semgraph::ros::detail {

void Cursor::Fail(std::uint64_t file_offset, std::string message) {
  if (failed_) return;
  failed_ = true;
  error_offset_ = file_offset;
  error_ = std::move(message);
}

bool Cursor::Need(std::uint64_t n, const char* what) {
  if (failed_) return false;
  if (n > left()) {
    Fail(file_offset(), std::string(what) + " (" + std::to_string(n) + " bytes) past the end of " +
                            "its record (" + std::to_string(left()) + " bytes left)");
    return false;
  }
  return true;
}

namespace {
template <class T>
T LoadLe(const std::uint8_t* p) {
  T v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) v |= static_cast<T>(T{p[i]} << (8 * i));
  return v;
}
}  // namespace

std::uint8_t Cursor::U8(const char* what) {
  if (!Need(1, what)) return 0;
  return bytes_[pos_++];
}
std::uint16_t Cursor::U16(const char* what) {
  if (!Need(2, what)) return 0;
  const auto v = LoadLe<std::uint16_t>(bytes_.data() + pos_);
  pos_ += 2;
  return v;
}
std::uint32_t Cursor::U32(const char* what) {
  if (!Need(4, what)) return 0;
  const auto v = LoadLe<std::uint32_t>(bytes_.data() + pos_);
  pos_ += 4;
  return v;
}
std::uint64_t Cursor::U64(const char* what) {
  if (!Need(8, what)) return 0;
  const auto v = LoadLe<std::uint64_t>(bytes_.data() + pos_);
  pos_ += 8;
  return v;
}

std::string_view Cursor::Str(const char* what) {
  const std::uint32_t n = U32(what);
  const auto bytes = Bytes(n, what);
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

std::span<const std::uint8_t> Cursor::Bytes(std::uint64_t n, const char* what) {
  if (!Need(n, what)) return {};
  const auto s = bytes_.subspan(pos_, n);
  pos_ += n;
  return s;
}

void Cursor::SkipPrefixed(const char* what) { (void)Bytes(U32(what), what); }

void ParseSchema(Cursor& c, McapSchema& out) {
  const std::uint64_t at = c.file_offset();
  out.id = c.U16("schema id");
  out.name = c.Str("schema name");
  (void)c.Str("schema encoding");
  (void)c.Str("schema data");
  if (!c.failed() && out.id == 0) c.Fail(at, "schema id 0 (reserved for \"no schema\")");
}

void ParseChannel(Cursor& c, McapChannel& out) {
  out.id = c.U16("channel id");
  out.schema_id = c.U16("channel schema id");
  out.topic = c.Str("channel topic");
  out.message_encoding = c.Str("channel message encoding");
  c.SkipPrefixed("channel metadata");
}

void ParseChunkHeader(Cursor& c, McapChunkHeader& out) {
  out.start_time = c.U64("chunk message_start_time");
  out.end_time = c.U64("chunk message_end_time");
  out.uncompressed_size = c.U64("chunk uncompressed_size");
  out.uncompressed_crc = c.U32("chunk uncompressed_crc");
  out.compression = c.Str("chunk compression");
  out.records_size = c.U64("chunk records length");
  out.records_offset = c.pos();
}

void ParseChunkIndex(Cursor& c, McapChunkIndex& out) {
  out.start_time = c.U64("chunk index message_start_time");
  out.end_time = c.U64("chunk index message_end_time");
  out.chunk_offset = c.U64("chunk index chunk_start_offset");
  out.chunk_length = c.U64("chunk index chunk_length");
}

void ParseMessageHeader(Cursor& c, McapMessageHeader& out) {
  out.channel_id = c.U16("message channel id");
  (void)c.U32("message sequence");
  out.log_time = c.U64("message log_time");
  (void)c.U64("message publish_time");
}

void ParseStatistics(Cursor& c, std::vector<std::pair<std::uint16_t, std::uint64_t>>& counts) {
  (void)c.U64("statistics message_count");
  (void)c.U16("statistics schema_count");
  for (const char* f : {"statistics channel_count", "statistics attachment_count",
                        "statistics metadata_count", "statistics chunk_count"}) {
    (void)c.U32(f);
  }
  (void)c.U64("statistics message_start_time");
  (void)c.U64("statistics message_end_time");
  const auto map =
      c.Bytes(c.U32("statistics channel_message_counts"), "statistics channel_message_counts");
  Cursor m(map, c.file_offset() - map.size());
  while (!m.failed() && m.left() > 0) {
    const std::uint16_t id = m.U16("channel_message_counts key");
    const std::uint64_t n = m.U64("channel_message_counts value");
    if (!m.failed()) counts.emplace_back(id, n);
  }
  if (m.failed()) c.Fail(m.error_offset(), m.error());
}

}  // namespace semgraph::ros::detail
