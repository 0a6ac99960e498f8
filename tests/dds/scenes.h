// Scenes of the DDS tests (tests/dds): built by the publisher processes, checked by the
// driver against values computed here independently (plain Eigen products, not the graph).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"

namespace semgraph::dds_test {

using semgraph::core::PoseSpec;
using semgraph::core::TwistSpec;

// The robot scene, owner "arm": world W, base B, two joints at 1 kHz, a camera, an object seen
// at 30 Hz (pose and twist), and a tool frame fixed on link 2 (a constant same-body edge).
inline double Theta1(int k) { return 0.001 * k; }
inline double Theta2(int k) { return -0.0005 * k; }
inline Eigen::Vector3d ObjectPosition(int j) { return {1.0 + 0.01 * j, 0.2, 0.3}; }
inline double ObjectRoll(int j) { return 0.02 * j; }
inline const Eigen::Quaterniond kQ_WB{Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())};
inline const Eigen::Vector3d kP_WB{0.5, -0.2, 0.0};
inline const Eigen::Quaterniond kQ_BC{
    Eigen::AngleAxisd(-0.4, Eigen::Vector3d(1, 1, 0).normalized())};
inline const Eigen::Vector3d kP_BC{0.1, 0.0, 1.2};

inline Eigen::Isometry3d Iso(const Eigen::Quaterniond& q, const Eigen::Vector3d& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = p;
  return X;
}
inline Eigen::Quaterniond Rz(double a) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()));
}
inline Eigen::Quaterniond Ry(double a) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()));
}
inline Eigen::Quaterniond Rx(double a) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()));
}

/// X_W,tool after joint step k, composed by hand.
inline Eigen::Isometry3d ExpectedToolInWorld(int k) {
  return Iso(kQ_WB, kP_WB) * Iso(Rz(Theta1(k)), {0, 0, 0.5}) * Iso(Ry(Theta2(k)), {0.4, 0, 0}) *
         Iso(Eigen::Quaterniond::Identity(), {0.1, 0, 0});
}
/// X_W,o after object step j.
inline Eigen::Isometry3d ExpectedObjectInWorld(int j) {
  return Iso(kQ_WB, kP_WB) * Iso(kQ_BC, kP_BC) * Iso(Rx(ObjectRoll(j)), ObjectPosition(j));
}

inline bool BuildRobot(core::SceneGraph<>& g) {
  bool ok = true;
  ok &= g.AddPose(PoseSpec::Of("b", "B").RelativeTo("w", "W"), kQ_WB, kP_WB).has_value();
  ok &= g.AddPose(PoseSpec::Of("l1", "L1").RelativeTo("b", "B"), Rz(Theta1(0)), {0, 0, 0.5})
            .has_value();
  ok &= g.AddPose(PoseSpec::Of("l2", "L2").RelativeTo("l1", "L1"), Ry(Theta2(0)), {0.4, 0, 0})
            .has_value();
  ok &= g.AddPose(PoseSpec::Of("tool", "L2").RelativeTo("l2", "L2"), Eigen::Quaterniond::Identity(),
                  {0.1, 0, 0})
            .has_value();
  ok &= g.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"), kQ_BC, kP_BC).has_value();
  ok &= g.AddPose(PoseSpec::Of("o", "O").RelativeTo("c", "C"), Rx(ObjectRoll(0)), ObjectPosition(0))
            .has_value();
  ok &= g.AddTwist(TwistSpec::Of("o", "O").RelativeTo("C").ExpressedIn("o"), {0.01, 0, 0},
                   {0, 0, 0.1})
            .has_value();
  return ok;
}

