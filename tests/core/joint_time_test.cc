// Stamped joint states (joint_time.cc; docs/kinematics.md "Time"): samples of (q, qdot) in the
// joints' edge histories, interpolated in joint space, differentiated, extrapolated with the
// joint velocity; a field not given keeps the newest sample's value; mimics follow; the stamp
// rules (stamp_mismatch both ways, stamp_too_old, duplicate_stamp with the joint tolerance) with
// the graph unchanged on refusal; the real-time stamped setters allocate nothing; stamped joint
// accelerations (each sample's qddot, kept from the state when not given, mimics m qddot, the
// composed acceleration of a point by hand, duplicates under the reject policy); the real-time
// stamped setters with qddot (the same samples as SetJoints, by hand and by finite differences,
// every refusal with the graph unchanged, no allocation). Expected
// values are written by hand from the joint formulas X(q) = X_origin Rot(u, q) / Trans(q u).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
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

// Real-time stamped setters with qddot. Each joint moves with a constant acceleration a:
// q(t) = q0 + v0 t + a t^2 / 2, sampled at t = 1, 2, 3 (and at 0.5 without qddot: the first
// stamped state, which makes the histories).
struct Motion {
  double q0, v0, a;
  double q(double t) const { return q0 + v0 * t + 0.5 * a * t * t; }
  double qdot(double t) const { return v0 + a * t; }
};
constexpr Motion kJ1{0.1, 0.4, 0.2}, kJ2{-0.2, 0.3, -0.1};  // within the limits for t <= 3

const std::string_view kBoth[] = {"j1", "j2"};

void FirstStampedState(Graph& g) {
  const JointValue q[] = {{"j1", kJ1.q(0.5)}, {"j2", kJ2.q(0.5)}};
  const JointValue qd[] = {{"j1", kJ1.qdot(0.5)}, {"j2", kJ2.qdot(0.5)}};
  ASSERT_TRUE(g.SetJoints(q, qd, S(0.5)).has_value());
}

void BuildTimeSamples(Graph& g) {
  FirstStampedState(g);
  for (double t : {1.0, 2.0, 3.0}) {
    const JointValue q[] = {{"j1", kJ1.q(t)}, {"j2", kJ2.q(t)}};
    const JointValue qd[] = {{"j1", kJ1.qdot(t)}, {"j2", kJ2.qdot(t)}};
    const JointValue qdd[] = {{"j1", kJ1.a}, {"j2", kJ2.a}};
    ASSERT_TRUE(g.SetJoints(q, qd, qdd, S(t)).has_value());
  }
}

void RealTimeSamples(Graph& g) {
  FirstStampedState(g);
  const JointGroup group = *g.MakeJointGroup(kBoth);
  for (double t : {1.0, 2.0, 3.0}) {
    const double q[] = {kJ1.q(t), kJ2.q(t)}, qd[] = {kJ1.qdot(t), kJ2.qdot(t)},
                 qdd[] = {kJ1.a, kJ2.a};
    ASSERT_EQ(g.SetJointState(group, q, qd, qdd, S(t)), ErrorCode::kOk) << t;
  }
}

Eigen::Vector3d Alpha(const Graph& g, const char* body, const char* ref, double t) {
  auto r = g.GetAngularAcceleration(TwistSpec::Of("", body).RelativeTo(ref).ExpressedIn("base"),
                                    At{S(t)});
  EXPECT_TRUE(r) << body << " at " << t;
  return r ? r->value.value : Eigen::Vector3d::Constant(NAN);
}

// The acceleration of l2's origin wrt `ref` in `in`, at t.
Eigen::Vector3d TipAcceleration(const Graph& g, const char* ref, const char* in, double t) {
  auto r =
      g.GetLinearAcceleration(TwistSpec::Of("l2", "L2").RelativeTo(ref).ExpressedIn(in), At{S(t)});
  EXPECT_TRUE(r) << ref << " at " << t;
  return r ? r->value.value : Eigen::Vector3d::Constant(NAN);
}

// The sample value of a joint at t in [1, 3]: linear between the samples at 1, 2, 3 (joint-space
// interpolation, docs/kinematics.md "Time").
double Sampled(double (Motion::*f)(double) const, const Motion& m, double t) {
  const double t0 = t < 2.0 ? 1.0 : 2.0, u = t - t0;
  return (1 - u) * (m.*f)(t0) + u * (m.*f)(t0 + 1.0);
}

