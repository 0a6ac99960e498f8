// File: examples/ft_sensor_loop.h
//
// A force/torque sensor on a robot's wrist, in a 1 kHz loop (docs/dynamics.md, "Walkthrough: an
// F/T sensor on a wrist"). Shared by examples/ft_sensor_loop.cpp (the program) and
// tests/examples/ft_sensor_loop_test.cc (which checks its answers and its allocations).
//
//   bodies:  World (the earth), Base, Link1, Link2, Link3 (the wrist), Tool (everything beyond
//            the sensor's measuring plane: the gripper and what it holds)
//   frames:  {world}|World, {base}|Base, {link1}|Link1, {link2}|Link2, {link3}|Link3,
//            {flange}|Link3, {ft}|Tool (the sensor's measuring frame), {tool_com}|Tool (the
//            tool's center of mass, axes as {ft}), {tcp}|Tool (the tool center point)
//
//   poses (X_PF in [P]):                               wrenches (on, by):
//     {world} -> {base}    Rz(30 deg), fixed              on Tool by Link3: the sensor's reading,
//     {base}  -> {link1}   joint 1: Rz(q1)                  about {ft} in [ft] (SetWrench)
//     {link1} -> {link2}   joint 2: Ry(q2)                on Tool by World: the tool's weight,
//     {link2} -> {link3}   joint 3: Ry(q3)                  m g at {tool_com}, -z of [world]
//     {link3} -> {flange}  constant (same body)             (rewritten each tick: see below)
//     {flange} -> {ft}     sensor mounting, Ry(90 deg)
//     {ft} -> {tool_com}, {ft} -> {tcp}   constant (same body)
//
// Semantics. The sensor measures the wrench on the Tool by the wrist (Link3) through its
// mounting, about {ft}'s origin, in [ft]; that is the stored form (the storage frame of the pair
// is {ft}, the op's point, a frame of Tool), so SetWrench takes the reading as it comes. The
// tool's weight acts on the Tool by the World, at the center of mass, along -z of [world]. A
// stored wrench is fixed in its storage frame, a frame of the body it acts on: a load whose
// direction is fixed in the world turns with the tool unless rewritten, so each tick rewrites it
// in its storage frame [tool_com] from the current orientation R_CW (a compiled pose query).
// The tool is taken as quasi-static (its acceleration times its mass neglected): the wrenches
// on it sum to zero, so the contact wrench on the Tool by the environment E is the negation of
// the net of the stored ones (sensor + weight). The loop reads it at {tcp}, in [tcp] and in
// [base], from two compiled net-wrench queries.
//
// Real time: Tick and RunLoop are noexcept and allocate nothing (tests/examples count it).
// Costs per tick: three SetPose, one compiled pose (5 edges), two SetWrench, two compiled net
// wrenches (2 terms each, paths of at most 7 edges).
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <utility>

#include "semgraph/core/scene_graph.h"