/// The answers compared between processes: one line per query, 17 significant digits.
inline std::string Answers(const core::SceneGraph<>& g) {
  std::string out;
  char line[512];
  auto pose = [&](const char* name, PoseSpec spec) {
    auto X = g.GetPose(spec);
    if (!X) {
      std::snprintf(line, sizeof line, "Q %s error %d\n", name, static_cast<int>(X.error().code));
    } else {
      const Eigen::Quaterniond q(X->value.rotation);
      const Eigen::Vector3d p = X->value.translation;
      std::snprintf(line, sizeof line, "Q %s %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", name,
                    q.w(), q.x(), q.y(), q.z(), p.x(), p.y(), p.z());
    }
    out += line;
  };
  pose("tool_in_w", PoseSpec::Of("tool").RelativeTo("w"));
  pose("o_in_w", PoseSpec::Of("o").RelativeTo("w"));
  pose("o_in_tool_at_w", PoseSpec::Of("o").RelativeTo("tool").ExpressedIn("w"));
  auto V = g.GetTwist(TwistSpec::Of("o").RelativeTo("C").ExpressedIn("w"));
  if (V) {
    std::snprintf(line, sizeof line, "Q twist_o_C_w %.17g %.17g %.17g %.17g %.17g %.17g 0\n",
                  V->linear.x(), V->linear.y(), V->linear.z(), V->angular.x(), V->angular.y(),
                  V->angular.z());
  } else {
    std::snprintf(line, sizeof line, "Q twist_o_C_w error %d\n", static_cast<int>(V.error().code));
  }
  out += line;
  return out;
}

// The 10 s scene, owner "arm" (stamped, time compressed): world W, base B; joints j1
// (revolute about z), j2 (revolute about y), j3 (prismatic along x), a mimic j4 of j2 and a
// fixed camera joint; joint states at 1 kHz (stamps t0 + k ms, k = 1..10000) and object
// detections o wrt c at 30 Hz (stamps t0 + j * 33333333 ns, j = 1..300), pose and twist.
inline constexpr std::int64_t kT0 = 5'000'000'000;
inline constexpr int kJointSteps = 10000;
inline constexpr int kDetections = 300;
inline std::int64_t JointStamp(int k) { return kT0 + std::int64_t{k} * 1'000'000; }
inline std::int64_t DetectionStamp(int j) { return kT0 + std::int64_t{j} * 33'333'333; }
inline double JointTime(int k) { return 1e-3 * k; }
inline double Q1(int k) { return 0.8 * std::sin(1.9 * JointTime(k)); }
inline double Q2(int k) { return 0.5 * std::cos(1.3 * JointTime(k)) - 0.2; }
inline double Q3(int k) { return 0.25 + 0.2 * std::sin(0.7 * JointTime(k)); }
inline double Q1dot(int k) { return 0.8 * 1.9 * std::cos(1.9 * JointTime(k)); }
inline double Q2dot(int k) { return -0.5 * 1.3 * std::sin(1.3 * JointTime(k)); }
inline double Q3dot(int k) { return 0.2 * 0.7 * std::cos(0.7 * JointTime(k)); }
inline Eigen::Vector3d DetectedPosition(int j) {
  return {1.0 + 0.01 * j, 0.2, 0.3 + 0.1 * std::sin(0.1 * j)};
}
inline double DetectedRoll(int j) { return 0.02 * j; }

inline core::TimeOptions TenSecondTime() {
  core::TimeOptions t;
  t.window = core::Duration::Seconds(11);
  t.sample_capacity = 16384;  // every sample of 10 s at 1 kHz
  return t;
}