TEST(JointTimeTest, RealTimeStampedAccelerationsAreTheJointFormulas) {
  Graph built = Robot(Interpolation::kScrew), rt = Robot(Interpolation::kScrew);
  BuildTimeSamples(built);
  RealTimeSamples(rt);
  for (double t : {1.0, 1.5, 2.0, 2.75, 3.0}) {
    SCOPED_TRACE(t);
    ExpectNear(Alpha(rt, "L1", "Base", t), Eigen::Vector3d(0, 0, kJ1.a), 1e-12);
    ExpectNear(Alpha(rt, "F", "L1", t), Eigen::Vector3d(0, 0, 2 * kJ1.a), 1e-12);  // the mimic
    // By hand from the interpolated (q, qdot) and qddot: r = Rz(q1) (1, q2, 0) from the axis,
    // a = alpha x r + w x (w x r) + 2 w x v_slide + a_slide.
    const double q1 = Sampled(&Motion::q, kJ1, t), q2 = Sampled(&Motion::q, kJ2, t);
    const double w1 = Sampled(&Motion::qdot, kJ1, t), v2 = Sampled(&Motion::qdot, kJ2, t);
    const Eigen::Vector3d r = Rz(q1) * Eigen::Vector3d(1, q2, 0), w(0, 0, w1), al(0, 0, kJ1.a);
    const Eigen::Vector3d v_slide = Rz(q1) * Eigen::Vector3d(0, v2, 0),
                          a_slide = Rz(q1) * Eigen::Vector3d(0, kJ2.a, 0);
    const Eigen::Vector3d a_hand =
        al.cross(r) + w.cross(w.cross(r)) + 2 * w.cross(v_slide) + a_slide;
    ExpectNear(TipAcceleration(rt, "Base", "base", t), a_hand, 1e-12);
    ExpectNear(TipAcceleration(rt, "L1", "l1", t), Eigen::Vector3d(0, kJ2.a, 0), 1e-12);
    // The build-time stamped SetJoints with qddot gives the same samples.
    ExpectNear(Alpha(built, "L1", "Base", t), Alpha(rt, "L1", "Base", t), 0.0);
    ExpectNear(TipAcceleration(built, "Base", "base", t), TipAcceleration(rt, "Base", "base", t),
               0.0);
    // Finite differences of the queried velocities (qdot is linear between the samples).
    const double h = 1e-4;
    const auto w_at = [&](double s) {
      return rt
          .GetAngularVelocity(TwistSpec::Of("", "L1").RelativeTo("Base").ExpressedIn("base"),
                              At{S(s)})
          ->value.value;
    };
    const auto v_at = [&](double s) {
      return rt
          .GetLinearVelocity(TwistSpec::Of("l2", "L2").RelativeTo("L1").ExpressedIn("l1"), At{S(s)})
          ->value.value;
    };
    const double lo = std::max(1.0, t - h), hi = std::min(3.0, t + h);
    ExpectNear(Eigen::Vector3d((w_at(hi) - w_at(lo)) / (hi - lo)), Alpha(rt, "L1", "Base", t),
               1e-6);
    ExpectNear(Eigen::Vector3d((v_at(hi) - v_at(lo)) / (hi - lo)),
               TipAcceleration(rt, "L1", "l1", t), 1e-6);
  }
  const JointGroup group = *rt.MakeJointGroup(kBoth);
  EXPECT_DOUBLE_EQ(rt.joint_acceleration(group.joints[0]), kJ1.a);
  EXPECT_DOUBLE_EQ(rt.joint_position(group.joints[1]), kJ2.q(3.0));
  EXPECT_EQ(Dump(rt), Dump(built));
}

TEST(JointTimeTest, RealTimeStampedAccelerationsKeepTheNewestPositionsAndVelocities) {
  Graph g = Robot(Interpolation::kLinear);
  RealTimeSamples(g);
  const JointGroup group = *g.MakeJointGroup(kBoth);
  const double qdd[] = {5.0, -0.7};
  ASSERT_EQ(g.SetJointAccelerations(group, qdd, S(4.0)), ErrorCode::kOk);
  EXPECT_DOUBLE_EQ(g.joint_position(group.joints[0]), kJ1.q(3.0));  // the t = 3 sample's
  EXPECT_DOUBLE_EQ(g.joint_velocity(group.joints[0]), kJ1.qdot(3.0));
  EXPECT_DOUBLE_EQ(g.joint_acceleration(group.joints[0]), 5.0);
  ExpectNear(Alpha(g, "L1", "Base", 4.0), Eigen::Vector3d(0, 0, 5), 1e-12);
  ExpectNear(Alpha(g, "F", "L1", 4.0), Eigen::Vector3d(0, 0, 10), 1e-12);  // m qddot
  ExpectNear(Alpha(g, "L1", "Base", 3.5), Eigen::Vector3d(0, 0, 0.5 * (kJ1.a + 5)), 1e-12);
  ExpectNear(TipAcceleration(g, "L1", "l1", 4.0), Eigen::Vector3d(0, -0.7, 0), 1e-12);
  auto X = g.GetOrientation(PoseSpec::Of("l1").RelativeTo("base"), At{S(3.5)});
  ExpectNear(X->value.value, Rz(kJ1.q(3.0)), 1e-12);  // q did not move from 3 to 4
  // A later stamped set without qddot keeps 5 (the state's), as for the build-time setter.
  const double q[] = {0.1, 0.2}, qd[] = {0.0, 0.0};
  ASSERT_EQ(g.SetJointState(group, q, qd, S(5.0)), ErrorCode::kOk);
  ExpectNear(Alpha(g, "L1", "Base", 5.0), Eigen::Vector3d(0, 0, 5), 1e-12);
}

