// ROS 1 bag v2.0 record headers: field parsing with every length checked against the bytes.
#include "ros1_bag_format.h"

namespace semgraph::ros::ros1 {
namespace {

// Calls visit(name, value, offset_of_field) for each `u32 len, name=value` field of `bytes`.
template <class Visit>
std::optional<FormatError> ForEachField(std::span<const std::uint8_t> bytes, Visit&& visit) {
  std::size_t pos = 0;
  while (pos < bytes.size()) {
    if (bytes.size() - pos < 4) {
      return FormatError{pos, "header field length cut off (" + std::to_string(bytes.size() - pos) +
                                  " bytes left)"};
    }
    const std::uint32_t len = LoadU32(bytes.data() + pos);
    if (len > bytes.size() - pos - 4) {
      return FormatError{pos, "header field length " + std::to_string(len) +
                                  " past the end of the header (" +
                                  std::to_string(bytes.size() - pos - 4) + " bytes left)"};
    }
    const std::string_view field(reinterpret_cast<const char*>(bytes.data() + pos + 4), len);
    const std::size_t eq = field.find('=');
    if (eq == std::string_view::npos) {
      return FormatError{pos, "header field without '='"};
    }
    if (auto error = visit(field.substr(0, eq), field.substr(eq + 1), pos)) return error;
    pos += 4 + std::size_t{len};
  }
  return std::nullopt;
}

std::optional<FormatError> WrongSize(std::string_view name, std::size_t want, std::size_t got,
                                     std::size_t at) {
  return FormatError{at, "header field '" + std::string(name) + "' has " + std::to_string(got) +
                             " bytes, not " + std::to_string(want)};
}

}  // namespace

std::optional<FormatError> ParseRecordHeader(std::span<const std::uint8_t> bytes,
                                             RecordHeader& out) {
  out = RecordHeader{};
  bool has_op = false;
  auto visit = [&](std::string_view name, std::string_view value,
                   std::size_t at) -> std::optional<FormatError> {
    const auto* v = reinterpret_cast<const std::uint8_t*>(value.data());
    auto u32 = [&](std::optional<std::uint32_t>& field) -> std::optional<FormatError> {
      if (value.size() != 4) return WrongSize(name, 4, value.size(), at);
      field = LoadU32(v);
      return std::nullopt;
    };
    auto u64 = [&](std::optional<std::uint64_t>& field) -> std::optional<FormatError> {
      if (value.size() != 8) return WrongSize(name, 8, value.size(), at);
      field = LoadU64(v);
      return std::nullopt;
    };
    auto time = [&](std::optional<std::uint64_t>& field) -> std::optional<FormatError> {
      if (value.size() != 8) return WrongSize(name, 8, value.size(), at);
      field = TimeToNs(LoadU32(v), LoadU32(v + 4));
      return std::nullopt;
    };
    if (name == "op") {
      if (value.size() != 1) return WrongSize(name, 1, value.size(), at);
      out.op = v[0];
      has_op = true;
      return std::nullopt;
    }
    if (name == "conn") return u32(out.conn);
    if (name == "time") return time(out.time_ns);
    if (name == "index_pos") return u64(out.index_pos);
    if (name == "conn_count") return u32(out.conn_count);
    if (name == "chunk_count") return u32(out.chunk_count);
    if (name == "chunk_pos") return u64(out.chunk_pos);
    if (name == "start_time") return time(out.start_time_ns);
    if (name == "end_time") return time(out.end_time_ns);
    if (name == "count") return u32(out.count);
    if (name == "ver") return u32(out.ver);
    if (name == "size") return u32(out.size);
    if (name == "compression") out.compression = value;
    if (name == "topic") out.topic = value;
    return std::nullopt;  // other fields (md5sum, ...) are not needed here
  };
  if (auto error = ForEachField(bytes, visit)) return error;
  if (!has_op) return FormatError{0, "record header without an 'op' field"};
  return std::nullopt;
}

std::optional<FormatError> ParseConnectionData(std::span<const std::uint8_t> bytes,
                                               ConnectionFields& out) {
  out = ConnectionFields{};
  bool has_type = false;
  auto visit = [&](std::string_view name, std::string_view value,
                   std::size_t) -> std::optional<FormatError> {
    if (name == "topic") out.topic = value;
    if (name == "type") {
      out.type = value;
      has_type = true;
    }
    return std::nullopt;
  };
  if (auto error = ForEachField(bytes, visit)) return error;
  if (!has_type) return FormatError{0, "connection header without a 'type' field"};
  return std::nullopt;
}

}  // namespace semgraph::ros::ros1