inline bool BuildJointRobot(core::SceneGraph<>& g) {
  bool ok = g.AddPose(PoseSpec::Of("b", "B").RelativeTo("w", "W"), kQ_WB, kP_WB).has_value();
  ok &= g.AddTwist(TwistSpec::Of("b", "B").RelativeTo("W").ExpressedIn("b"), {0, 0, 0}, {0, 0, 0})
            .has_value();
  auto joint = [&](const char* name, core::JointType type, const char* parent,
                   const char* parent_body, const char* child, const char* child_body,
                   Eigen::Vector3d p, Eigen::Vector3d axis, double lower, double upper,
                   const char* mimic = "", double multiplier = 1, double offset = 0,
                   Eigen::Quaterniond q = Eigen::Quaterniond::Identity()) {
    core::JointSpec s;
    s.name = name;
    s.type = type;
    s.parent = parent;
    s.parent_body = parent_body;
    s.child = child;
    s.child_body = child_body;
    s.q_origin = q;
    s.p_origin = p;
    s.axis = axis;
    s.lower = lower;
    s.upper = upper;
    s.mimic = mimic;
    s.multiplier = multiplier;
    s.offset = offset;
    ok &= g.AddJoint(s).has_value();
  };
  using core::JointType;
  joint("j1", JointType::kRevolute, "b", "B", "l1", "L1", {0, 0, 0.5}, Eigen::Vector3d::UnitZ(), -3,
        3);
  joint("j2", JointType::kRevolute, "l1", "L1", "l2", "L2", {0.4, 0, 0}, Eigen::Vector3d::UnitY(),
        -3, 3);
  joint("j3", JointType::kPrismatic, "l2", "L2", "l3", "L3", {0.3, 0, 0}, Eigen::Vector3d::UnitX(),
        0, 0.5);
  joint("j4", JointType::kRevolute, "l3", "L3", "finger", "F", {0.05, 0, 0},
        Eigen::Vector3d::UnitZ(), -3, 3, "j2", -0.5, 0.1);
  joint("cam", JointType::kFixed, "b", "B", "c", "C", kP_BC, Eigen::Vector3d::UnitX(), 0, 0, "", 1,
        0, kQ_BC);
  ok &= g.AddPose(PoseSpec::Of("tool", "L3").RelativeTo("l3", "L3"), Eigen::Quaterniond::Identity(),
                  {0.1, 0, 0})
            .has_value();
  const core::Stamp t0 = core::Stamp::Nanoseconds(kT0);
  ok &= g.AddPose(PoseSpec::Of("o", "O").RelativeTo("c", "C"), Rx(DetectedRoll(0)),
                  DetectedPosition(0), t0)
            .has_value();
  ok &= g.AddTwist(TwistSpec::Of("o", "O").RelativeTo("C").ExpressedIn("o"), {0, 0, 0}, {0, 0, 0.1},
                   t0)
            .has_value();
  const core::JointValue q[] = {{"j1", Q1(0)}, {"j2", Q2(0)}, {"j3", Q3(0)}};
  const core::JointValue qdot[] = {{"j1", Q1dot(0)}, {"j2", Q2dot(0)}, {"j3", Q3dot(0)}};
  ok &= g.SetJoints(q, qdot, t0).has_value();
  return ok;
}

/// X_W,tool and X_W,finger at joint step k, composed by hand.
inline Eigen::Isometry3d ExpectedJointTool(int k) {
  return Iso(kQ_WB, kP_WB) * Iso(Rz(Q1(k)), {0, 0, 0.5}) * Iso(Ry(Q2(k)), {0.4, 0, 0}) *
         Iso(Eigen::Quaterniond::Identity(), {0.3 + Q3(k), 0, 0}) *
         Iso(Eigen::Quaterniond::Identity(), {0.1, 0, 0});
}
inline Eigen::Isometry3d ExpectedFinger(int k) {
  return Iso(kQ_WB, kP_WB) * Iso(Rz(Q1(k)), {0, 0, 0.5}) * Iso(Ry(Q2(k)), {0.4, 0, 0}) *
         Iso(Eigen::Quaterniond::Identity(), {0.3 + Q3(k), 0, 0}) *
         Iso(Rz(-0.5 * Q2(k) + 0.1), {0.05, 0, 0});
}