// State() plus the stored accelerations (at the samples and between) and the joint states.
std::string StateWithAccelerations(const Graph& g) {
  std::string out = State(g);
  char buf[200];
  for (double t : {1.0, 1.5, 2.0, 2.5, 3.0}) {
    for (const char* body : {"L1", "F"}) {
      auto a = g.GetAngularAcceleration(
          TwistSpec::Of("", body).RelativeTo(body[0] == 'F' ? "L1" : "Base").ExpressedIn("base"),
          At{S(t)});
      if (a) {
        std::snprintf(buf, sizeof buf, "alpha %s@%g %.17g\n", body, t, a->value.value.z());
        out += buf;
      }
    }
    auto s = g.GetLinearAcceleration(TwistSpec::Of("l2", "L2").RelativeTo("L1").ExpressedIn("l1"),
                                     At{S(t)});
    if (s) {
      std::snprintf(buf, sizeof buf, "slide@%g %.17g\n", t, s->value.value.y());
      out += buf;
    }
  }
  for (const char* name : {"j1", "j2", "m"}) {
    if (auto j = g.FindJoint(name)) {
      std::snprintf(buf, sizeof buf, "%s %.17g %.17g %.17g\n", name, g.joint_position(*j),
                    g.joint_velocity(*j), g.joint_acceleration(*j));
      out += buf;
    }
  }
  return out;
}

TEST(JointTimeTest, RealTimeStampedAccelerationsRefuseInOrderAndChangeNothing) {
  const double q[] = {0.1, 0.2}, qd[] = {0.3, 0.4}, qdd[] = {1.0, 2.0};
  const double nan[] = {1.0, NAN}, over[] = {0.1, 1.5};
  {  // invalid_number -> joint_limit -> stamp_too_old, each with the graph unchanged
    Graph g = Robot(Interpolation::kScrew, DuplicatePolicy::kReplace, Duration::Seconds(1));
    RealTimeSamples(g);
    const JointGroup group = *g.MakeJointGroup(kBoth);
    const std::string before = StateWithAccelerations(g);
    UpdateError why;
    EXPECT_EQ(g.SetJointAccelerations(group, nan, S(3.5), &why), ErrorCode::kInvalidNumber);
    EXPECT_EQ(why.joint, 1u);
    EXPECT_EQ(why.value.role, coord::ValueRole::kJointAcceleration);
    EXPECT_EQ(StateWithAccelerations(g), before);
    why = UpdateError{};
    // A non-finite qddot comes before a limit and a stamp too old.
    EXPECT_EQ(g.SetJointState(group, over, qd, nan, S(0.1), &why), ErrorCode::kInvalidNumber);
    EXPECT_EQ(why.value.role, coord::ValueRole::kJointAcceleration);
    EXPECT_EQ(why.joint, 1u);
    why = UpdateError{};
    EXPECT_EQ(g.SetJointState(group, over, qd, qdd, S(0.1), &why), ErrorCode::kJointLimit);
    EXPECT_EQ(why.joint, 1u);
    EXPECT_DOUBLE_EQ(why.limit, 1.0);
    EXPECT_EQ(g.SetJointState(group, q, qd, qdd, S(1.5)), ErrorCode::kStampTooOld);
    EXPECT_EQ(g.SetJointAccelerations(group, qdd, S(1.5)), ErrorCode::kStampTooOld);
    EXPECT_EQ(StateWithAccelerations(g), before);
  }
  {  // stamp_mismatch: a timeless joint, and a joint without a stamped state yet
    Graph g = Robot(Interpolation::kScrew);
    const JointValue q1[] = {{"j1", 0.2}};
    ASSERT_TRUE(g.SetJoints(q1, {}).has_value());
    const JointGroup group = *g.MakeJointGroup(kBoth);
    const std::string before = StateWithAccelerations(g);
    EXPECT_EQ(g.SetJointState(group, q, qd, qdd, S(1.0)), ErrorCode::kStampMismatch);
    EXPECT_EQ(g.SetJointAccelerations(group, qdd, S(1.0)), ErrorCode::kStampMismatch);
    const std::string_view j2[] = {"j2"};
    const double one[] = {1.0};
    EXPECT_EQ(g.SetJointAccelerations(*g.MakeJointGroup(j2), one, S(1.0)),
              ErrorCode::kStampMismatch);  // never set: its first stamped state is SetJoints'
    EXPECT_EQ(StateWithAccelerations(g), before);
  }
  {  // duplicate_stamp under reject: another qddot at a stored stamp; the same is a no-op
    Graph g = Robot(Interpolation::kScrew, DuplicatePolicy::kReject);
    RealTimeSamples(g);
    const JointGroup group = *g.MakeJointGroup(kBoth);
    const std::string before = StateWithAccelerations(g);
    const double q2[] = {kJ1.q(2.0), kJ2.q(2.0)}, qd2[] = {kJ1.qdot(2.0), kJ2.qdot(2.0)};
    const double same[] = {kJ1.a, kJ2.a}, other[] = {kJ1.a, kJ2.a + 1e-3};
    EXPECT_EQ(g.SetJointState(group, q2, qd2, other, S(2.0)), ErrorCode::kDuplicateStamp);
    EXPECT_EQ(StateWithAccelerations(g), before);
    EXPECT_EQ(g.SetJointState(group, q2, qd2, same, S(2.0)), ErrorCode::kOk);
    EXPECT_EQ(StateWithAccelerations(g), before);
    // SetJointAccelerations at the newest stamp keeps its q and qdot: only qddot decides.
    EXPECT_EQ(g.SetJointAccelerations(group, other, S(3.0)), ErrorCode::kDuplicateStamp);
    EXPECT_EQ(g.SetJointAccelerations(group, same, S(3.0)), ErrorCode::kOk);
    EXPECT_EQ(StateWithAccelerations(g), before);
  }
  {  // unknown_joint: a joint removed since the group was made (before the stamp rules)
    Graph g = Robot(Interpolation::kScrew, DuplicatePolicy::kReplace, Duration::Seconds(1));
    RealTimeSamples(g);
    const JointGroup group = *g.MakeJointGroup(kBoth);
    ASSERT_TRUE(g.RemovePose("l2", "l1"));
    const std::string before = StateWithAccelerations(g);
    EXPECT_EQ(g.SetJointAccelerations(group, qdd, S(0.1)), ErrorCode::kUnknownJoint);
    EXPECT_EQ(g.SetJointState(group, over, qd, qdd, S(4.0)), ErrorCode::kUnknownJoint);
    EXPECT_EQ(StateWithAccelerations(g), before);
  }
}

