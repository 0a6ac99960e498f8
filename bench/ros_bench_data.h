// File: bench/ros_bench_data.h
//
// The data of the ROS bag benchmarks (bench/ros_bench.cc, ros_icount.cc, ros_bag_read.cc):
//  - RobotTf: what a robot's robot_state_publisher sends: one /tf_static message (two sensor
//    frames fixed on the last link) and, every `period_ns`, one /tf message with a new sample of
//    each link of the chain f0 <- f1 <- ... <- f`depth` (rotations about moving axes, fixed link
//    offsets; deterministic).
//  - McapWriter: a minimal MCAP writer (the MCAP specification, https://mcap.dev/spec): header,
//    schema, channel, chunks of message records (uncompressed or zstd, with CRC32s), data end,
//    a summary (schemas, channels, statistics, chunk indexes), footer. Bench-only: it writes the
//    1 GiB bag of the reading benchmark and the bags the other benchmarks load. Its files are
//    read by Foxglove's @mcap/core with CRC validation (bench/ros_check_mcap.mjs, by hand).
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "ros_tf2_peer.h"
#include "semgraph/ros/messages.h"

namespace semgraph_bench::rosdata {

struct RobotTf {
  semgraph::ros::TFMessage statics;             ///< /tf_static
  std::vector<semgraph::ros::TFMessage> steps;  ///< /tf, one message per step
};

inline constexpr std::int64_t kDefaultT0 = 1'700'000'000'000'000'000;  ///< ns (2023-11-14)
inline constexpr std::int64_t kDefaultPeriod = 10'000'000;             ///< 100 Hz

/// The /tf_static message (stamped t0_ns) and the /tf message of step k (stamp t0 + k·period).
semgraph::ros::TFMessage RobotStatics(int depth, std::int64_t t0_ns = kDefaultT0);
semgraph::ros::TFMessage RobotStep(int depth, int k, std::int64_t t0_ns = kDefaultT0,
                                   std::int64_t period_ns = kDefaultPeriod);
/// `steps` messages of `depth` transforms each.
RobotTf MakeRobotTf(int depth, int steps, std::int64_t t0_ns = kDefaultT0,
                    std::int64_t period_ns = kDefaultPeriod);

class McapWriter {
 public:
  enum class Compression { kNone, kZstd };
  /// Opens `path` for writing (truncates). Chunks hold about `chunk_bytes` of records. Chunk
  /// CRCs are always written; the data section's CRC only with `data_crc` (rosbag2 writes it as
  /// 0: the mcap C++ writer's enableDataCRC is off by default).
  McapWriter(const std::string& path, Compression compression,
             std::size_t chunk_bytes = std::size_t{1} << 20, bool data_crc = false);
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;
  /// A ros2msg schema and a cdr channel on `topic`; returns the channel id.
  std::uint16_t AddChannel(const std::string& topic, const std::string& type_name);
  /// One message (CDR bytes with their 4-byte header); log times must not decrease.
  void Write(std::uint16_t channel, std::int64_t log_time_ns, const std::vector<std::uint8_t>& cdr);
  /// Flushes the last chunk, writes data end, summary and footer; returns the file size.
  std::uint64_t Close();

 private:
  void FlushChunk();
  void Emit(const std::vector<std::uint8_t>& bytes);

  std::FILE* file_ = nullptr;
  Compression compression_;
  std::size_t chunk_bytes_;
  bool data_crc_on_;
  std::uint64_t offset_ = 0;
  std::uint32_t data_crc_ = 0;
  std::vector<std::uint8_t> chunk_;     ///< message records of the open chunk
  std::vector<std::uint8_t> channels_;  ///< schema and channel records (for the summary)
  std::vector<std::uint8_t> chunk_indexes_;
  std::vector<std::uint64_t> channel_counts_;
  std::uint16_t next_channel_ = 1;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0, messages_ = 0, chunks_ = 0;
  std::uint64_t first_time_ = 0, last_time_ = 0;
  std::uint32_t sequence_ = 0;
};

/// Writes an MCAP bag of RobotStatics and `steps` /tf messages (log time = stamp; the motion of
/// RobotStep repeats every 1,000 steps, the stamps do not); returns the file size. Streams:
/// memory does not grow with `steps`.
std::uint64_t WriteRobotBag(const std::string& path, int depth, std::int64_t steps,
                            McapWriter::Compression compression, bool data_crc = false);

/// A /tf or /tf_static message of a bag, decoded.
struct DecodedTf {
  bool is_static = false;
  std::string topic;
  std::int64_t log_time_ns = 0;
  semgraph::ros::TFMessage tf;
};

/// Every /tf and /tf_static message of a bag, in log-time order, read by semgraph's reader
/// (aborts with a message on a read or decode error).
std::vector<DecodedTf> DecodeBagTf(const std::string& path);
/// Their transforms, one by one, for tf2.
std::vector<rostf2::Transform> Flatten(const std::vector<DecodedTf>& messages);

}  // namespace semgraph_bench::rosdata