namespace semgraph::examples::ft_sensor {

namespace sg = semgraph::core;
using Vec = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
using Backend = coord::QuaternionBackend;

// The arm's geometry (m, rad, kg): shared with the test's own forward kinematics.
inline constexpr double kBaseYaw = M_PI / 6;
inline const Vec kBaseOrigin{0.2, -0.1, 0.8};  // {base} in {world}
inline const Vec kLink1Origin{0, 0, 0.3};      // {link1} in {base}
inline const Vec kLink2Origin{0, 0, 0.1};      // {link2} in {link1}
inline const Vec kLink3Origin{0.5, 0, 0};      // {link3} in {link2}
inline const Vec kFlangeOrigin{0.4, 0, 0};     // {flange} in {link3}
inline const Vec kFtOrigin{0.02, 0, 0};        // {ft} in {flange}, rotated Ry(kFtPitch)
inline constexpr double kFtPitch = M_PI / 2;   // the sensor's z along the arm
inline const Vec kComOrigin{0.01, 0, 0.06};    // {tool_com} in {ft}, axes of {ft}
inline const Vec kTcpOrigin{0, 0, 0.15};       // {tcp} in {ft}, rotated Rz(kTcpYaw)
inline constexpr double kTcpYaw = M_PI / 4;
inline constexpr double kToolMass = 1.2;
inline constexpr double kGravity = 9.81;

inline Quat Rz(double a) { return Quat(Eigen::AngleAxisd(a, Vec::UnitZ())); }
inline Quat Ry(double a) { return Quat(Eigen::AngleAxisd(a, Vec::UnitY())); }

/// The tool's weight in [world]: on Tool by World, at {tool_com}.
inline Vec WeightInWorld() { return Vec(0, 0, -kToolMass * kGravity); }

struct Joints {
  double q1 = 0, q2 = 0, q3 = 0;
};

/// A wrench's two parts (force, moment about the point named where it is used).
struct ForceMoment {
  Vec f = Vec::Zero();
  Vec m = Vec::Zero();
};

/// One tick's answers: the contact wrench on Tool by the environment, about {tcp}, in [tcp]
/// and in [base].
struct ContactAtTcp {
  ForceMoment in_tcp, in_base;
};

/// The scene, its handles and its compiled queries. Setup once (allocates, may fail with a
/// message); then Tick from the loop. Not movable: compiled queries point into the graph.
class FtSensorLoop {
 public:
  FtSensorLoop() = default;
  FtSensorLoop(const FtSensorLoop&) = delete;
  FtSensorLoop& operator=(const FtSensorLoop&) = delete;

  /// Builds the scene and compiles the queries. An empty message on success.
  std::string Setup() {
    if (std::string e = AddPoses(); !e.empty()) return e;
    if (std::string e = AddWrenches(); !e.empty()) return e;
    return Compile();
  }

  /// One control tick: the joints and the sensor's reading (on Tool by Link3, about {ft}, in
  /// [ft]) in; the contact wrench at {tcp} out. Returns false when an update or a query fails.
  bool Tick(const Joints& q, const ForceMoment& reading_ft, ContactAtTcp& out) noexcept {
    using semgraph::base::ErrorCode;
    bool ok = graph_.SetPose(joint1_, Rz(q.q1), kLink1Origin) == ErrorCode::kOk;
    ok &= graph_.SetPose(joint2_, Ry(q.q2), kLink2Origin) == ErrorCode::kOk;
    ok &= graph_.SetPose(joint3_, Ry(q.q3), kLink3Origin) == ErrorCode::kOk;
    Backend::PoseCoords X_CW;  // {world} relative to {tool_com}: R_CW turns [world] into [com]
    ok &= X_CW_->Evaluate(X_CW) == ErrorCode::kOk;
    ok &= graph_.SetWrench(weight_, X_CW.rotation * WeightInWorld(), Vec::Zero()) == ErrorCode::kOk;
    ok &= graph_.SetWrench(sensor_, reading_ft.f, reading_ft.m) == ErrorCode::kOk;
    ok &= ContactFromNet(*net_tcp_, out.in_tcp);
    ok &= ContactFromNet(*net_base_, out.in_base);
    return ok;
  }

  [[nodiscard]] const sg::SceneGraph<Backend>& graph() const noexcept { return graph_; }

 private:
  // Quasi-static: contact + (sensor + weight) = 0, so the contact is -net.
  static bool ContactFromNet(const sg::CompiledWrench<Backend>& net,
                             ForceMoment& contact) noexcept {
    if (net.Evaluate(contact.f, contact.m) != semgraph::base::ErrorCode::kOk) return false;
    contact.f = -contact.f;
    contact.m = -contact.m;
    return true;
  }

