// The tf2 half of coming_from_tf2 (see coming_from_tf2.cpp for the semgraph half and the
// comparison): the scene of coming_from_tf2.h built and queried the way a ROS 1 tf2 user would.
// Compiled as C++17: the ROS 1 message headers use std::allocator<void>::rebind, which C++20
// removed, so tf2 cannot be included next to semgraph (C++20) in one translation unit.
#include <geometry_msgs/TransformStamped.h>
#include <tf2/LinearMath/Quaternion.h>
#include <tf2/LinearMath/Vector3.h>
#include <tf2/buffer_core.h>

#include <string>

#include "coming_from_tf2.h"

namespace coming_from_tf2 {
namespace {

geometry_msgs::TransformStamped Message(const std::string& parent, const std::string& child,
                                        const Transform& X, double stamp) {
  geometry_msgs::TransformStamped m;
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.header.stamp = ros::Time(stamp);
  m.transform.rotation.w = X.q.w;
  m.transform.rotation.x = X.q.x;
  m.transform.rotation.y = X.q.y;
  m.transform.rotation.z = X.q.z;
  m.transform.translation.x = X.p.x;
  m.transform.translation.y = X.p.y;
  m.transform.translation.z = X.p.z;
  return m;
}

tf2::Quaternion Q(const geometry_msgs::TransformStamped& m) {
  const auto& r = m.transform.rotation;
  return tf2::Quaternion(r.x, r.y, r.z, r.w);  // tf2 takes x, y, z, w
}
tf2::Vector3 P(const geometry_msgs::TransformStamped& m) {
  const auto& t = m.transform.translation;
  return tf2::Vector3(t.x, t.y, t.z);
}
Transform FromMsg(const geometry_msgs::TransformStamped& m) {
  const auto& r = m.transform.rotation;
  const auto& t = m.transform.translation;
  return {{r.w, r.x, r.y, r.z}, {t.x, t.y, t.z}};
}
Quat FromTf2(const tf2::Quaternion& q) { return {q.w(), q.x(), q.y(), q.z()}; }
Vec3 FromTf2(const tf2::Vector3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

Answers AskTf2() {
  tf2::BufferCore buffer;
  // Frames exist as soon as a transform names them; every message is parent -> child.
  buffer.setTransform(Message("w", "b", kX_WB, 0.0), "example", /*is_static=*/true);
  buffer.setTransform(Message("b", "c", kX_BC, 0.0), "example", true);
  buffer.setTransform(Message("t", "k", kX_TK, 0.0), "example", true);
  // The object: two stamped samples; tf2 interpolates between them.
  buffer.setTransform(Message("c", "o", kX_CO, kT1), "example");
  buffer.setTransform(Message("c", "o", XCOLater(), kT1 + kDt), "example");

  const ros::Time t1(kT1), t2(kT1 + kDt);
  Answers a{};
  // lookupTransform(target, source): the pose of source in target.
  a.X_BO = FromMsg(buffer.lookupTransform("b", "o", t1));
  a.X_WC = FromMsg(buffer.lookupTransform("w", "c", ros::Time(0)));  // Time(0): latest

  // Expressing o-relative-to-b in the world axes needs the rotation of b in w, by hand.
  const tf2::Quaternion q_WB = Q(buffer.lookupTransform("w", "b", ros::Time(0)));
  const geometry_msgs::TransformStamped X_BO = buffer.lookupTransform("b", "o", t1);
  a.p_BoOo_W = FromTf2(tf2::quatRotate(q_WB, P(X_BO)));
  a.R_BO_W = FromTf2(q_WB * Q(X_BO) * q_WB.inverse());  // the operator, conjugated into [w]

  a.can_w_o = buffer.canTransform("w", "o", t1);
  a.can_w_k = buffer.canTransform("w", "k", t1);

  // ROS 1 tf2 has no lookupTwist (it is commented out in buffer_core.h): difference two lookups.
  const geometry_msgs::TransformStamped X_WO_1 = buffer.lookupTransform("w", "o", t1);
  const geometry_msgs::TransformStamped X_WO_2 = buffer.lookupTransform("w", "o", t2);
  a.v_WO_W = FromTf2((P(X_WO_2) - P(X_WO_1)) / kDt);
  tf2::Quaternion dq = Q(X_WO_2) * Q(X_WO_1).inverse();  // rotation over dt, in [w]
  if (dq.w() < 0) dq = dq * -1.0;                        // the short way round
  a.w_WO_W = FromTf2(dq.getAxis() * (dq.getAngle() / kDt));

  // A second parent for the cup: tf2 takes it (the cup now hangs below the camera).
  a.second_parent_accepted = buffer.setTransform(Message("c", "k", kX_TK, kT1), "example");
  return a;
}

}  // namespace coming_from_tf2
