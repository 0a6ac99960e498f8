// File: ros/src/ros1_bag_format.h (internal to semgraph::ros)
//
// The record layer of ROS 1 bags v2.0 (ros_comm's rosbag_storage, "Bag format 2.0"): a record is
// `u32 header_len, header, u32 data_len, data`; a header is a sequence of fields
// `u32 field_len, name '=' value`; integers are little-endian; a time is `u32 sec, u32 nsec`.
// These functions parse one record header from bytes already in memory (a chunk, or a record
// header read from the file) and never read past the span they are given.
//
// Invariants: a parsed RecordHeader's views point into the parsed bytes; an error message says
// what is wrong and the offset of the problem relative to the start of the given span.
// Costs: ParseRecordHeader is O(header bytes), allocation-free on success.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace semgraph::ros::ros1 {

inline constexpr std::string_view kMagic = "#ROSBAG V2.0\n";
inline constexpr std::string_view kMagicPrefix = "#ROSBAG V";

// Record op codes (the `op` header field).
inline constexpr std::uint8_t kOpMessageData = 0x02;
inline constexpr std::uint8_t kOpBagHeader = 0x03;
inline constexpr std::uint8_t kOpIndexData = 0x04;
inline constexpr std::uint8_t kOpChunk = 0x05;
inline constexpr std::uint8_t kOpChunkInfo = 0x06;
inline constexpr std::uint8_t kOpConnection = 0x07;

// The fields a reader needs, from one record header. Absent fields stay nullopt / empty.
struct RecordHeader {
  std::uint8_t op = 0;
  std::optional<std::uint32_t> conn;                        // message data, connection, index data
  std::optional<std::uint64_t> time_ns;                     // message data (`time`)
  std::optional<std::uint64_t> index_pos;                   // bag header
  std::optional<std::uint32_t> conn_count;                  // bag header
  std::optional<std::uint32_t> chunk_count;                 // bag header
  std::optional<std::uint64_t> chunk_pos;                   // chunk info
  std::optional<std::uint64_t> start_time_ns, end_time_ns;  // chunk info
  std::optional<std::uint32_t> count;                       // chunk info, index data
  std::optional<std::uint32_t> ver;                         // chunk info, index data
  std::optional<std::uint32_t> size;                        // chunk: the uncompressed size
  std::optional<std::string_view> compression;              // chunk
  std::optional<std::string_view> topic;                    // connection
};

// A parse failure: what is wrong, and where (relative to the parsed span).
struct FormatError {
  std::uint64_t offset = 0;
  std::string message;
};

// Parses header bytes (without their u32 length prefix). Errors: a field length past the end of
// the header, a field without '=', a known field of the wrong size, no `op` field.
[[nodiscard]] std::optional<FormatError> ParseRecordHeader(std::span<const std::uint8_t> bytes,
                                                           RecordHeader& out);

// The fields of a connection record's data (itself a header: topic, type, md5sum, ...).
struct ConnectionFields {
  std::string_view topic;
  std::string_view type;
};
[[nodiscard]] std::optional<FormatError> ParseConnectionData(std::span<const std::uint8_t> bytes,
                                                             ConnectionFields& out);

// ROS 1 time (u32 sec, u32 nsec) as nanoseconds: at most about 4.3e18, so it fits an int64.
[[nodiscard]] constexpr std::uint64_t TimeToNs(std::uint32_t sec, std::uint32_t nsec) noexcept {
  return std::uint64_t{sec} * 1'000'000'000u + nsec;
}

[[nodiscard]] inline std::uint32_t LoadU32(const std::uint8_t* p) noexcept {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 |
         std::uint32_t{p[3]} << 24;
}
[[nodiscard]] inline std::uint64_t LoadU64(const std::uint8_t* p) noexcept {
  return std::uint64_t{LoadU32(p)} | std::uint64_t{LoadU32(p + 4)} << 32;
}

}  // namespace semgraph::ros::ros1
