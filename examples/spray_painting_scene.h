// File: examples/spray_painting_scene.h
//
// The scene of De Laet et al., IROS 2013, §V (Fig. 7/8): a robot spray-paints a moving
// cylinder observed by a point-cloud camera. The numbers are plausible, not measured; they are
// shared by examples/spray_painting.cpp (which prints the queries) and
// tests/core/spray_painting_test.cc (which checks them against world poses built by hand).
//
//   bodies:  B robot base, E end effector, O2 spray gun, O1 cylinder, C camera
//   frames:  {b}|B, {e}|E, {o2}|O2, {o1}|O1, {f1}|O1 (paint point on the cylinder), {c}|C
//
//   poses (edge form, X_PF in [P]):       twists:
//     {b} -> {c}    camera mounting         B -> c     zero, given in [b] (converted on add)
//     {c} -> {o1}   object detection        C -> o1    measured by the camera, given in [c]
//     {o1} -> {f1}  paint point (constant)  E -> o2    zero (rigid gun mounting), in [o2]
//     {b} -> {e}    robot joint positions   B -> e     robot joint velocities, in [e]
//     {e} -> {o2}   spray gun mounting
#pragma once

#include <Eigen/Geometry>

namespace semgraph::examples::spray_painting {

/// R = Rz(yaw) Ry(pitch) Rx(roll), the scene-script convention.
inline Eigen::Quaterniond Rpy(double roll, double pitch, double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

struct EdgePose {
  const char* of;
  const char* of_body;
  const char* wrt;
  const char* wrt_body;
  Eigen::Quaterniond q_PF;  // R_PF: orientation of the child in the parent
  Eigen::Vector3d p_PoFo_P;
};

// Poses of §V, in the order of the text.
inline const EdgePose kPoses[] = {
    {"c", "C", "b", "B", Rpy(0.0, 0.35, 3.14159265358979 * 0.75), {1.2, 0.4, 0.9}},
    {"o1", "O1", "c", "C", Rpy(0.2, -0.1, 0.3), {0.5, 0.2, 1.1}},
    {"f1", "O1", "o1", "O1", Rpy(0.0, 0.0, 0.785398), {0.02, 0.0, 0.2}},
    {"o2", "O2", "e", "E", Rpy(0.0, 1.5707963267949 / 2, 0.0), {0.0, 0.05, 0.12}},
    {"e", "E", "b", "B", Rpy(0.1, 0.4, -0.6), {0.55, -0.15, 0.7}},
};

// Twist of the object O1 relative to the camera C at o1, expressed in [c] (Listing 1).
inline const Eigen::Vector3d kV_CO1_c{0.2, 0.1, 0.1};
inline const Eigen::Vector3d kW_CO1_c{0.05, 0.1, 0.2};
// Twist of the end effector E relative to the base B: screw twist at {e}, in [e].
inline const Eigen::Vector3d kV_BE_e{0.04, -0.03, 0.02};
inline const Eigen::Vector3d kW_BE_e{0.0, 0.15, -0.1};

}  // namespace semgraph::examples::spray_painting
