// Stamped joint states (joint_time.cc; docs/kinematics.md "Time"): samples of (q, qdot) in the
// joints' edge histories, interpolated in joint space, differentiated, extrapolated with the
// joint velocity; a field not given keeps the newest sample's value; mimics follow; the stamp
// rules (stamp_mismatch both ways, stamp_too_old, duplicate_stamp with the joint tolerance) with
// the graph unchanged on refusal; the real-time stamped setters allocate nothing; stamped joint
// accelerations (each sample's qddot, kept from the state when not given, mimics m qddot, the
// composed acceleration of a point by hand, duplicates under the reject policy). Expected
// values are written by hand from the joint formulas X(q) = X_origin Rot(u, q) / Trans(q u).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/alloc_counter.h"
#include "support/tolerance.h"

namespace semgraph::core {
namespace {

using semgraph::testing::CountAllocations;
using semgraph::testing::ExpectNear;
using Graph = SceneGraph<coord::QuaternionBackend>;

Stamp S(double seconds) { return *StampFromSeconds(seconds); }
Eigen::Quaterniond Rz(double a) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()));
}

// base --(j1: revolute about z, origin p = (0, 0, 0.5))--> l1 --(j2: prismatic along x of l2,
// origin p = (1, 0, 0), R = Rz(pi/2))--> l2; mimic m of j1 (q = 2 q1 + 0.1) to f|F on l1.
Graph Robot(Interpolation mode, DuplicatePolicy duplicates = DuplicatePolicy::kReplace,
            Duration window = Duration::Seconds(10)) {
  TimeOptions o;
  o.interpolation = mode;
  o.duplicate_stamp = duplicates;
  o.window = window;
  Graph g = *Graph::Create(o);
  JointSpec j1;
  j1.name = "j1";
  j1.type = JointType::kRevolute;
  j1.parent = "base";
  j1.parent_body = "Base";
  j1.child = "l1";
  j1.child_body = "L1";
  j1.p_origin = {0, 0, 0.5};
  j1.axis = {0, 0, 1};
  j1.lower = -3;
  j1.upper = 3;
  EXPECT_TRUE(g.AddJoint(j1).has_value());
  JointSpec j2;
  j2.name = "j2";
  j2.type = JointType::kPrismatic;
  j2.parent = "l1";
  j2.child = "l2";
  j2.child_body = "L2";
  j2.p_origin = {1, 0, 0};
  j2.q_origin = Rz(M_PI / 2);
  j2.axis = {1, 0, 0};
  j2.lower = -1;
  j2.upper = 1;
  EXPECT_TRUE(g.AddJoint(j2).has_value());
  JointSpec m;
  m.name = "m";
  m.type = JointType::kContinuous;
  m.parent = "l1";
  m.child = "f";
  m.child_body = "F";
  m.axis = {0, 0, 1};
  m.mimic = "j1";
  m.multiplier = 2;
  m.offset = 0.1;
  EXPECT_TRUE(g.AddJoint(m).has_value());
  return g;
}

// The graph's text dump plus what its histories hold (Dump() shows the current values only):
// each joint edge's sample range and values at a few stamps.
std::string State(const Graph& g) {
  std::string out = Dump(g);
  char buf[160];
  for (const char* frame : {"l1", "l2", "f"}) {
    const char* parent = std::string(frame) == "l2" || std::string(frame) == "f" ? "l1" : "base";
    if (auto uses = g.ExplainPose(PoseSpec::Of(frame).RelativeTo(parent), Latest{})) {
      for (const EdgeUse& u : *uses) {
        std::snprintf(buf, sizeof buf, "%s stamped %d [%lld, %lld]\n", frame, u.stamped ? 1 : 0,
                      u.first ? static_cast<long long>(u.first->nanoseconds()) : -1LL,
                      u.last ? static_cast<long long>(u.last->nanoseconds()) : -1LL);
        out += buf;
      }
    }
    for (double t : {0.5, 1.0, 1.25, 1.5, 2.0}) {
      if (auto X = g.GetPose(PoseSpec::Of(frame).RelativeTo(parent), At{S(t)})) {
        const auto& q = X->value.value.rotation;
        const auto& p = X->value.value.translation;
        std::snprintf(buf, sizeof buf, "%s@%g %.17g %.17g %.17g %.17g %.17g\n", frame, t, q.w(),
                      q.z(), p.x(), p.y(), p.z());
        out += buf;
      }
    }
  }
  return out;
}