  std::string AddPoses() {
    const Quat I = Quat::Identity();
    for (const sg::BuildResult& r : {
             graph_.AddPose(sg::PoseSpec::Of("base", "Base").RelativeTo("world", "World"),
                            Rz(kBaseYaw), kBaseOrigin),
             graph_.AddPose(sg::PoseSpec::Of("link1", "Link1").RelativeTo("base"), I, kLink1Origin),
             graph_.AddPose(sg::PoseSpec::Of("link2", "Link2").RelativeTo("link1"), I,
                            kLink2Origin),
             graph_.AddPose(sg::PoseSpec::Of("link3", "Link3").RelativeTo("link2"), I,
                            kLink3Origin),
             graph_.AddPose(sg::PoseSpec::Of("flange", "Link3").RelativeTo("link3"), I,
                            kFlangeOrigin),
             graph_.AddPose(sg::PoseSpec::Of("ft", "Tool").RelativeTo("flange"), Ry(kFtPitch),
                            kFtOrigin),
             graph_.AddPose(sg::PoseSpec::Of("tool_com", "Tool").RelativeTo("ft"), I, kComOrigin),
             graph_.AddPose(sg::PoseSpec::Of("tcp", "Tool").RelativeTo("ft"), Rz(kTcpYaw),
                            kTcpOrigin),
         }) {
      if (!r) return r.error().message;
    }
    return {};
  }

  std::string AddWrenches() {
    // The reading about {ft} in [ft] ({ft} becomes the pair's storage frame); the weight at
    // {tool_com} in [world] (converted once to [tool_com], its storage frame, then rewritten
    // each tick).
    for (const sg::BuildResult& r :
         {graph_.AddWrench(sg::WrenchSpec::On("Tool").By("Link3").At("ft"), Vec::Zero(),
                           Vec::Zero()),
          graph_.AddWrench(
              sg::WrenchSpec::On("Tool").By("World").At("tool_com").ExpressedIn("world"),
              WeightInWorld(), Vec::Zero())}) {
      if (!r) return r.error().message;
    }
    auto sensor = graph_.FindWrench("Tool", "Link3");
    auto weight = graph_.FindWrench("Tool", "World");
    if (!sensor || !weight) return "FindWrench failed";
    const auto& topology = graph_.topology();
    if (sensor->frame != topology.FindFrame("ft") ||
        weight->frame != topology.FindFrame("tool_com")) {
      return "unexpected storage frames";  // the handles take values in these frames
    }
    sensor_ = *sensor;
    weight_ = *weight;
    return {};
  }

  std::string Compile() {
    auto j1 = graph_.FindPoseEdge("link1", "base");
    auto j2 = graph_.FindPoseEdge("link2", "link1");
    auto j3 = graph_.FindPoseEdge("link3", "link2");
    auto X_CW = graph_.CompilePose(sg::PoseSpec::Of("world").RelativeTo("tool_com"));
    auto net_tcp = graph_.CompileWrench(sg::WrenchSpec::On("Tool").At("tcp"));
    auto net_base = graph_.CompileWrench(sg::WrenchSpec::On("Tool").At("tcp").ExpressedIn("base"));
    if (!j1 || !j2 || !j3) return "a joint edge was not found";
    if (!X_CW || !net_tcp || !net_base) return "a query did not compile";
    joint1_ = *j1;
    joint2_ = *j2;
    joint3_ = *j3;
    X_CW_.emplace(std::move(*X_CW));
    net_tcp_.emplace(std::move(*net_tcp));
    net_base_.emplace(std::move(*net_base));
    return {};
  }

