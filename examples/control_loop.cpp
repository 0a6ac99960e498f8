// control_loop: the real-time pattern semgraph is built for. A scene is built once; queries are
// compiled once (semantics checked, paths resolved); then a 1 kHz control loop evaluates them
// while a second thread feeds new joint poses and a new measured twist through handles.
// Evaluate / SetPose / SetTwist are noexcept, allocation-free, lock-free and string-free.
//
// Legend: W world {w}; B robot base {b}; L1, L2 links {l1}, {l2}; T tool {t} on L2; O object
// {o}. X_WB is the pose of B in W.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

#include "semgraph/core/scene_graph.h"

namespace sg = semgraph::core;
using Eigen::AngleAxisd;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {
Quaterniond Rz(double angle) { return Quaterniond(AngleAxisd(angle, Vector3d::UnitZ())); }
Quaterniond Ry(double angle) { return Quaterniond(AngleAxisd(angle, Vector3d::UnitY())); }

bool Check(const sg::BuildResult& r) {
  if (!r) std::fprintf(stderr, "%s\n", r.error().message.c_str());
  return static_cast<bool>(r);
}
}  // namespace

int main(int argc, char** argv) {
  const int cycles = argc > 1 ? std::atoi(argv[1]) : 1000;  // 1 s at 1 kHz by default

  // ---- Build phase: allocations and rich errors are fine here.
  sg::SceneGraph<> graph;
  bool ok = Check(graph.AddPose(sg::PoseSpec::Of("b", "B").RelativeTo("w", "W"),
                                Quaterniond::Identity(), Vector3d(0, 0, 0.4)));
  ok &= Check(graph.AddPose(sg::PoseSpec::Of("l1", "L1").RelativeTo("b", "B"), Rz(0.0),
                            Vector3d(0, 0, 0.3)));
  ok &= Check(graph.AddPose(sg::PoseSpec::Of("l2", "L2").RelativeTo("l1", "L1"), Ry(0.0),
                            Vector3d(0.5, 0, 0)));
  ok &= Check(graph.AddPose(sg::PoseSpec::Of("t", "L2").RelativeTo("l2", "L2"),
                            Quaterniond::Identity(),
                            Vector3d(0.4, 0, 0)));  // tool point: constant on L2
  ok &=
      Check(graph.AddPose(sg::PoseSpec::Of("o", "O").RelativeTo("w", "W"), Quaterniond::Identity(),
                          Vector3d(0.8, 0.3, 0.1)));  // object pose from perception
  ok &= Check(graph.AddTwist(sg::TwistSpec::Of("o", "O").RelativeTo("W").ExpressedIn("o"),
                             Vector3d::Zero(), Vector3d::Zero()));
  ok &= Check(graph.AddTwist(sg::TwistSpec::Of("l1", "L1").RelativeTo("B").ExpressedIn("l1"),
                             Vector3d::Zero(), Vector3d::Zero()));
  ok &= Check(graph.AddTwist(sg::TwistSpec::Of("l2", "L2").RelativeTo("L1").ExpressedIn("l2"),
                             Vector3d::Zero(), Vector3d::Zero()));
  ok &= Check(graph.AddTwist(sg::TwistSpec::Of("b", "B").RelativeTo("W").ExpressedIn("b"),
                             Vector3d::Zero(), Vector3d::Zero()));
  if (!ok) return 1;

  // Handles for the values the feeder thread updates, and the compiled queries of the loop.
  auto joint1 = graph.FindPoseEdge("l1", "b");
  auto joint2 = graph.FindPoseEdge("l2", "l1");
  auto joint1_rate = graph.FindTwistEdge("l1", "B");
  auto joint2_rate = graph.FindTwistEdge("l2", "L1");
  // Where is the tool relative to the object, expressed in the object frame?
  auto X_OT = graph.CompilePose(sg::PoseSpec::Of("t", "L2").RelativeTo("o", "O"));
  // How fast does the tool point move relative to the object, in the world axes?
  auto V_OT_W = graph.CompileTwist(sg::TwistSpec::Of("t", "L2").RelativeTo("O").ExpressedIn("w"));
  if (!joint1 || !joint2 || !joint1_rate || !joint2_rate || !X_OT || !V_OT_W) {
    std::fprintf(stderr, "setup failed\n");
    return 1;
  }

  // ---- Feeder thread: joint encoders at ~2 kHz (the single writer).
  std::atomic<bool> stop{false};
  std::thread feeder([&] {
    const auto start = std::chrono::steady_clock::now();
    while (!stop.load(std::memory_order_relaxed)) {
      const double t =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double q1 = 0.5 * std::sin(t), q2 = 0.3 * std::cos(2 * t);
      const double dq1 = 0.5 * std::cos(t), dq2 = -0.6 * std::sin(2 * t);
      (void)graph.SetPose(*joint1, Rz(q1), Vector3d(0, 0, 0.3));
      (void)graph.SetPose(*joint2, Ry(q2), Vector3d(0.5, 0, 0));
      (void)graph.SetTwist(*joint1_rate, Vector3d::Zero(),
                           Vector3d(0, 0, dq1));  // screw twist at l1, in [l1]
      (void)graph.SetTwist(*joint2_rate, Vector3d::Zero(), Vector3d(0, dq2, 0));
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
  });

  // ---- Control loop at 1 kHz: evaluate, compute a command, sleep until the next period.
  std::vector<double> eval_ns(cycles);  // preallocated: the loop itself allocates nothing
  typename sg::SceneGraph<>::Backend::PoseCoords X;
  Vector3d v, w;
  double distance = 0.0;
  auto next = std::chrono::steady_clock::now();
  for (int i = 0; i < cycles; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    if (X_OT->Evaluate(X) != semgraph::base::ErrorCode::kOk) return 1;
    if (V_OT_W->Evaluate(v, w) != semgraph::base::ErrorCode::kOk) return 1;
    const auto t1 = std::chrono::steady_clock::now();
    eval_ns[i] = std::chrono::duration<double, std::nano>(t1 - t0).count();
    distance = X.translation.norm();  // a controller would servo on X and v here
    next += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(next);
  }
  stop = true;
  feeder.join();

  std::sort(eval_ns.begin(), eval_ns.end());
  std::printf("control loop: %d cycles at 1 kHz; last tool-object distance %.4f m, |v| %.4f m/s\n",
              cycles, distance, v.norm());
  std::printf("evaluate (pose + twist) latency: p50 %.0f ns, p99 %.0f ns, max %.0f ns\n",
              eval_ns[cycles / 2], eval_ns[cycles * 99 / 100], eval_ns.back());
  return 0;
}