// Two samples: t = 1 s: q1 = 0.2, qdot1 = 0.5, q2 = 0.1; t = 2 s: q1 = 0.6, qdot1 = 1.5, q2 = 0.3
// (qdot2 not given: it keeps 0 from the state).
void TwoSamples(Graph& g) {
  const JointValue q_a[] = {{"j1", 0.2}, {"j2", 0.1}};
  const JointValue qd_a[] = {{"j1", 0.5}};
  ASSERT_TRUE(g.SetJoints(q_a, qd_a, S(1.0)).has_value());
  const JointValue q_b[] = {{"j1", 0.6}, {"j2", 0.3}};
  const JointValue qd_b[] = {{"j1", 1.5}};
  ASSERT_TRUE(g.SetJoints(q_b, qd_b, S(2.0)).has_value());
}

TEST(JointTimeTest, InterpolatesInJointSpaceInBothModes) {
  for (Interpolation mode : {Interpolation::kScrew, Interpolation::kLinear}) {
    Graph g = Robot(mode);
    TwoSamples(g);
    // At 1.5 s: q1 = 0.4, q2 = 0.2. l1 wrt base: Rz(0.4), p = (0, 0, 0.5).
    auto X1 = g.GetPose(PoseSpec::Of("l1").RelativeTo("base"), At{S(1.5)});
    ASSERT_TRUE(X1.has_value());
    ExpectNear(X1->value.value.rotation, Rz(0.4), 1e-12);
    ExpectNear(X1->value.value.translation, Eigen::Vector3d(0, 0, 0.5), 1e-12);
    EXPECT_EQ(*X1->time.oldest, S(1.0));
    EXPECT_EQ(*X1->time.newest, S(2.0));
    // l2 wrt l1: origin (1, 0, 0) + Rz(pi/2) (0.2, 0, 0) = (1, 0.2, 0).
    auto X2 = g.GetPose(PoseSpec::Of("l2").RelativeTo("l1"), At{S(1.5)});
    ASSERT_TRUE(X2.has_value());
    ExpectNear(X2->value.value.translation, Eigen::Vector3d(1, 0.2, 0), 1e-12);
    ExpectNear(X2->value.value.rotation, Rz(M_PI / 2), 1e-12);
    // The mimic follows: q = 2 * 0.4 + 0.1 = 0.9.
    auto Xf = g.GetOrientation(PoseSpec::Of("f").RelativeTo("l1"), At{S(1.5)});
    ASSERT_TRUE(Xf.has_value());
    ExpectNear(Xf->value.value, Rz(0.9), 1e-12);
    // Twist edges: qdot1 = 1.0 at 1.5 s (0.5 .. 1.5); w = (0, 0, 1) at l1 in [l1].
    auto V = g.GetTwist(TwistSpec::Of("l1").RelativeTo("Base").ExpressedIn("l1"), At{S(1.5)});
    ASSERT_TRUE(V.has_value());
    ExpectNear(V->value.angular, Eigen::Vector3d(0, 0, 1.0), 1e-12);
    ExpectNear(V->value.linear, Eigen::Vector3d::Zero(), 1e-12);
    // From the poses: (0.6 - 0.2) / 1 s = 0.4 rad/s.
    auto D = g.GetTwist(TwistSpec::Of("l1").RelativeTo("Base").ExpressedIn("l1"), At{S(1.5)},
                        TwistSource::kPoses);
    ASSERT_TRUE(D.has_value());
    ExpectNear(D->value.angular, Eigen::Vector3d(0, 0, 0.4), 1e-12);
    // The state is the newest sample's; untimed queries read it.
    EXPECT_DOUBLE_EQ(g.joint_position(*g.FindJoint("j1")), 0.6);
    EXPECT_DOUBLE_EQ(g.joint_velocity(*g.FindJoint("j1")), 1.5);
    EXPECT_DOUBLE_EQ(g.joint_velocity(*g.FindJoint("j2")), 0.0);
    auto latest = g.GetOrientation(PoseSpec::Of("l1").RelativeTo("base"));
    ExpectNear(latest->value, Rz(0.6), 1e-12);
  }
}

