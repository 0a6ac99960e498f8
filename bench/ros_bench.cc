// semgraph_ros_bench: ROS bags into the graph, wall time (Google Benchmark, one binary so that
// each semgraph/tf2 ratio comes from one run). The data: bench/ros_bench_data.h's robot (a chain
// f0 <- ... <- f8 at 100 Hz for 20 s, two static camera frames: 16,002 transforms), written as
// an MCAP bag by the bench's own writer and read back and decoded by semgraph's reader before
// anything is timed. Both sides keep 10 s of history (tf2's default cache; semgraph's window).
//   ros_ingest_tflift        TfLift::Apply of every decoded message into a fresh graph (its body
//                            plan fed the bag's static transforms first, as ApplyBag does)
//   ros_ingest_tf2           tf2 BufferCore::setTransform of the same transforms, fresh buffer
//   ros_query_oneshot/d      GetPose(fd wrt f0, At{t}) by names, linear interpolation
//   ros_query_compiled/d     CompiledPose::Evaluate at At{t}
//   ros_query_tf2/d          tf2 lookupTransform(f0, fd, t)
//   ros_read_mcap            OpenBag + Next over a 64 MiB bag (page cache warm): bytes/s
//   ros_load_mcap            LoadBag (two passes, decode, lift) of the same bag: bytes/s
// Before timing, every query is checked against tf2 (1e-9). bench/ros_run.sh runs it all.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "ros_bench_data.h"
#include "semgraph/ros/bag_loader.h"

namespace {

using namespace semgraph;
using semgraph_bench::rosdata::DecodedTf;
using Graph = core::SceneGraph<>;

constexpr int kDepth = 8;
constexpr int kSteps = 2000;  // 20 s at 100 Hz
constexpr std::int64_t kQueryOffset =
    15'005'500'000;  // t0 + 15.0055 s: between samples, in the last 10 s

core::TimeOptions TenSeconds() {
  return core::TimeOptions{core::Duration::Seconds(10), core::Interpolation::kLinear,
                           core::DuplicatePolicy::kReplace, 1024};
}

std::string TempPath(const std::string& name) {
  const char* dir = std::getenv("SEMGRAPH_BENCH_TMP");
  return (std::filesystem::path(dir != nullptr ? dir
                                               : std::filesystem::temp_directory_path().c_str()) /
          name)
      .string();
}

struct Data {
  std::string bag = TempPath("semgraph_ros_bench_robot.mcap");
  std::string big = TempPath("semgraph_ros_bench_64MiB.mcap");
  std::uint64_t big_bytes = 0;
  std::vector<DecodedTf> messages;
  std::size_t transforms = 0;
  std::unique_ptr<Graph> graph;  // the bag, loaded
#if defined(SEMGRAPH_HAVE_TF2)
  std::unique_ptr<semgraph_bench::rostf2::Messages> tf2_messages;
  std::unique_ptr<semgraph_bench::rostf2::Buffer> tf2;  // the bag, loaded
#endif
};

const Data& GetData() {
  static Data* d = [] {
    auto* x = new Data;
    semgraph_bench::rosdata::WriteRobotBag(x->bag, kDepth, kSteps,
                                           semgraph_bench::rosdata::McapWriter::Compression::kNone);
    x->messages = semgraph_bench::rosdata::DecodeBagTf(x->bag);
    for (const DecodedTf& m : x->messages) x->transforms += m.tf.transforms.size();
    x->graph = std::make_unique<Graph>(*Graph::Create(TenSeconds()));
    auto report = ros::LoadBag(*x->graph, x->bag, {});
    if (!report || !report->findings.empty() || report->counts.applied != x->transforms) {
      std::fprintf(stderr, "ros_bench: the bag did not load cleanly\n");
      std::abort();
    }
    // 64 MiB: 98,250 messages of 8 transforms (683 bytes of file each).
    x->big_bytes = semgraph_bench::rosdata::WriteRobotBag(
        x->big, kDepth, 98'250, semgraph_bench::rosdata::McapWriter::Compression::kNone);
#if defined(SEMGRAPH_HAVE_TF2)
    const auto flat = semgraph_bench::rosdata::Flatten(x->messages);
    x->tf2_messages = std::make_unique<semgraph_bench::rostf2::Messages>(flat);
    x->tf2 = std::make_unique<semgraph_bench::rostf2::Buffer>();
    if (x->tf2->Ingest(*x->tf2_messages) != flat.size()) std::abort();
    // Every query depth: semgraph == tf2.
    const std::int64_t t = semgraph_bench::rosdata::kDefaultT0 + kQueryOffset;
    for (int dd = 1; dd <= kDepth; ++dd) {
      const std::string fd = "f" + std::to_string(dd);
      semgraph_bench::rostf2::Pose7 y;
      auto X = x->graph->GetPose(core::PoseSpec::Of(fd).RelativeTo("f0"),
                                 core::At(core::Stamp::Nanoseconds(t)));
      if (!X || !x->tf2->Lookup("f0", fd, t, y)) std::abort();
      const Eigen::Isometry3d A = X->value.ToIsometry();
      Eigen::Isometry3d B = Eigen::Isometry3d::Identity();
      B.linear() = Eigen::Quaterniond(y.qw, y.qx, y.qy, y.qz).toRotationMatrix();
      B.translation() = Eigen::Vector3d(y.x, y.y, y.z);
      if ((A.matrix() - B.matrix()).cwiseAbs().maxCoeff() > 1e-9) {
        std::fprintf(stderr, "ros_bench: semgraph and tf2 differ at d = %d\n", dd);
        std::abort();
      }
    }
#endif
    return x;
  }();
  return *d;
}

void ros_ingest_tflift(benchmark::State& state) {
  const Data& d = GetData();
  std::unique_ptr<Graph> graph;
  std::unique_ptr<ros::TfLift<coord::QuaternionBackend>> lift;
  for (auto _ : state) {
    state.PauseTiming();
    lift.reset();
    graph = std::make_unique<Graph>(*Graph::Create(TenSeconds()));
    auto plan = ros::BodyPlan::Make({});
    for (const DecodedTf& m : d.messages) {
      if (!m.is_static) continue;
      for (const auto& t : m.tf.transforms) {
        plan->AddStatic(ros::LiftFrameName(t.header.frame_id),
                        ros::LiftFrameName(t.child_frame_id));
      }
    }
    lift = std::make_unique<ros::TfLift<coord::QuaternionBackend>>(*graph, std::move(*plan));
    state.ResumeTiming();
    for (const DecodedTf& m : d.messages) lift->Apply(m.tf, m.is_static, m.topic, m.log_time_ns);
    benchmark::DoNotOptimize(lift->counts());
  }
  if (lift->counts().applied != d.transforms) state.SkipWithError("transforms refused");
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * d.transforms));
}
BENCHMARK(ros_ingest_tflift)->Unit(benchmark::kMicrosecond);

