// Scenes of the DDS tests (tests/dds): built by the publisher processes, checked by the
// driver against values computed here independently (plain Eigen products, not the graph).
#pragma once

#include <Eigen/Geometry>
#include <cstdio>
#include <string>

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
inline const Eigen::Quaterniond kQ_BC{Eigen::AngleAxisd(-0.4, Eigen::Vector3d(1, 1, 0).normalized())};
inline const Eigen::Vector3d kP_BC{0.1, 0.0, 1.2};

inline Eigen::Isometry3d Iso(const Eigen::Quaterniond& q, const Eigen::Vector3d& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = p;
  return X;
}
inline Eigen::Quaterniond Rz(double a) { return Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ())); }
inline Eigen::Quaterniond Ry(double a) { return Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY())); }
inline Eigen::Quaterniond Rx(double a) { return Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX())); }

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
  ok &= g.AddPose(PoseSpec::Of("l1", "L1").RelativeTo("b", "B"), Rz(Theta1(0)), {0, 0, 0.5}).has_value();
  ok &= g.AddPose(PoseSpec::Of("l2", "L2").RelativeTo("l1", "L1"), Ry(Theta2(0)), {0.4, 0, 0}).has_value();
  ok &= g.AddPose(PoseSpec::Of("tool", "L2").RelativeTo("l2", "L2"), Eigen::Quaterniond::Identity(), {0.1, 0, 0}).has_value();
  ok &= g.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"), kQ_BC, kP_BC).has_value();
  ok &= g.AddPose(PoseSpec::Of("o", "O").RelativeTo("c", "C"), Rx(ObjectRoll(0)), ObjectPosition(0)).has_value();
  ok &= g.AddTwist(TwistSpec::Of("o", "O").RelativeTo("C").ExpressedIn("o"), {0.01, 0, 0}, {0, 0, 0.1}).has_value();
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
      std::snprintf(line, sizeof line, "Q %s %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", name, q.w(), q.x(), q.y(),
                    q.z(), p.x(), p.y(), p.z());
    }
    out += line;
  };
  pose("tool_in_w", PoseSpec::Of("tool").RelativeTo("w"));
  pose("o_in_w", PoseSpec::Of("o").RelativeTo("w"));
  pose("o_in_tool_at_w", PoseSpec::Of("o").RelativeTo("tool").ExpressedIn("w"));
  auto V = g.GetTwist(TwistSpec::Of("o").RelativeTo("C").ExpressedIn("w"));
  if (V) {
    std::snprintf(line, sizeof line, "Q twist_o_C_w %.17g %.17g %.17g %.17g %.17g %.17g 0\n", V->linear.x(),
                  V->linear.y(), V->linear.z(), V->angular.x(), V->angular.y(), V->angular.z());
  } else {
    std::snprintf(line, sizeof line, "Q twist_o_C_w error %d\n", static_cast<int>(V.error().code));
  }
  out += line;
  return out;
}

}  // namespace semgraph::dds_test