TEST(JointTimeTest, JacobianAtATime) {
  Graph g = Robot(Interpolation::kScrew);
  TwoSamples(g);
  // At 1.5 s (q1 = 0.4, q2 = 0.2), point l2 in [base]: j1 turns about z through (0, 0, 0.5), l2 is
  // at Rz(0.4) (1, 0.2, 0) from it; j2 slides along Rz(0.4) Rz(pi/2) x.
  const auto J =
      g.GetJacobian(TwistSpec::Of("l2").RelativeTo("Base").ExpressedIn("base"), At{S(1.5)});
  ASSERT_TRUE(J.has_value());
  ASSERT_EQ(J->value.J.cols(), 2);
  const double c = std::cos(0.4), s = std::sin(0.4);
  Eigen::Matrix<double, 6, 2> expected;
  expected << -(s + 0.2 * c), -s,  //
      c - 0.2 * s, c,              //
      0, 0,                        //
      0, 0,                        //
      0, 0,                        //
      1, 0;
  ExpectNear(J->value.J, expected, 1e-12);
  EXPECT_EQ(*J->time.time, S(1.5));
  EXPECT_EQ(*J->time.oldest, S(1.0));
  EXPECT_EQ(*J->time.newest, S(2.0));
  EXPECT_EQ(g.GetJacobian(TwistSpec::Of("l2").RelativeTo("Base").ExpressedIn("base"), At{S(3.0)})
                .error()
                .code,
            ErrorCode::kExtrapolation);
}

TEST(JointTimeTest, ExtrapolatesWithTheJointVelocity) {
  Graph g = Robot(Interpolation::kScrew);
  TwoSamples(g);
  // 0.1 s past the newest sample: q1 = 0.6 + 1.5 * 0.1 = 0.75.
  auto X = g.GetOrientation(PoseSpec::Of("l1").RelativeTo("base"),
                            At{S(2.1), Duration::Milliseconds(200)});
  ASSERT_TRUE(X.has_value());
  ExpectNear(X->value.value, Rz(0.75), 1e-12);
  EXPECT_TRUE(X->time.extrapolated);
  EXPECT_EQ(g.GetOrientation(PoseSpec::Of("l1").RelativeTo("base"), At{S(2.1)}).error().code,
            ErrorCode::kExtrapolation);
}

TEST(JointTimeTest, OutOfOrderSamplesKeepTheNewestAsTheState) {
  Graph g = Robot(Interpolation::kScrew);
  TwoSamples(g);
  const JointValue q[] = {{"j1", 0.5}};
  ASSERT_TRUE(g.SetJoints(q, {}, S(1.5)).has_value());  // qdot: the newest sample's, 1.5
  EXPECT_DOUBLE_EQ(g.joint_position(*g.FindJoint("j1")), 0.6);
  auto X = g.GetOrientation(PoseSpec::Of("l1").RelativeTo("base"), At{S(1.25)});
  ExpectNear(X->value.value, Rz(0.35), 1e-12);  // between 0.2 (1 s) and 0.5 (1.5 s)
  auto V = g.GetAngularVelocity(TwistSpec::Of("l1", "L1").RelativeTo("Base").ExpressedIn("l1"),
                                At{S(1.5)});
  ExpectNear(V->value.value, Eigen::Vector3d(0, 0, 1.5), 1e-12);
}