  sg::SceneGraph<Backend> graph_;
  sg::PoseHandle joint1_, joint2_, joint3_;
  sg::WrenchHandle sensor_, weight_;
  std::optional<sg::CompiledPose<Backend>> X_CW_;
  std::optional<sg::CompiledWrench<Backend>> net_tcp_, net_base_;
};

// ---------------------------------------------------------------- the simulated robot

/// The joint motion at time t (s): slow, so the quasi-static assumption holds.
inline Joints JointsAt(double t) {
  return {0.6 * std::sin(0.5 * t), -0.4 + 0.3 * std::sin(0.7 * t), 0.9 + 0.4 * std::cos(0.9 * t)};
}

/// The true contact wrench on Tool by the environment at time t, about {tcp}, in [world]: the
/// tool pressing on a surface (normal force up to 10 N, some friction and a small torque).
inline ForceMoment ContactInWorldAt(double t) {
  return {Vec(1.5 * std::sin(M_PI * t), -1.0 * std::cos(M_PI * t), 8.0 + 2.0 * std::sin(2 * t)),
          Vec(0.05 * std::sin(t), 0.02, -0.1 * std::cos(t))};
}

/// The world poses of the frames the simulator needs, by plain Eigen forward kinematics.
struct ArmPoses {
  Eigen::Isometry3d X_W_base, X_W_ft, X_W_com, X_W_tcp;
};
inline Eigen::Isometry3d Pose(const Quat& q, const Vec& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = p;
  return X;
}
inline ArmPoses ForwardKinematics(const Joints& q) {
  ArmPoses X;
  X.X_W_base = Pose(Rz(kBaseYaw), kBaseOrigin);
  const Eigen::Isometry3d X_W_flange = X.X_W_base * Pose(Rz(q.q1), kLink1Origin) *
                                       Pose(Ry(q.q2), kLink2Origin) * Pose(Ry(q.q3), kLink3Origin) *
                                       Pose(Quat::Identity(), kFlangeOrigin);
  X.X_W_ft = X_W_flange * Pose(Ry(kFtPitch), kFtOrigin);
  X.X_W_com = X.X_W_ft * Pose(Quat::Identity(), kComOrigin);
  X.X_W_tcp = X.X_W_ft * Pose(Rz(kTcpYaw), kTcpOrigin);
  return X;
}

/// What the sensor reads when the contact is `contact_W` (about {tcp}, in [world]): the
/// wrench on Tool by Link3 about {ft} in [ft], from the tool's equilibrium
/// sensor + weight + contact = 0 (moments about {ft}'s origin, m_q = m_p + (p - q) x f).
inline ForceMoment SensorReading(const ArmPoses& X, const ForceMoment& contact_W) {
  const Vec o = X.X_W_ft.translation();
  const Vec weight = WeightInWorld();
  const Vec f_W = -(weight + contact_W.f);
  const Vec m_W = -((X.X_W_com.translation() - o).cross(weight) + contact_W.m +
                    (X.X_W_tcp.translation() - o).cross(contact_W.f));
  const Eigen::Matrix3d R_FW = X.X_W_ft.linear().transpose();
  return {R_FW * f_W, R_FW * m_W};
}

// ---------------------------------------------------------------- the loop

struct LoopSummary {
  int ticks = 0;
  int failed_ticks = 0;
  double worst_error = 0;  ///< max over ticks of |graph's contact - true contact| (N, N m)
  ContactAtTcp last;       ///< the last tick's answer
};

/// The 1 kHz loop: each tick, the simulated joints and reading in, the contact out, compared
/// with the simulator's truth. `paced`: sleep until each 1 ms period (else as fast as it runs).
/// `tick_ns` (size >= ticks) receives each tick's duration. noexcept, allocation-free.
inline LoopSummary RunLoop(FtSensorLoop& loop, int ticks, bool paced,
                           std::span<double> tick_ns) noexcept {
  LoopSummary s;
  auto next = std::chrono::steady_clock::now();
  for (int k = 0; k < ticks; ++k) {
    const double t = 1e-3 * k;
    const Joints q = JointsAt(t);
    const ArmPoses X = ForwardKinematics(q);
    const ForceMoment truth_W = ContactInWorldAt(t);
    const ForceMoment reading = SensorReading(X, truth_W);
    const auto t0 = std::chrono::steady_clock::now();
    const bool ok = loop.Tick(q, reading, s.last);
    tick_ns[k] =
        std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
    s.failed_ticks += ok ? 0 : 1;
    const Eigen::Matrix3d R_TW = X.X_W_tcp.linear().transpose();
    const double error = std::max((s.last.in_tcp.f - R_TW * truth_W.f).norm(),
                                  (s.last.in_tcp.m - R_TW * truth_W.m).norm());
    s.worst_error = std::max(s.worst_error, error);
    ++s.ticks;
    if (paced) {
      next += std::chrono::milliseconds(1);
      std::this_thread::sleep_until(next);
    }
  }
  return s;
}

}  // namespace semgraph::examples::ft_sensor