#if defined(SEMGRAPH_HAVE_TF2)
void ros_ingest_tf2(benchmark::State& state) {
  const Data& d = GetData();
  std::unique_ptr<semgraph_bench::rostf2::Buffer> buffer;
  std::size_t accepted = 0;
  for (auto _ : state) {
    state.PauseTiming();
    buffer = std::make_unique<semgraph_bench::rostf2::Buffer>();
    state.ResumeTiming();
    accepted = buffer->Ingest(*d.tf2_messages);
    benchmark::DoNotOptimize(accepted);
  }
  if (accepted != d.transforms) state.SkipWithError("tf2 refused transforms");
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * d.transforms));
}
BENCHMARK(ros_ingest_tf2)->Unit(benchmark::kMicrosecond);
#endif

void ros_query_oneshot(benchmark::State& state) {
  const Data& d = GetData();
  const std::string of = "f" + std::to_string(state.range(0)), relative_to = "f0";
  const core::At at(core::Stamp::Nanoseconds(semgraph_bench::rosdata::kDefaultT0 + kQueryOffset));
  for (auto _ : state) {
    auto X = d.graph->GetPose(core::PoseSpec::Of(of).RelativeTo(relative_to), at);
    benchmark::DoNotOptimize(X);
  }
}
BENCHMARK(ros_query_oneshot)->DenseRange(2, kDepth, 2);

void ros_query_compiled(benchmark::State& state) {
  const Data& d = GetData();
  auto c = d.graph->CompilePose(
      core::PoseSpec::Of("f" + std::to_string(state.range(0))).RelativeTo("f0"));
  if (!c) std::abort();
  const core::At at(core::Stamp::Nanoseconds(semgraph_bench::rosdata::kDefaultT0 + kQueryOffset));
  coord::QuaternionBackend::PoseCoords X;
  core::TimeReport report;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c->Evaluate(X, at, report));
    benchmark::DoNotOptimize(X);
  }
}
BENCHMARK(ros_query_compiled)->DenseRange(2, kDepth, 2);

#if defined(SEMGRAPH_HAVE_TF2)
void ros_query_tf2(benchmark::State& state) {
  const Data& d = GetData();
  const std::string of = "f" + std::to_string(state.range(0)), relative_to = "f0";
  const std::int64_t t = semgraph_bench::rosdata::kDefaultT0 + kQueryOffset;
  semgraph_bench::rostf2::Pose7 y;
  for (auto _ : state) {
    benchmark::DoNotOptimize(d.tf2->Lookup(relative_to, of, t, y));
    benchmark::DoNotOptimize(y);
  }
}
BENCHMARK(ros_query_tf2)->DenseRange(2, kDepth, 2);
#endif

void ros_read_mcap(benchmark::State& state) {
  const Data& d = GetData();
  std::uint64_t records = 0;
  for (auto _ : state) {
    auto reader = ros::OpenBag(d.big);
    if (!reader) std::abort();
    ros::BagRecord r;
    records = 0;
    for (;;) {
      auto more = (*reader)->Next(r);
      if (!more) std::abort();
      if (!*more) break;
      ++records;
    }
    benchmark::DoNotOptimize(records);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * d.big_bytes));
  state.counters["records"] = static_cast<double>(records);
}
BENCHMARK(ros_read_mcap)->Unit(benchmark::kMillisecond);

void ros_load_mcap(benchmark::State& state) {
  const Data& d = GetData();
  for (auto _ : state) {
    state.PauseTiming();
    auto graph = std::make_unique<Graph>(*Graph::Create(TenSeconds()));
    state.ResumeTiming();
    auto report = ros::LoadBag(*graph, d.big, {});
    if (!report || !report->findings.empty()) std::abort();
    benchmark::DoNotOptimize(report);
    state.PauseTiming();
    graph.reset();
    state.ResumeTiming();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * d.big_bytes));
}
BENCHMARK(ros_load_mcap)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