TEST(JointTimeTest, StampRulesRefuseAndChangeNothing) {
  {  // timeless first, then stamped; and stamped first, then unstamped (both setters)
    Graph g = Robot(Interpolation::kScrew);
    const JointValue q[] = {{"j1", 0.2}};
    ASSERT_TRUE(g.SetJoints(q, {}).has_value());
    const std::string before = State(g);
    auto r = g.SetJoints(q, {}, S(1.0));
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, ErrorCode::kStampMismatch);
    EXPECT_NE(r.error().message.find("j1"), std::string::npos) << r.error().message;
    EXPECT_EQ(State(g), before);
    const JointValue q2[] = {{"j2", 0.1}};
    ASSERT_TRUE(g.SetJoints(q2, {}, S(1.0)).has_value());
    const std::string stamped = State(g);
    auto u = g.SetJoints(q2, {});
    ASSERT_FALSE(u.has_value());
    EXPECT_EQ(u.error().code, ErrorCode::kStampMismatch);
    const std::string_view j2[] = {"j2"};
    const JointGroup group = *g.MakeJointGroup(j2);
    const double x[] = {0.2};
    EXPECT_EQ(g.SetJointPositions(group, x), ErrorCode::kStampMismatch);
    EXPECT_EQ(State(g), stamped);
    const std::string_view j1[] = {"j1"};
    EXPECT_EQ(g.SetJointPositions(*g.MakeJointGroup(j1), x, S(2.0)), ErrorCode::kStampMismatch);
    EXPECT_EQ(State(g), stamped);
  }
  {  // too old for the window; a limit violation comes first
    Graph g = Robot(Interpolation::kScrew, DuplicatePolicy::kReplace, Duration::Seconds(1));
    TwoSamples(g);
    const std::string before = State(g);
    const JointValue q[] = {{"j1", 0.1}};
    auto r = g.SetJoints(q, {}, S(0.5));
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, ErrorCode::kStampTooOld);
    const JointValue far[] = {{"j1", 4.0}};
    EXPECT_EQ(g.SetJoints(far, {}, S(0.5)).error().code, ErrorCode::kJointLimit);
    EXPECT_EQ(State(g), before);
    const std::string_view j1[] = {"j1"};
    const double x[] = {0.1};
    EXPECT_EQ(g.SetJointPositions(*g.MakeJointGroup(j1), x, S(0.5)), ErrorCode::kStampTooOld);
    EXPECT_EQ(State(g), before);
  }
  {  // duplicates under reject: the same sample is a no-op, another one is refused
    Graph g = Robot(Interpolation::kScrew, DuplicatePolicy::kReject);
    TwoSamples(g);
    const std::string before = State(g);
    const JointValue same[] = {{"j1", 0.2 + 1e-12}};
    const JointValue same_v[] = {{"j1", 0.5}};
    EXPECT_TRUE(g.SetJoints(same, same_v, S(1.0)).has_value());
    EXPECT_EQ(State(g), before);
    const JointValue other[] = {{"j1", 0.2 + 1e-6}};
    auto r = g.SetJoints(other, same_v, S(1.0));
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, ErrorCode::kDuplicateStamp);
    const JointValue other_v[] = {{"j1", 0.7}};
    EXPECT_EQ(g.SetJoints(same, other_v, S(1.0)).error().code, ErrorCode::kDuplicateStamp);
    EXPECT_EQ(State(g), before);
  }
  {  // replace: another value at a stamp replaces the sample
    Graph g = Robot(Interpolation::kScrew);
    TwoSamples(g);
    const JointValue q[] = {{"j1", 0.4}};
    ASSERT_TRUE(g.SetJoints(q, {}, S(1.0)).has_value());
    auto X = g.GetOrientation(PoseSpec::Of("l1").RelativeTo("base"), At{S(1.5)});
    ExpectNear(X->value.value, Rz(0.5), 1e-12);
  }
}

