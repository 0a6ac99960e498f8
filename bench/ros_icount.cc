// semgraph_ros_icount KERNEL D ITERS: queries on a loaded bag, one kernel per process, for
// callgrind instruction counts (bench/ros_icount.sh runs them all; like icount.cc). The bag:
// bench/ros_bench_data.h's robot (chain f0 <- ... <- f8 at 100 Hz, 20 s), written as MCAP by
// the bench's writer into $SEMGRAPH_BENCH_TMP (default: the temporary directory), loaded by
// LoadBag into a graph with linear interpolation and a 10 s window, and fed to tf2 (10 s cache)
// from the same decoded messages. Each kernel is an extern "C" noipa function doing one query
// of fD wrt f0 at t0 + 15.0055 s (between samples):
//   oneshot_at     SceneGraph::GetPose(PoseSpec by names, At{t})   (tf2's lookupTransform use)
//   compiled_at    CompiledPose::Evaluate(X, At{t}, report)         (compiled once, before)
//   tf2_at         tf2 BufferCore::lookupTransform("f0", "fD", t)
// and the ingest of the whole bag (16,002 transforms; D ignored, ITERS times; Ir per transform =
// Ir / (ITERS x 16,002)), each into a fresh graph or buffer made outside the counted function:
//   ingest_tflift  TfLift::Apply of every decoded message (the plan fed the static transforms)
//   ingest_tf2     tf2 setTransform of every transform (prebuilt geometry_msgs messages)
// Before counting, semgraph's and tf2's answers are checked against each other (1e-9).
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "ros_bench_data.h"
#include "semgraph/ros/bag_loader.h"

using namespace semgraph;
using QuatB = coord::QuaternionBackend;

namespace {
constexpr std::int64_t kNewest = semgraph_bench::rosdata::kDefaultT0 + 19'990'000'000;
std::int64_t kT = kNewest - 45'500'000;  // AGE recent (main sets it)
}  // namespace

#if defined(__clang__)
#define SEMGRAPH_KERNEL __attribute__((noinline))
#else
#define SEMGRAPH_KERNEL __attribute__((noipa))  // callgrind toggles by the function's name
#endif

extern "C" {
SEMGRAPH_KERNEL int icount_oneshot_at(const core::SceneGraph<QuatB>* g, const std::string* of,
                                      const std::string* relative_to, QuatB::PoseCoords* X) {
  auto r = g->GetPose(core::PoseSpec::Of(*of).RelativeTo(*relative_to),
                      core::At{core::Stamp::Nanoseconds(kT)});
  if (r) *X = r->value.value;
  return r ? 0 : 1;
}
SEMGRAPH_KERNEL int icount_compiled_at(const core::CompiledPose<QuatB>* c, QuatB::PoseCoords* X) {
  core::TimeReport report;
  return static_cast<int>(c->Evaluate(*X, core::At{core::Stamp::Nanoseconds(kT)}, report));
}
SEMGRAPH_KERNEL std::uint64_t icount_ingest_tflift(
    ros::TfLift<QuatB>* lift, const std::vector<semgraph_bench::rosdata::DecodedTf>* messages) {
  for (const auto& m : *messages) lift->Apply(m.tf, m.is_static, m.topic, m.log_time_ns);
  return lift->counts().applied;
}
#if defined(SEMGRAPH_HAVE_TF2)
SEMGRAPH_KERNEL std::size_t icount_ingest_tf2(semgraph_bench::rostf2::Buffer* buffer,
                                              const semgraph_bench::rostf2::Messages* messages) {
  return buffer->Ingest(*messages);
}
SEMGRAPH_KERNEL int icount_tf2_at(const semgraph_bench::rostf2::Buffer* tf,
                                  const std::string* relative_to, const std::string* of,
                                  semgraph_bench::rostf2::Pose7* out) {
  return tf->Lookup(*relative_to, *of, kT, *out) ? 0 : 1;
}
#endif
}

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s oneshot_at|compiled_at|tf2_at D ITERS [recent|middle]\n",
                 argv[0]);
    return 2;
  }
  const std::string kernel = argv[1];
  const int d = std::atoi(argv[2]);
  const long iters = std::atol(argv[3]);
  if (d < 1 || d > 8) return 2;
  if (argc > 4 && std::string(argv[4]) == "middle") kT = kNewest - 4'984'500'000;
  const char* dir = std::getenv("SEMGRAPH_BENCH_TMP");
  const std::string bag =
      (std::filesystem::path(dir != nullptr ? dir
                                            : std::filesystem::temp_directory_path().c_str()) /
       ("semgraph_ros_icount_" + std::to_string(::getpid()) + ".mcap"))
          .string();
  semgraph_bench::rosdata::WriteRobotBag(bag, 8, 2000,
                                         semgraph_bench::rosdata::McapWriter::Compression::kNone);
  auto graph = core::SceneGraph<QuatB>::Create(
      core::TimeOptions{core::Duration::Seconds(10), core::Interpolation::kLinear,
                        core::DuplicatePolicy::kReplace, 1024});
  auto report = ros::LoadBag(*graph, bag, {});
  if (!report || !report->findings.empty()) {
    std::fprintf(stderr, "the bag did not load cleanly\n");
    return 1;
  }
  const std::string f0 = "f0", fd = "f" + std::to_string(d);
  QuatB::PoseCoords X;
  if (icount_oneshot_at(&*graph, &fd, &f0, &X) != 0) return 1;
