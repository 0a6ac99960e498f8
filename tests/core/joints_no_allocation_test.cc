// The joints' real-time claims (joints.h, jacobian.h), proven by counting the global operator
// new (tests/support/alloc_counter.h): setting positions, velocities, accelerations or all of
// them for a group of joints (with a mimic following), accepted and rejected (joint_limit,
// invalid_number, unknown_joint), and evaluating compiled poses, twists, accelerations and
// Jacobians after the updates, allocate nothing. Each case runs once unarmed (to check its result
// code), then 100 times armed.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "support/alloc_counter.h"

namespace semgraph::core {
namespace {

using semgraph::testing::CountAllocations;

template <class F>
void ExpectNoAllocation(const std::string& what, ErrorCode expected, F&& run) {
  ASSERT_EQ(run(), expected) << what << " took another path than intended";
  std::size_t allocations = 0;
  {
    CountAllocations counting;
    for (int i = 0; i < 100; ++i) {
      if (run() != expected) break;
    }
    allocations = counting.count();
  }
  EXPECT_EQ(allocations, 0u) << what;
}

TEST(JointsNoAllocation, StateUpdatesAndCompiledQueries) {
  SceneGraph<> g;
  const char* links[] = {"l0", "l1", "l2", "l3", "l4", "l5", "l6", "l7"};
  const char* bodies[] = {"L0", "L1", "L2", "L3", "L4", "L5", "L6", "L7"};
  for (int i = 0; i < 7; ++i) {
    JointSpec s;
    const std::string name = "j" + std::to_string(i + 1);
    s.name = name;
    s.type = i == 3 ? JointType::kPrismatic : JointType::kRevolute;
    s.parent = links[i];
    s.parent_body = bodies[i];
    s.child = links[i + 1];
    s.child_body = bodies[i + 1];
    s.p_origin = {0.1, 0.0, 0.3};
    s.q_origin = Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * i, Eigen::Vector3d::UnitX()));
    s.axis = {0, i % 2 ? 1.0 : 0.0, i % 2 ? 0.0 : 1.0};
    s.lower = -2;
    s.upper = 2;
    ASSERT_TRUE(g.AddJoint(s));
  }
  JointSpec finger;
  finger.name = "finger";
  finger.type = JointType::kPrismatic;
  finger.parent = "l7";
  finger.child = "f";
  finger.child_body = "F";
  finger.mimic = "j7";
  finger.multiplier = 0.5;
  ASSERT_TRUE(g.AddJoint(finger));
  const JointGroup all = g.AllJoints();
  ASSERT_EQ(all.size(), 7u);
  auto pose = g.CompilePose(PoseSpec::Of("f").RelativeTo("l0"));
  auto twist = g.CompileTwist(TwistSpec::Of("f").RelativeTo("L0").ExpressedIn("l0"));
  auto jacobian = g.CompileJacobian(TwistSpec::Of("f").RelativeTo("L0").ExpressedIn("l0"));
  auto acceleration = g.CompileAcceleration(TwistSpec::Of("f").RelativeTo("L0").ExpressedIn("l0"));
  ASSERT_TRUE(pose && twist && jacobian && acceleration);
  ASSERT_EQ(jacobian->num_columns(), 7u);
  std::vector<double> q(7, 0.3), qdot(7, -0.2), q_over(7, 0.3), q_nan(7, 0.3);
  q_over[5] = 2.5;
  q_nan[2] = std::nan("");
  double t = 0;
  ExpectNoAllocation("SetJointPositions", ErrorCode::kOk, [&] {
    q[0] = std::sin(t += 0.01);
    return g.SetJointPositions(all, q);
  });
  ExpectNoAllocation("SetJointVelocities", ErrorCode::kOk,
                     [&] { return g.SetJointVelocities(all, qdot); });
  ExpectNoAllocation("SetJointState", ErrorCode::kOk,
                     [&] { return g.SetJointState(all, q, qdot); });
  std::vector<double> qddot(7, 0.4), qddot_nan(7, 0.4);
  qddot_nan[4] = std::nan("");
  ExpectNoAllocation("SetJointAccelerations", ErrorCode::kOk, [&] {
    qddot[1] = std::cos(t += 0.01);
    return g.SetJointAccelerations(all, qddot);
  });
  ExpectNoAllocation("SetJointVelocities keeping the accelerations", ErrorCode::kOk,
                     [&] { return g.SetJointVelocities(all, qdot); });
  ExpectNoAllocation("SetJointState with accelerations", ErrorCode::kOk,
                     [&] { return g.SetJointState(all, q, qdot, qddot); });
  ExpectNoAllocation("SetJointAccelerations with NaN", ErrorCode::kInvalidNumber,
                     [&] { return g.SetJointAccelerations(all, qddot_nan); });
  ExpectNoAllocation("SetJointPositions over a limit", ErrorCode::kJointLimit,
                     [&] { return g.SetJointPositions(all, q_over); });
  ExpectNoAllocation("SetJointPositions with NaN", ErrorCode::kInvalidNumber,
                     [&] { return g.SetJointPositions(all, q_nan); });
  UpdateError why;  // the detail of a refusal (update_error.h) allocates nothing either
  ExpectNoAllocation("SetJointPositions over a limit, with its detail", ErrorCode::kJointLimit,
                     [&] { return g.SetJointPositions(all, q_over, &why); });
  ExpectNoAllocation("SetJointPositions with NaN, with its detail", ErrorCode::kInvalidNumber,
                     [&] { return g.SetJointPositions(all, q_nan, &why); });
  ExpectNoAllocation("SetJointState with a NaN acceleration, with its detail",
                     ErrorCode::kInvalidNumber,
                     [&] { return g.SetJointState(all, q, qdot, qddot_nan, &why); });
  coord::QuaternionBackend::PoseCoords X;
  ExpectNoAllocation("CompiledPose after joint updates", ErrorCode::kOk, [&] {
    if (g.SetJointPositions(all, q) != ErrorCode::kOk) return ErrorCode::kInvalidNumber;
    return pose->Evaluate(X);
  });
  Eigen::Vector3d v, w;
  ExpectNoAllocation("CompiledTwist", ErrorCode::kOk, [&] { return twist->Evaluate(v, w); });
  Eigen::Vector3d a, alpha;
  ExpectNoAllocation("CompiledAcceleration after joint updates", ErrorCode::kOk, [&] {
    if (g.SetJointAccelerations(all, qddot) != ErrorCode::kOk) return ErrorCode::kInvalidNumber;
    return acceleration->Evaluate(a, alpha);
  });
  Eigen::Matrix<double, 6, 7> J;  // caller storage, fixed size
  ExpectNoAllocation("CompiledJacobian (fixed-size storage)", ErrorCode::kOk,
                     [&] { return jacobian->Evaluate(J); });
  JacobianMatrix Jd(6, 7);  // caller storage, allocated once before
  ExpectNoAllocation("CompiledJacobian (dynamic storage)", ErrorCode::kOk,
                     [&] { return jacobian->Evaluate(Jd); });
  // J qdot is the twist (no other twist edges on the path).
  Eigen::Matrix<double, 7, 1> qd;
  for (int i = 0; i < 7; ++i) qd(i) = qdot[static_cast<std::size_t>(i)];
  const Eigen::Matrix<double, 6, 1> Jq = J * qd;
  EXPECT_LE((Jq.head<3>() - v).norm(), 1e-12);
  EXPECT_LE((Jq.tail<3>() - w).norm(), 1e-12);
  // A removed joint: the stale group is refused without allocating.
  ASSERT_TRUE(g.RemovePose("f", "l7"));
  ASSERT_TRUE(g.RemovePose("l4", "l3"));
  ExpectNoAllocation("SetJointPositions with a removed joint", ErrorCode::kUnknownJoint,
                     [&] { return g.SetJointPositions(all, q); });
  ExpectNoAllocation("CompiledJacobian after the removal", ErrorCode::kQueryInvalidated,
                     [&] { return jacobian->Evaluate(J); });
}

}  // namespace
}  // namespace semgraph::core