// Samples with qddot: t = 1 s: q1 = 0.2, qdot1 = 0.5, qddot1 = 2, q2 = 0.1, qddot2 = -1; t = 2 s:
// q1 = 0.6, qdot1 = 1.5, qddot1 = 4, q2 = 0.3 (qdot2 = 0 and qddot2 = -1 kept from the state).
void TwoSamplesWithAccelerations(Graph& g) {
  const JointValue q_a[] = {{"j1", 0.2}, {"j2", 0.1}};
  const JointValue qd_a[] = {{"j1", 0.5}};
  const JointValue qdd_a[] = {{"j1", 2.0}, {"j2", -1.0}};
  ASSERT_TRUE(g.SetJoints(q_a, qd_a, qdd_a, S(1.0)).has_value());
  const JointValue q_b[] = {{"j1", 0.6}, {"j2", 0.3}};
  const JointValue qd_b[] = {{"j1", 1.5}};
  const JointValue qdd_b[] = {{"j1", 4.0}};
  ASSERT_TRUE(g.SetJoints(q_b, qd_b, qdd_b, S(2.0)).has_value());
}

TEST(JointTimeTest, StampedAccelerations) {
  Graph g = Robot(Interpolation::kScrew);
  TwoSamplesWithAccelerations(g);
  const auto alpha = [&](const char* body, const char* ref, double t) {
    auto r = g.GetAngularAcceleration(TwistSpec::Of("", body).RelativeTo(ref).ExpressedIn("base"),
                                      At{S(t)});
    EXPECT_TRUE(r) << body << " at " << t;
    return r ? r->value.value : Eigen::Vector3d::Constant(NAN);
  };
  ExpectNear(alpha("L1", "Base", 1.0), Eigen::Vector3d(0, 0, 2), 1e-12);
  ExpectNear(alpha("L1", "Base", 1.5), Eigen::Vector3d(0, 0, 3), 1e-12);  // interpolated
  ExpectNear(alpha("F", "L1", 1.5), Eigen::Vector3d(0, 0, 6), 1e-12);     // the mimic: 2 qddot
  // The slider's own acceleration at t = 2 (kept from t = 1): qddot2 along its axis, y of l1.
  auto slide = g.GetLinearAcceleration(TwistSpec::Of("l2", "L2").RelativeTo("L1").ExpressedIn("l1"),
                                       At{S(2.0)});
  ASSERT_TRUE(slide);
  ExpectNear(slide->value.value, Eigen::Vector3d(0, -1, 0), 1e-12);
  // l2's origin wrt Base in [base] at t = 2, by hand: r = Rz(q1) (1, q2, 0) from the axis,
  // a = alpha x r + w x (w x r) + a_slide (no Coriolis: qdot2 = 0).
  const Eigen::Vector3d r = Rz(0.6) * Eigen::Vector3d(1, 0.3, 0), w(0, 0, 1.5), al(0, 0, 4);
  const Eigen::Vector3d a_hand =
      al.cross(r) + w.cross(w.cross(r)) + Rz(0.6) * Eigen::Vector3d(0, -1, 0);
  auto tip = g.GetLinearAcceleration(
      TwistSpec::Of("l2", "L2").RelativeTo("Base").ExpressedIn("base"), At{S(2.0)});
  ASSERT_TRUE(tip);
  ExpectNear(tip->value.value, a_hand, 1e-12);
  // A sample without qddot keeps the state's (4), and so do the real-time setters.
  const JointValue q_c[] = {{"j1", 0.8}};
  ASSERT_TRUE(g.SetJoints(q_c, {}, S(3.0)).has_value());
  ExpectNear(alpha("L1", "Base", 2.5), Eigen::Vector3d(0, 0, 4), 1e-12);
  const std::string_view names[] = {"j1"};
  const JointGroup group = *g.MakeJointGroup(names);
  const double q[] = {0.9}, qdot[] = {1.0};
  ASSERT_EQ(g.SetJointState(group, q, qdot, S(4.0)), ErrorCode::kOk);
  ExpectNear(alpha("L1", "Base", 4.0), Eigen::Vector3d(0, 0, 4), 1e-12);
  EXPECT_DOUBLE_EQ(g.joint_acceleration(group.joints[0]), 4.0);
}

