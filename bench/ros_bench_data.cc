// bench/ros_bench_data.h: the benchmarks' robot tf and MCAP writer.
#include "ros_bench_data.h"

#include <zlib.h>
#include <zstd.h>

#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "semgraph/ros/bag_reader.h"

namespace semgraph_bench::rosdata {
namespace {

using semgraph::ros::TFMessage;
using semgraph::ros::TransformStamped;

TransformStamped Make(const std::string& parent, const std::string& child, std::int64_t t_ns,
                      double angle, int axis, double x, double y, double z) {
  TransformStamped t;
  t.header.stamp.sec = t_ns / 1'000'000'000;
  t.header.stamp.nanosec = static_cast<std::uint32_t>(t_ns % 1'000'000'000);
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation = {x, y, z};
  const double s = std::sin(angle / 2), c = std::cos(angle / 2);
  t.transform.rotation = {axis == 0 ? s : 0.0, axis == 1 ? s : 0.0, axis == 2 ? s : 0.0, c};
  return t;
}

// Little-endian appends (MCAP is little-endian).
void U8(std::vector<std::uint8_t>& o, std::uint8_t v) { o.push_back(v); }
void U16(std::vector<std::uint8_t>& o, std::uint16_t v) {
  for (int i = 0; i < 2; ++i) o.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void U32(std::vector<std::uint8_t>& o, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) o.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void U64(std::vector<std::uint8_t>& o, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) o.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void Str(std::vector<std::uint8_t>& o, const std::string& s) {
  U32(o, static_cast<std::uint32_t>(s.size()));
  o.insert(o.end(), s.begin(), s.end());
}
/// opcode, u64 length, content.
void Record(std::vector<std::uint8_t>& o, std::uint8_t op, const std::vector<std::uint8_t>& c) {
  U8(o, op);
  U64(o, c.size());
  o.insert(o.end(), c.begin(), c.end());
}
constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
std::uint32_t Crc(std::uint32_t crc, const std::uint8_t* p, std::size_t n) {
  return static_cast<std::uint32_t>(crc32(crc, p, static_cast<uInt>(n)));
}

}  // namespace

TFMessage RobotStatics(int depth, std::int64_t t0_ns) {
  TFMessage m;
  const std::string last = "f" + std::to_string(depth);
  m.transforms.push_back(Make(last, "camera", t0_ns, 0.3, 0, 0.05, 0.0, 0.1));
  m.transforms.push_back(Make("camera", "camera_optical", t0_ns, -1.5707963, 2, 0, 0, 0));
  return m;
}

TFMessage RobotStep(int depth, int k, std::int64_t t0_ns, std::int64_t period_ns) {
  TFMessage m;
  const std::int64_t t = t0_ns + k * period_ns;
  const double s = static_cast<double>(k) * static_cast<double>(period_ns) * 1e-9;
  for (int i = 1; i <= depth; ++i) {
    const double angle = (0.5 + 0.1 * i) * std::sin((0.3 + 0.17 * i) * s + i);
    m.transforms.push_back(Make("f" + std::to_string(i - 1), "f" + std::to_string(i), t, angle,
                                i % 3, 0.01 * i, 0.1, 0.3 - 0.02 * i));
  }
  return m;
}

RobotTf MakeRobotTf(int depth, int steps, std::int64_t t0_ns, std::int64_t period_ns) {
  RobotTf out;
  out.statics = RobotStatics(depth, t0_ns);
  out.steps.reserve(static_cast<std::size_t>(steps));
  for (int k = 0; k < steps; ++k) out.steps.push_back(RobotStep(depth, k, t0_ns, period_ns));
  return out;
}

McapWriter::McapWriter(const std::string& path, Compression compression, std::size_t chunk_bytes,
                       bool data_crc)
    : compression_(compression), chunk_bytes_(chunk_bytes), data_crc_on_(data_crc) {
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) throw std::runtime_error("cannot write " + path);
  std::vector<std::uint8_t> o(kMagic, kMagic + 8), header;
  Str(header, "ros2");
  Str(header, "semgraph bench/ros_bench_data.cc");
  Record(o, 0x01, header);
  // The data section's CRC covers the file from its first byte (the magic) up to DataEnd.
  std::fwrite(o.data(), 1, o.size(), file_);
  offset_ = o.size();
  data_crc_ = Crc(0, o.data(), o.size());
}

McapWriter::~McapWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

void McapWriter::Emit(const std::vector<std::uint8_t>& bytes) {
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
    throw std::runtime_error("short write");
  }
  data_crc_ = Crc(data_crc_, bytes.data(), bytes.size());
  offset_ += bytes.size();
}

std::uint16_t McapWriter::AddChannel(const std::string& topic, const std::string& type_name) {
  const std::uint16_t id = next_channel_++;
  std::vector<std::uint8_t> schema, channel, records;
  U16(schema, id);
  Str(schema, type_name);
  Str(schema, "ros2msg");
  Str(schema, "");  // the .msg text: not needed to read CDR of a known type
  Record(records, 0x03, schema);
  U16(channel, id);
  U16(channel, id);  // its own schema
  Str(channel, topic);
  Str(channel, "cdr");
  U32(channel, 0);  // no metadata
  Record(records, 0x04, channel);
  Emit(records);
  channels_.insert(channels_.end(), records.begin(), records.end());
  channel_counts_.push_back(0);
  return id;
}

void McapWriter::Write(std::uint16_t channel, std::int64_t log_time_ns,
                       const std::vector<std::uint8_t>& cdr) {
  const auto t = static_cast<std::uint64_t>(log_time_ns);
  if (chunk_.empty()) chunk_start_ = t;
  chunk_end_ = t;
  if (messages_++ == 0) first_time_ = t;
  last_time_ = t;
  ++channel_counts_[channel - 1];
  U8(chunk_, 0x05);
  U64(chunk_, 2 + 4 + 8 + 8 + cdr.size());
  U16(chunk_, channel);
  U32(chunk_, sequence_++);
  U64(chunk_, t);
  U64(chunk_, t);
  chunk_.insert(chunk_.end(), cdr.begin(), cdr.end());
  if (chunk_.size() >= chunk_bytes_) FlushChunk();
}

void McapWriter::FlushChunk() {
  if (chunk_.empty()) return;
  std::vector<std::uint8_t> body;
  std::string name;
  if (compression_ == Compression::kZstd) {
    name = "zstd";
    body.resize(ZSTD_compressBound(chunk_.size()));
    const std::size_t n = ZSTD_compress(body.data(), body.size(), chunk_.data(), chunk_.size(), 1);
    if (ZSTD_isError(n)) throw std::runtime_error("zstd failed");
    body.resize(n);
  } else {
    body = chunk_;
  }
  std::vector<std::uint8_t> content, record;
  U64(content, chunk_start_);
  U64(content, chunk_end_);
  U64(content, chunk_.size());
  U32(content, Crc(0, chunk_.data(), chunk_.size()));
  Str(content, name);
  U64(content, body.size());
  content.insert(content.end(), body.begin(), body.end());
  const std::uint64_t at = offset_;
  Record(record, 0x06, content);
  Emit(record);
  // Its chunk index for the summary (no message index records: message_index_length 0).
  std::vector<std::uint8_t> index;
  U64(index, chunk_start_);
  U64(index, chunk_end_);
  U64(index, at);
  U64(index, record.size());
  U32(index, 0);  // message_index_offsets: empty map
  U64(index, 0);  // message_index_length
  Str(index, name);
  U64(index, body.size());
  U64(index, chunk_.size());
  Record(chunk_indexes_, 0x08, index);
  ++chunks_;
  chunk_.clear();
}

std::uint64_t McapWriter::Close() {
  FlushChunk();
  std::vector<std::uint8_t> end;  // DataEnd: the CRC of every byte before it
  end.push_back(0x0F);
  U64(end, 4);
  U32(end, data_crc_on_ ? data_crc_ : 0);
  std::fwrite(end.data(), 1, end.size(), file_);
  offset_ += end.size();
  // Summary: schemas and channels, statistics, chunk indexes.
  const std::uint64_t summary_start = offset_;
  std::vector<std::uint8_t> summary = channels_, stats;
  U64(stats, messages_);
  U16(stats, static_cast<std::uint16_t>(channel_counts_.size()));
  U32(stats, static_cast<std::uint32_t>(channel_counts_.size()));
  U32(stats, 0);
  U32(stats, 0);
  U32(stats, static_cast<std::uint32_t>(chunks_));
  U64(stats, first_time_);
  U64(stats, last_time_);
  U32(stats, static_cast<std::uint32_t>(channel_counts_.size() * 10));
  for (std::size_t i = 0; i < channel_counts_.size(); ++i) {
    U16(stats, static_cast<std::uint16_t>(i + 1));
    U64(stats, channel_counts_[i]);
  }
  Record(summary, 0x0B, stats);
  summary.insert(summary.end(), chunk_indexes_.begin(), chunk_indexes_.end());
  std::vector<std::uint8_t> footer_head;
  footer_head.push_back(0x02);
  U64(footer_head, 8 + 8 + 4);
  U64(footer_head, summary_start);
  U64(footer_head, 0);  // no summary offset records
  std::uint32_t crc = Crc(0, summary.data(), summary.size());
  crc = Crc(crc, footer_head.data(), footer_head.size());
  std::vector<std::uint8_t> tail = summary;
  tail.insert(tail.end(), footer_head.begin(), footer_head.end());
  U32(tail, crc);
  tail.insert(tail.end(), kMagic, kMagic + 8);
  std::fwrite(tail.data(), 1, tail.size(), file_);
  offset_ += tail.size();
  std::fclose(file_);
  file_ = nullptr;
  return offset_;
}

std::uint64_t WriteRobotBag(const std::string& path, int depth, std::int64_t steps,
                            McapWriter::Compression compression, bool data_crc) {
  constexpr std::int64_t t0 = kDefaultT0, period = kDefaultPeriod;
  McapWriter w(path, compression, std::size_t{1} << 20, data_crc);
  const std::uint16_t statics = w.AddChannel("/tf_static", "tf2_msgs/msg/TFMessage");
  const std::uint16_t dynamic = w.AddChannel("/tf", "tf2_msgs/msg/TFMessage");
  std::vector<std::uint8_t> bytes;
  if (!semgraph::ros::EncodeCdr(RobotStatics(depth, t0), bytes)) std::abort();
  w.Write(statics, t0, bytes);
  // One step's message, re-stamped: the motion repeats every 1,000 steps (so that a 1 GiB bag
  // is written at disk speed); every stamp is new.
  std::vector<TFMessage> cycle;
  for (int k = 0; k < 1000; ++k) cycle.push_back(RobotStep(depth, k, t0, period));
  for (std::int64_t k = 0; k < steps; ++k) {
    TFMessage& m = cycle[static_cast<std::size_t>(k % 1000)];
    const std::int64_t t = t0 + k * period;
    for (TransformStamped& x : m.transforms) {
      x.header.stamp.sec = t / 1'000'000'000;
      x.header.stamp.nanosec = static_cast<std::uint32_t>(t % 1'000'000'000);
    }
    bytes.clear();
    if (!semgraph::ros::EncodeCdr(m, bytes)) std::abort();
    w.Write(dynamic, t, bytes);
  }
  return w.Close();
}

std::vector<DecodedTf> DecodeBagTf(const std::string& path) {
  auto reader = semgraph::ros::OpenBag(path);
  if (!reader) {
    std::fprintf(stderr, "%s\n", semgraph::ros::Describe(reader.error()).c_str());
    std::abort();
  }
  std::vector<DecodedTf> out;
  semgraph::ros::BagRecord r;
  for (;;) {
    auto more = (*reader)->Next(r);
    if (!more) {
      std::fprintf(stderr, "%s\n", semgraph::ros::Describe(more.error()).c_str());
      std::abort();
    }
    if (!*more) break;
    if (r.kind != semgraph::ros::MessageKind::kTfMessage) continue;
    DecodedTf m{r.topic == "/tf_static", std::string(r.topic), r.log_time_ns, {}};
    const auto ok = r.encoding == semgraph::ros::MessageEncoding::kCdr
                        ? semgraph::ros::DecodeCdr(r.data, m.tf)
                        : semgraph::ros::DecodeRos1(r.data, m.tf);
    if (!ok) {
      std::fprintf(stderr, "%s: %s\n", path.c_str(), semgraph::ros::Describe(ok.error()).c_str());
      std::abort();
    }
    out.push_back(std::move(m));
  }
  return out;
}

std::vector<rostf2::Transform> Flatten(const std::vector<DecodedTf>& messages) {
  std::vector<rostf2::Transform> out;
  for (const DecodedTf& m : messages) {
    for (const TransformStamped& t : m.tf.transforms) {
      const auto& q = t.transform.rotation;
      const auto& p = t.transform.translation;
      out.push_back({t.header.frame_id,
                     t.child_frame_id,
                     semgraph::ros::ToNanoseconds(t.header.stamp),
                     m.is_static,
                     {q.w, q.x, q.y, q.z, p.x, p.y, p.z}});
    }
  }
  return out;
}

}  // namespace semgraph_bench::rosdata
