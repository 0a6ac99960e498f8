// coming_from_tf2.h: what the two halves of the coming_from_tf2 example share. The scene's
// numbers (so that tf2 and semgraph are fed identical inputs) and the answers each side returns,
// in plain doubles: this header is included by a C++17 translation unit (tf2) and a C++20 one
// (semgraph), so it uses neither library.
//
// The scene (frame {x} on body X; tf2 has frames only):
//   {w}|W world  ->  {b}|B robot base   static, X_WB
//   {b}|B        ->  {c}|C camera       static mount, X_BC
//   {c}|C        ->  {o}|O object       seen by the camera, moving: X_CO at t = 1.0 s, and a
//                                       constant twist (v_CO_C of the point o, w_CO_C), in [c]
//   {t}|T table  ->  {k}|K cup          a second, unconnected tree
// Quaternions are [w, x, y, z] (Hamilton); positions in metres; velocities in m/s and rad/s.
#pragma once

#include <cmath>

namespace coming_from_tf2 {

struct Quat {
  double w, x, y, z;
};
struct Vec3 {
  double x, y, z;
};
struct Transform {
  Quat q;  // rotation of the child's axes in the parent's
  Vec3 p;  // position of the child's origin in the parent, in the parent's axes
};

/// The rotation by `angle` about the unit axis (ax, ay, az).
inline Quat AxisAngle(double ax, double ay, double az, double angle) {
  const double s = std::sin(angle / 2);
  return {std::cos(angle / 2), ax * s, ay * s, az * s};
}
/// Hamilton product a * b (rotate by b, then by a).
inline Quat Mul(const Quat& a, const Quat& b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

// ---- the scene's numbers
inline constexpr double kPi = 3.14159265358979323846;
inline const Transform kX_WB{AxisAngle(0, 0, 1, kPi / 2),
                             {2.0, 1.0, 0.0}};  // base, turned 90° about z
inline const Transform kX_BC{AxisAngle(0, 1, 0, 0.6), {0.3, 0.0, 1.2}};  // camera, pitched down
inline const Transform kX_CO{Mul(AxisAngle(1, 0, 0, 0.3), AxisAngle(0, 0, 1, 0.5)),
                             {0.2, -0.1, 1.5}};
inline const Transform kX_TK{AxisAngle(0, 0, 1, 0.2), {0.4, 0.1, 0.8}};  // cup on the table
inline constexpr Vec3 kV_CO_C{0.05, 0.02, -0.1};  // velocity of o relative to C, in [c]
inline constexpr Vec3 kW_CO_C{0.0, 0.1, 0.3};     // angular velocity of O relative to C, in [c]
inline constexpr double kT1 = 1.0, kDt = 0.1;     // tf2 gets X_CO at t1 and at t1 + dt

/// X_CO at t1 + dt under the constant twist: p + v dt, and exp([w] dt) applied in [c].
inline Transform XCOLater() {
  const double n = std::sqrt(kW_CO_C.x * kW_CO_C.x + kW_CO_C.y * kW_CO_C.y + kW_CO_C.z * kW_CO_C.z);
  const Quat dq = AxisAngle(kW_CO_C.x / n, kW_CO_C.y / n, kW_CO_C.z / n, n * kDt);
  return {Mul(dq, kX_CO.q),
          {kX_CO.p.x + kV_CO_C.x * kDt, kX_CO.p.y + kV_CO_C.y * kDt, kX_CO.p.z + kV_CO_C.z * kDt}};
}

/// The questions both sides answer (at t1).
struct Answers {
  Transform X_BO;  // pose of the object in the base frame: tf2 lookupTransform("b", "o")
  Transform X_WC;  // pose of the camera in the world (through static transforms only)
  Vec3 p_BoOo_W;   // position of o relative to b, expressed in the world axes [w]
  Quat R_BO_W;     // orientation of [o] relative to [b], as an operator written in [w]
  bool can_w_o;    // canTransform("w", "o")
  bool can_w_k;    // canTransform("w", "k"): k is in another tree
  Vec3 v_WO_W,
      w_WO_W;  // velocity of the point o of O relative to W, and O's angular velocity, in [w]
  bool second_parent_accepted;  // was {k} given a second parent ({c}) without complaint?
};

/// The tf2 half (coming_from_tf2_tf2.cc). Throws tf2::TransformException on a tf2 error.
Answers AskTf2();

}  // namespace coming_from_tf2