TEST(JointTimeTest, AnotherAccelerationAtAStoredStampIsADuplicateUnderReject) {
  Graph g = Robot(Interpolation::kScrew, DuplicatePolicy::kReject);
  TwoSamplesWithAccelerations(g);
  const std::string before = State(g);
  const JointValue q_b[] = {{"j1", 0.6}, {"j2", 0.3}};
  const JointValue qd_b[] = {{"j1", 1.5}};
  const JointValue other[] = {{"j1", 5.0}}, same[] = {{"j1", 4.0}};
  auto dup = g.SetJoints(q_b, qd_b, other, S(2.0));
  ASSERT_FALSE(dup);
  EXPECT_EQ(dup.error().code, ErrorCode::kDuplicateStamp);
  EXPECT_EQ(State(g), before);
  auto alpha = g.GetAngularAcceleration(
      TwistSpec::Of("", "L1").RelativeTo("Base").ExpressedIn("base"), At{S(2.0)});
  ASSERT_TRUE(alpha);
  ExpectNear(alpha->value.value, Eigen::Vector3d(0, 0, 4), 1e-12);
  EXPECT_TRUE(g.SetJoints(q_b, qd_b, same, S(2.0)).has_value());  // the same sample again
}

TEST(JointTimeTest, RealTimeStampedUpdatesAllocateNothing) {
  Graph g = Robot(Interpolation::kLinear);
  const JointValue q0[] = {{"j1", 0.0}, {"j2", 0.0}};
  ASSERT_TRUE(g.SetJoints(q0, {}, S(0.0)).has_value());  // the first stamped state (allocates)
  const std::string_view names[] = {"j1", "j2"};
  const JointGroup group = *g.MakeJointGroup(names);
  auto compiled = *g.CompilePose(PoseSpec::Of("l2").RelativeTo("base"));
  int tick = 1;
  const auto step = [&]() {
    const double t = tick * 1e-3;  // 1 kHz
    const double q[] = {std::sin(t), 0.5 * std::sin(t)}, qdot[] = {std::cos(t), 0.5 * std::cos(t)};
    ++tick;
    return g.SetJointState(group, q, qdot,
                           Stamp::Nanoseconds(static_cast<std::int64_t>(tick - 1) * 1000000));
  };
  ASSERT_EQ(step(), ErrorCode::kOk);
  std::size_t allocations = 0;
  {
    CountAllocations counting;
    for (int i = 0; i < 2000; ++i) {  // past the capacity: the oldest samples are dropped
      if (step() != ErrorCode::kOk) break;
    }
    const double bad[] = {9.0, 0.0};
    EXPECT_EQ(g.SetJointPositions(group, bad, Stamp::Nanoseconds(tick * 1000000)),
              ErrorCode::kJointLimit);
    coord::QuaternionBackend::PoseCoords X{};
    TimeReport report;
    EXPECT_EQ(compiled.Evaluate(X, At{Stamp::Nanoseconds((tick - 2) * 1000000 - 500000)}, report),
              ErrorCode::kOk);
    allocations = counting.count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(tick, 2002);
  // The last sample is q1 = sin(2.001): the state and the latest query say so.
  EXPECT_DOUBLE_EQ(g.joint_position(group.joints[0]), std::sin(2.001));
}

}  // namespace
}  // namespace semgraph::core
