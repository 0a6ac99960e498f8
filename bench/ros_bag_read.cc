// semgraph_ros_bag_read: the bag reading benchmark (bench/ros_read.sh runs it).
//   semgraph_ros_bag_read write FILE MIB [none|zstd] [datacrc]   an MCAP bag of about MIB MiB
//                          (the bench's writer: the robot of ros_bench_data.h; chunk CRCs, and
//                          the data section's CRC with `datacrc`)
//   semgraph_ros_bag_read read FILE    OpenBag + Next over every record (no decoding)
//   semgraph_ros_bag_read scan FILE    ScanBag (reads and decodes every /tf, /tf_static message)
//   semgraph_ros_bag_read load FILE    LoadBag into a graph (10 s window, linear, 1,024 samples per
//                                      edge: the graph's size does not grow with the bag)
// Prints one JSON line: bytes, seconds (wall, steady clock), MB/s (10^6 bytes per second),
// records or transforms, and memory: rss_start_kib (VmRSS before opening the bag, after the
// graph is made), max_rss_kib (getrusage peak of the process) and their difference.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "ros_bench_data.h"
#include "semgraph/ros/bag_loader.h"

using namespace semgraph;

namespace {

long RssKib() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::atol(line.c_str() + 6);
  }
  return -1;
}

long MaxRssKib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

int Fail(const std::string& what) {
  std::fprintf(stderr, "semgraph_ros_bag_read: %s\n", what.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: %s write FILE MIB [none|zstd] | read FILE | scan FILE | load FILE\n",
                 argv[0]);
    return 2;
  }
  const std::string cmd = argv[1], file = argv[2];
  if (cmd == "write") {
    if (argc < 4) return 2;
    const double mib = std::atof(argv[3]);
    const bool zstd = argc > 4 && std::strcmp(argv[4], "zstd") == 0;
    const bool data_crc = argc > 5 && std::strcmp(argv[5], "datacrc") == 0;
    // One /tf message of 8 transforms is 683 bytes of file, uncompressed: steps for MIB.
    const auto steps = static_cast<std::int64_t>(mib * 1048576.0 / 683.0);
    const std::uint64_t bytes = semgraph_bench::rosdata::WriteRobotBag(
        file, 8, steps,
        zstd ? semgraph_bench::rosdata::McapWriter::Compression::kZstd
             : semgraph_bench::rosdata::McapWriter::Compression::kNone,
        data_crc);
    std::printf("{\"written\": \"%s\", \"bytes\": %llu, \"messages\": %lld}\n", file.c_str(),
                static_cast<unsigned long long>(bytes), static_cast<long long>(steps + 1));
    return 0;
  }
  const auto bytes = std::filesystem::file_size(file);
  std::unique_ptr<core::SceneGraph<>> graph;
  if (cmd == "load") {
    graph = std::make_unique<core::SceneGraph<>>(*core::SceneGraph<>::Create(
        core::TimeOptions{core::Duration::Seconds(10), core::Interpolation::kLinear,
                          core::DuplicatePolicy::kReplace, 1024}));
  }
  const long rss_start = RssKib();
  const auto t0 = std::chrono::steady_clock::now();
  std::uint64_t count = 0;
  if (cmd == "read") {
    auto reader = ros::OpenBag(file);
    if (!reader) return Fail(ros::Describe(reader.error()));
    ros::BagRecord r;
    for (;;) {
      auto more = (*reader)->Next(r);
      if (!more) return Fail(ros::Describe(more.error()));
      if (!*more) break;
      ++count;
    }
  } else if (cmd == "scan") {
    auto scan = ros::ScanBag(file, {});
    if (!scan) return Fail(ros::Describe(scan.error()));
    count = scan->records;
  } else if (cmd == "load") {
    auto report = ros::LoadBag(*graph, file, {});
    if (!report) return Fail(ros::Describe(report.error()));
    if (!report->findings.empty()) return Fail("findings: " + report->findings.groups()[0].message);
    count = report->counts.applied;
  } else {
    return Fail("unknown command " + cmd);
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const long max_rss = MaxRssKib();
  std::printf(
      "{\"op\": \"%s\", \"bytes\": %llu, \"seconds\": %.3f, \"MB_per_s\": %.1f, \"%s\": %llu, "
      "\"rss_start_kib\": %ld, \"max_rss_kib\": %ld, \"rss_growth_kib\": %ld}\n",
      cmd.c_str(), static_cast<unsigned long long>(bytes), s, static_cast<double>(bytes) / s / 1e6,
      cmd == "load" ? "transforms" : "records", static_cast<unsigned long long>(count), rss_start,
      max_rss, max_rss - rss_start);
  return 0;
}