#if defined(SEMGRAPH_HAVE_TF2)
  const auto flat = semgraph_bench::rosdata::Flatten(semgraph_bench::rosdata::DecodeBagTf(bag));
  semgraph_bench::rostf2::Messages messages(flat);
  semgraph_bench::rostf2::Buffer tf;
  if (tf.Ingest(messages) != flat.size()) return 1;
  semgraph_bench::rostf2::Pose7 y;
  if (icount_tf2_at(&tf, &f0, &fd, &y) != 0) return 1;
  const Eigen::Quaterniond q_tf2(y.qw, y.qx, y.qy, y.qz);
  if ((X.translation - Eigen::Vector3d(y.x, y.y, y.z)).norm() > 1e-9 ||
      X.rotation.angularDistance(q_tf2) > 1e-9) {
    std::fprintf(stderr, "semgraph and tf2 differ at d = %d\n", d);
    return 1;
  }
#endif
  const auto decoded = semgraph_bench::rosdata::DecodeBagTf(bag);
  std::filesystem::remove(bag);
  if (kernel == "ingest_tflift") {
    for (long i = 0; i < iters; ++i) {
      auto fresh = core::SceneGraph<QuatB>::Create(
          core::TimeOptions{core::Duration::Seconds(10), core::Interpolation::kLinear,
                            core::DuplicatePolicy::kReplace, 1024});
      auto plan = ros::BodyPlan::Make({});
      for (const auto& m : decoded) {
        if (!m.is_static) continue;
        for (const auto& t : m.tf.transforms) {
          plan->AddStatic(ros::LiftFrameName(t.header.frame_id),
                          ros::LiftFrameName(t.child_frame_id));
        }
      }
      ros::TfLift<QuatB> lift(*fresh, std::move(*plan));
      if (icount_ingest_tflift(&lift, &decoded) != 16'002) return 1;
    }
#if defined(SEMGRAPH_HAVE_TF2)
  } else if (kernel == "ingest_tf2") {
    for (long i = 0; i < iters; ++i) {
      semgraph_bench::rostf2::Buffer fresh;
      if (icount_ingest_tf2(&fresh, &messages) != 16'002) return 1;
    }
#endif
  } else if (kernel == "oneshot_at") {
    for (long i = 0; i < iters; ++i) icount_oneshot_at(&*graph, &fd, &f0, &X);
  } else if (kernel == "compiled_at") {
    auto c = graph->CompilePose(core::PoseSpec::Of(fd).RelativeTo(f0));
    if (!c) return 1;
    for (long i = 0; i < iters; ++i) icount_compiled_at(&*c, &X);
#if defined(SEMGRAPH_HAVE_TF2)
  } else if (kernel == "tf2_at") {
    for (long i = 0; i < iters; ++i) icount_tf2_at(&tf, &f0, &fd, &y);
#endif
  } else {
    std::fprintf(stderr, "unknown kernel %s\n", kernel.c_str());
    return 2;
  }
  return 0;
}
