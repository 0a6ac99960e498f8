// The scene the live tests broadcast (ros_dds_test_node's `scene` and `step K`) and rebuild
// locally to compare with what a listener read back:
//   world (body world)
//   +- table        timeless inter-body edge        -> rt/tf_static
//   |  +- table_top constant (body table)           -> rt/tf_static
//   +- base         stamped inter-body edge (body base): one sample per step -> rt/tf
//      +- camera    constant (body base)            -> rt/tf_static
//      +- arm       stamped inter-body edge (body arm): one sample per step -> rt/tf
//         +- tool   constant (body arm)             -> rt/tf_static
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"

namespace semgraph::ros_dds_test {

inline constexpr std::int64_t kT0 = 1'733'300'000'000'000'000;  // ns
inline constexpr std::int64_t kStep = 50'000'000;               // 50 ms between samples

inline const std::vector<std::string>& SceneFrames() {
  static const std::vector<std::string> frames = {"world",  "table", "table_top", "base",
                                                  "camera", "arm",   "tool"};
  return frames;
}

inline Eigen::Quaterniond AxisAngle(double angle, double x, double y, double z) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d(x, y, z).normalized()));
}

/// The timeless part, and sample 0 of the stamped edges.
inline bool BuildScene(core::SceneGraph<>& g) {
  using core::PoseSpec;
  bool ok = true;
  for (const char* b : {"world", "table", "base", "arm"}) ok &= g.AddBody(b).has_value();
  ok &= g.AddPose(PoseSpec::Of("table", "table").RelativeTo("world", "world"),
                  AxisAngle(0.3, 0, 0, 1), Eigen::Vector3d(2.0, -1.0, 0.0))
            .has_value();
  ok &= g.AddPose(PoseSpec::Of("table_top", "table").RelativeTo("table", "table"),
                  AxisAngle(0.0, 0, 0, 1), Eigen::Vector3d(0.0, 0.0, 0.75))
            .has_value();
  ok &=
      g.AddPose(PoseSpec::Of("base", "base").RelativeTo("world", "world"), AxisAngle(0.1, 0, 0, 1),
                Eigen::Vector3d(0.5, 0.25, 0.0), core::Stamp::Nanoseconds(kT0))
          .has_value();
  ok &= g.AddPose(PoseSpec::Of("camera", "base").RelativeTo("base", "base"),
                  AxisAngle(-1.2, 1, 2, 3), Eigen::Vector3d(0.1, 0.0, 0.4))
            .has_value();
  ok &= g.AddPose(PoseSpec::Of("arm", "arm").RelativeTo("base", "base"), AxisAngle(0.2, 0, 1, 0),
                  Eigen::Vector3d(0.0, 0.0, 0.3), core::Stamp::Nanoseconds(kT0))
            .has_value();
  ok &= g.AddPose(PoseSpec::Of("tool", "arm").RelativeTo("arm", "arm"), AxisAngle(0.7, 1, 0, 0),
                  Eigen::Vector3d(0.0, 0.0, 0.2))
            .has_value();
  return ok;
}

/// Sample k (k >= 1) of the stamped edges, at kT0 + k·kStep.
inline bool AddStep(core::SceneGraph<>& g, int k) {
  using core::PoseSpec;
  const core::Stamp at = core::Stamp::Nanoseconds(kT0 + k * kStep);
  const double s = 0.05 * k;
  bool ok = g.AddPose(PoseSpec::Of("base").RelativeTo("world"), AxisAngle(0.1 + s, 0, 0, 1),
                      Eigen::Vector3d(0.5 + s, 0.25 - 0.5 * s, 0.0), at)
                .has_value();
  ok &= g.AddPose(PoseSpec::Of("arm").RelativeTo("base"), AxisAngle(0.2 + 2 * s, 0, 1, 0.2),
                  Eigen::Vector3d(0.0, std::sin(s), 0.3), at)
            .has_value();
  return ok;
}

}  // namespace semgraph::ros_dds_test