/// The stamps the 10 s scene's answers are compared at: on joint samples, between them, and on
/// detections, across the 10 s.
inline std::vector<std::int64_t> CompareStamps() {
  std::vector<std::int64_t> out;
  for (int i = 0; i <= 40; ++i) {
    out.push_back(JointStamp(250 * i));                        // on a joint sample
    if (i < 40) out.push_back(JointStamp(250 * i) + 123'457);  // between joint samples
  }
  for (int j = 7; j <= kDetections; j += 29) out.push_back(DetectionStamp(j));
  return out;
}

/// Answers at each stamp: one line per (query, stamp), 17 significant digits, or the error code.
inline std::string TimedAnswers(const core::SceneGraph<>& g) {
  std::string out;
  char line[512];
  for (std::int64_t t : CompareStamps()) {
    const core::At at(core::Stamp::Nanoseconds(t));
    auto pose = [&](const char* name, PoseSpec spec) {
      auto X = g.GetPose(spec, at);
      if (!X) {
        std::snprintf(line, sizeof line, "Q %s@%lld error %d\n", name, static_cast<long long>(t),
                      static_cast<int>(X.error().code));
      } else {
        const Eigen::Quaterniond q(X->value.value.rotation);
        const Eigen::Vector3d p = X->value.value.translation;
        std::snprintf(line, sizeof line, "Q %s@%lld %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                      name, static_cast<long long>(t), q.w(), q.x(), q.y(), q.z(), p.x(), p.y(),
                      p.z());
      }
      out += line;
    };
    auto twist = [&](const char* name, TwistSpec spec) {
      auto V = g.GetTwist(spec, at);
      if (!V) {
        std::snprintf(line, sizeof line, "Q %s@%lld error %d\n", name, static_cast<long long>(t),
                      static_cast<int>(V.error().code));
      } else {
        std::snprintf(line, sizeof line, "Q %s@%lld %.17g %.17g %.17g %.17g %.17g %.17g\n", name,
                      static_cast<long long>(t), V->value.linear.x(), V->value.linear.y(),
                      V->value.linear.z(), V->value.angular.x(), V->value.angular.y(),
                      V->value.angular.z());
      }
      out += line;
    };
    pose("tool_in_w", PoseSpec::Of("tool").RelativeTo("w"));
    pose("finger_in_w", PoseSpec::Of("finger").RelativeTo("w"));
    pose("o_in_w", PoseSpec::Of("o").RelativeTo("w"));
    pose("o_in_tool_at_w", PoseSpec::Of("o").RelativeTo("tool").ExpressedIn("w"));
    twist("tool_wrt_W_in_w", TwistSpec::Of("tool").RelativeTo("W").ExpressedIn("w"));
    twist("o_wrt_W_in_w", TwistSpec::Of("o").RelativeTo("W").ExpressedIn("w"));
  }
  return out;
}

// ---- covariances (docs/uncertainty.md): the numbers of the covariance test
// (distributed_test.cc, dds_test_node covariance). A symmetric, diagonally dominant (hence
// positive definite) 6x6 matrix: diag(d) + 1e-6 * (i + 1)(j + 1) / 36 off the diagonal, times
// `scale`.
inline core::Covariance6 TestCovariance(double scale) {
  const double d[6] = {4e-4, 5e-4, 6e-4, 1e-4, 2e-4, 3e-4};
  core::Covariance6 S;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) S(i, j) = i == j ? d[i] : 1e-6 * (i + 1) * (j + 1) / 36.0;
  }
  return scale * S;
}
/// The camera's calibration (a constant edge {cam} wrt {l2}, both on L2) and its covariance.
inline const Eigen::Vector3d kP_L2Cam{0.05, 0.0, 0.02};
inline double CovarianceObjectRoll() { return 0.3; }

// The dynamics scene (the robot scene, owner "arm"): the object's twist edge C -> {o}|O carries
// the acceleration (kA_o, kAlpha_o) in its edge form, and the wrench on O by C is stored at o
// as (kF_o, kM_o): values set by the publisher process after the structure.
inline const Eigen::Vector3d kA_o{0.3, -0.2, 0.1};
inline const Eigen::Vector3d kAlpha_o{0.0, 0.05, 0.4};
inline const Eigen::Vector3d kF_o{2.0, 0.0, -1.0};
inline const Eigen::Vector3d kM_o{0.0, 0.5, 0.0};

}  // namespace semgraph::dds_test