TEST(JointTimeTest, RealTimeStampedAccelerationsAllocateNothing) {
  Graph g = Robot(Interpolation::kLinear);
  const JointValue q0[] = {{"j1", 0.0}, {"j2", 0.0}};
  // The first stamped state, without qddot: it reserves the acceleration words (allocates).
  ASSERT_TRUE(g.SetJoints(q0, {}, S(0.0)).has_value());
  const JointGroup group = *g.MakeJointGroup(kBoth);
  std::int64_t tick = 1;
  std::size_t allocations = 0;
  std::size_t accepted = 0;
  {
    CountAllocations counting;
    for (int i = 0; i < 2000; ++i, ++tick) {  // 1 kHz, past the capacity
      const double t = static_cast<double>(tick) * 1e-3;
      const double q[] = {std::sin(t), 0.5 * std::sin(t)}, qd[] = {std::cos(t), 0.5 * std::cos(t)},
                   qdd[] = {-std::sin(t), -0.5 * std::sin(t)};
      const Stamp s = Stamp::Nanoseconds(tick * 1000000);
      const ErrorCode c = i % 2 == 0 ? g.SetJointState(group, q, qd, qdd, s)
                                     : g.SetJointAccelerations(group, qdd, s);
      accepted += c == ErrorCode::kOk ? 1 : 0;
    }
    const double nan[] = {NAN, 0.0};
    EXPECT_EQ(g.SetJointAccelerations(group, nan, Stamp::Nanoseconds(tick * 1000000)),
              ErrorCode::kInvalidNumber);
    const double over[] = {0.0, 9.0}, zero[] = {0.0, 0.0};
    EXPECT_EQ(g.SetJointState(group, over, zero, zero, Stamp::Nanoseconds(tick * 1000000)),
              ErrorCode::kJointLimit);
    allocations = counting.count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(accepted, 2000u);
  // The last sample (tick 2000, SetJointAccelerations): qddot1 = -sin(2).
  const double t_last = 2.0;
  EXPECT_DOUBLE_EQ(g.joint_acceleration(group.joints[0]), -std::sin(t_last));
  ExpectNear(Alpha(g, "L1", "Base", t_last), Eigen::Vector3d(0, 0, -std::sin(t_last)), 1e-12);
  ExpectNear(Alpha(g, "F", "L1", t_last), Eigen::Vector3d(0, 0, -2 * std::sin(t_last)), 1e-12);
}

}  // namespace
}  // namespace semgraph::core
