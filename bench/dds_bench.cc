// dds_bench: end-to-end latency and sustained throughput of a distributed scene on loopback
// (docs/distributed.md; run by bench/dds_run.sh beside ddsperf). Two processes: this one
// publishes, a child (argv[0] mirror ...) mirrors and runs a reader thread that spins on a
// compiled query.
//   latency:    one edge set every 100 us (10 kHz); the publisher writes its clock into the
//               value (p.y); the reader sees the new value through its compiled query and
//               records now - p.y (one machine, one clock). p50 / p99 / p99.9.
//   throughput: 100 edges set as fast as the publisher can; the mirror counts values applied
//               per second while the reader keeps evaluating.
//   reader:     spin (the reader thread spins on the query) or wait (it blocks until the
//               mirror's on_change wakes it: C++20 atomic wait, a futex).
//   batch:      1 (one DDS write per update) or N (Publisher::BeginBatch / Flush per N updates).
//   dds_bench [SAMPLES] [UPDATES] [spin|wait] [BATCH]    defaults 20000, 300000, spin, 1; domain 41
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "semgraph/dds/mirror.h"
#include "semgraph/dds/publisher.h"

extern char** environ;

namespace {

using namespace semgraph;
using namespace std::chrono_literals;
constexpr std::uint32_t kDomain = 41;
constexpr int kEdges = 100;

double Seconds() { return static_cast<double>(dds::NowNs()) * 1e-9; }

int MirrorMain(long samples, long updates, bool wait) {
  std::atomic<std::uint64_t> changes{0};
  dds::MirrorOptions options;
  options.name = "bench";
  options.domain = kDomain;
  if (wait) {
    options.on_change = [&changes] {
      changes.fetch_add(1, std::memory_order_release);
      changes.notify_one();
    };
  }
  auto m = dds::Mirror::Create(options);
  if (!m) return 3;
  dds::Mirror& mirror = **m;
  if (!mirror.WaitUntil([&] { return mirror.CaughtUp(); }, 20s)) return 4;
  std::optional<core::CompiledPose<coord::QuaternionBackend>> e0, last;
  mirror.WithGraph([&](const core::SceneGraph<>& g) {
    if (auto c = g.CompilePose(core::PoseSpec::Of("e0").RelativeTo("w"))) e0.emplace(std::move(*c));
    if (auto c =
            g.CompilePose(core::PoseSpec::Of("e" + std::to_string(kEdges - 1)).RelativeTo("w")))
      last.emplace(std::move(*c));
  });
  if (!e0 || !last) return 5;
  std::vector<double> latency_us;
  latency_us.reserve(samples);
  std::atomic<bool> stop{false};
  std::atomic<long> evaluations{0}, recorded{0};
  // Latency: the reader thread spins on the compiled query, or waits for a change.
  std::thread reader([&] {
    coord::QuaternionBackend::PoseCoords X;
    double seen = 0;
    std::uint64_t last_change = changes.load(std::memory_order_acquire);
    while (!stop.load(std::memory_order_relaxed)) {
      if (wait) {
        changes.wait(last_change, std::memory_order_acquire);
        last_change = changes.load(std::memory_order_acquire);
      }
      if (e0->Evaluate(X) != base::ErrorCode::kOk) continue;
      evaluations.fetch_add(1, std::memory_order_relaxed);
      if (X.translation.x() != seen && static_cast<long>(latency_us.size()) < samples) {
        const double now = Seconds();
        seen = X.translation.x();
        if (seen > 0 && X.translation.y() > 0) {  // phase 2 writes y = 0
          latency_us.push_back((now - X.translation.y()) * 1e6);
          recorded.fetch_add(1, std::memory_order_release);
        }
      }
    }
  });
  std::printf("READY\n");
  std::fflush(stdout);
  // Throughput: the publisher's last update of the last edge carries x = -1.
  mirror.WaitUntil(
      [&] {
        coord::QuaternionBackend::PoseCoords X;
        return e0->Evaluate(X) == base::ErrorCode::kOk &&
               X.translation.x() == static_cast<double>(samples);
      },
      60s);
  const std::uint64_t base_count = mirror.values_applied();
  double t0 = 0, t1 = 0;
  std::uint64_t first = 0;
  for (;;) {
    const std::uint64_t n = mirror.values_applied();
    if (t0 == 0 && n > base_count + 1000) {
      t0 = Seconds();
      first = n;
    }
    coord::QuaternionBackend::PoseCoords X;
    if (t0 != 0 && last->Evaluate(X) == base::ErrorCode::kOk && X.translation.x() == -1.0) {
      t1 = Seconds();
      break;
    }
    std::this_thread::sleep_for(100us);
    if (t0 != 0 && Seconds() - t0 > 30) break;
  }
  const std::uint64_t applied = mirror.values_applied() - first;
  stop.store(true);
  changes.fetch_add(1);
  changes.notify_one();
  reader.join();
  std::sort(latency_us.begin(), latency_us.end());
  auto pct = [&](double p) {
    return latency_us.empty()
               ? 0.0
               : latency_us[std::min(latency_us.size() - 1,
                                     static_cast<std::size_t>(p * latency_us.size()))];
  };
  std::printf(
      "latency_samples %zu of %ld sent (the reader sees only the newest value)\nlatency_us p50 "
      "%.1f p99 %.1f p99.9 %.1f max %.1f\n",
      latency_us.size(), samples, pct(0.5), pct(0.99), pct(0.999),
      latency_us.empty() ? 0.0 : latency_us.back());
  std::printf(
      "throughput applied %llu in %.3f s: %.0f updates/s into the mirror (reader evaluations "
      "%ld)\n",
      static_cast<unsigned long long>(applied), t1 - t0, applied / std::max(1e-9, t1 - t0),
      evaluations.load());
  (void)updates;
  return 0;
}

int PublisherMain(const char* self, long samples, long updates, const char* reader_mode,
                  long batch) {
  core::SceneGraph<> g;
  std::vector<core::PoseHandle> edges;
  for (int i = 0; i < kEdges; ++i) {
    const std::string f = "e" + std::to_string(i), b = "E" + std::to_string(i);
    if (!g.AddPose(core::PoseSpec::Of(f, b).RelativeTo("w", "W"), Eigen::Quaterniond::Identity(),
                   {0, 0, 0}))
      return 3;
  }
  for (int i = 0; i < kEdges; ++i) edges.push_back(*g.FindPoseEdge("e" + std::to_string(i), "w"));
  auto pub = dds::Publisher::Create(g, {"bench", kDomain});
  if (!pub || !(*pub)->PublishStructure()) return 3;
  std::string out_path = "/tmp/semgraph_dds_bench_mirror.txt";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0600);
  const std::string s1 = std::to_string(samples), s2 = std::to_string(updates);
  char* argv[] = {const_cast<char*>(self),        const_cast<char*>("mirror"),
                  const_cast<char*>(s1.c_str()),  const_cast<char*>(s2.c_str()),
                  const_cast<char*>(reader_mode), nullptr};
  pid_t pid = 0;
  if (posix_spawn(&pid, self, &actions, nullptr, argv, environ) != 0) return 3;
  // Wait for READY.
  for (int i = 0; i < 2000; ++i) {
    std::FILE* f = std::fopen(out_path.c_str(), "r");
    char buf[64] = {0};
    const bool ready = f && std::fgets(buf, sizeof buf, f) && std::string(buf) == "READY\n";
    if (f) std::fclose(f);
    if (ready) break;
    std::this_thread::sleep_for(10ms);
  }
  std::this_thread::sleep_for(200ms);
  auto next = std::chrono::steady_clock::now();
  for (long k = 1; k <= samples; ++k) {
    next += 100us;
    std::this_thread::sleep_until(next);
    (void)(*pub)->SetPose(edges[0], Eigen::Quaterniond::Identity(),
                          {static_cast<double>(k), Seconds(), 0});
  }
  std::this_thread::sleep_for(200ms);
  const double t0 = Seconds();
  for (long k = 1; k <= updates; ++k) {
    const int e = static_cast<int>(k % kEdges);
    if (batch > 1 && k % batch == 1) (*pub)->BeginBatch();
    (void)(*pub)->SetPose(edges[e], Eigen::Quaterniond::Identity(), {static_cast<double>(k), 0, 0});
    if (batch > 1 && (k % batch == 0 || k == updates)) (*pub)->Flush();
  }
  (void)(*pub)->SetPose(edges[kEdges - 1], Eigen::Quaterniond::Identity(), {-1.0, 0, 0});
  const double t1 = Seconds();
  std::printf(
      "reader %s, batch %ld: publisher sent %ld updates in %.3f s: %.0f updates/s (write failures "
      "%llu)\n",
      reader_mode, batch, updates, t1 - t0, updates / (t1 - t0),
      static_cast<unsigned long long>((*pub)->write_failures()));
  int status = 0;
  waitpid(pid, &status, 0);
  std::FILE* f = std::fopen(out_path.c_str(), "r");
  char line[256];
  while (f && std::fgets(line, sizeof line, f)) {
    if (std::string(line) != "READY\n") std::fputs(line, stdout);
  }
  if (f) std::fclose(f);
  std::remove(out_path.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::string(argv[1]) == "mirror") {
    return MirrorMain(argc > 2 ? std::atol(argv[2]) : 20000, argc > 3 ? std::atol(argv[3]) : 300000,
                      argc > 4 && std::string(argv[4]) == "wait");
  }
  const char* reader_mode = argc > 3 && std::string(argv[3]) == "wait" ? "wait" : "spin";
  return PublisherMain(argv[0], argc > 1 ? std::atol(argv[1]) : 20000,
                       argc > 2 ? std::atol(argv[2]) : 300000, reader_mode,
                       argc > 4 ? std::max(1L, std::atol(argv[4])) : 1);
}
