// Joint accelerations qddot (joints.h; scene_graph.h: SetJoints with accelerations,
// SetJointAccelerations, SetJointState with qddot; docs/dynamics.md): the edge form each joint
// stores (revolute: alpha = u qddot, a = 0; prismatic: a = u qddot, alpha = 0) and a composite
// acceleration, both against values worked out by hand with Eigen; a joint whose qddot was never
// given leaves its edge without an acceleration (no_acceleration naming the edge); a later q or
// qdot keeps qddot (as a joint keeps every field it is not given) and the twist stored beside it
// follows; mimic joints follow m qddot; removal forgets it; every rejection (by name and by
// group) leaves the graph unchanged (Dump), and stamped joints refuse qddot (stamp_mismatch: not
// supported yet). The peer check against DART is joints_accelerations_dart_test.cc.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "semgraph/core/update_error.h"

namespace semgraph::core {
namespace {

using Graph = SceneGraph<>;
using Vec = Eigen::Vector3d;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Eigen::Matrix3d Rpy(double r, double p, double y) {
  return (Eigen::AngleAxisd(y, Vec::UnitZ()) * Eigen::AngleAxisd(p, Vec::UnitY()) *
          Eigen::AngleAxisd(r, Vec::UnitX()))
      .toRotationMatrix();
}

// A two-link arm: B {b} -j1 revolute about z, origin (0, 0, 0.4) rotated rpy(0.1, -0.2, 0.3)->
// L1 {l1} -j2 prismatic along (1, 1, 0)/sqrt 2, origin (0.5, 0, 0)-> L2 {l2}; a fixed joint
// l2 -> {t}|T and a point {e} fixed on L2 at (0.2, -0.1, 0.3) from {l2}.
class JointAccelerations : public ::testing::Test {
 protected:
  void SetUp() override {
    JointSpec j1 = Joint("j1", JointType::kRevolute, "b", "B", "l1", "L1");
    j1.R_origin = Rpy(0.1, -0.2, 0.3);
    j1.p_origin = {0.0, 0.0, 0.4};
    j1.axis = {0, 0, 2};  // normalized to z
    ASSERT_TRUE(g.AddJoint(j1));
    JointSpec j2 = Joint("j2", JointType::kPrismatic, "l1", "", "l2", "L2");
    j2.p_origin = {0.5, 0.0, 0.0};
    j2.axis = {1, 1, 0};
    ASSERT_TRUE(g.AddJoint(j2));
    ASSERT_TRUE(g.AddJoint(Joint("fx", JointType::kFixed, "l2", "", "t", "T")));
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("e", "L2").RelativeTo("l2"), Eigen::Quaterniond::Identity(),
                          Vec(0.2, -0.1, 0.3)));
  }
  static JointSpec Joint(std::string_view name, JointType type, std::string_view parent,
                         std::string_view parent_body, std::string_view child,
                         std::string_view child_body) {
    JointSpec s;
    s.name = name;
    s.type = type;
    s.parent = parent;
    s.parent_body = parent_body;
    s.child = child;
    s.child_body = child_body;
    s.lower = -2;
    s.upper = 2;
    return s;
  }
  // AccelerationCoord(e|L2, B, [b]) by hand, for j1 at (q1, qd1, qdd1) and j2 at (q2, qd2, qdd2):
  // L1 turns about the axis z1 = R_b1 z through l1's origin, L2 slides along u_b = R_b1 u.
  static void ByHand(double q1, double qd1, double qdd1, double q2, double qd2, double qdd2, Vec& a,
                     Vec& alpha) {
    const Eigen::Matrix3d R_b1 = Rpy(0.1, -0.2, 0.3) * Eigen::AngleAxisd(q1, Vec::UnitZ());
    const Vec p_b1(0, 0, 0.4), u = Vec(1, 1, 0).normalized();
    const Vec p_be = p_b1 + R_b1 * (Vec(0.5, 0, 0) + q2 * u + Vec(0.2, -0.1, 0.3));
    const Vec w = R_b1 * Vec::UnitZ() * qd1, dw = R_b1 * Vec::UnitZ() * qdd1;
    const Vec r = p_be - p_b1, u_b = R_b1 * u;
    // The point of L1 at e, then L2's slide relative to L1 with its Coriolis term.
    a = dw.cross(r) + w.cross(w.cross(r)) + 2 * w.cross(u_b * qd2) + u_b * qdd2;
    alpha = dw;  // a prismatic joint adds no rotation
  }
  void ExpectByHand(double q1, double qd1, double qdd1, double q2, double qd2, double qdd2) {
    Vec a, alpha;
    ByHand(q1, qd1, qdd1, q2, qd2, qdd2, a, alpha);
    auto A = g.GetAcceleration(spec);
    ASSERT_TRUE(A) << g.Describe(A.error(), spec);
    EXPECT_LE((A->linear - a).norm(), 1e-13) << A->linear.transpose() << " vs " << a.transpose();
    EXPECT_LE((A->angular - alpha).norm(), 1e-13);
    EXPECT_EQ(CheckInvariants(g), "");
  }
  void ExpectNoAcceleration(std::string_view head) {
    auto A = g.GetAcceleration(spec);
    ASSERT_FALSE(A);
    EXPECT_EQ(A.error().code, ErrorCode::kNoAcceleration);
    EXPECT_EQ(g.names().name(A.error().name), head);
  }
  double Qddot(std::string_view joint) { return g.joint_acceleration(*g.FindJoint(joint)); }

  Graph g;
  const TwistSpec spec = TwistSpec::Of("e", "L2").RelativeTo("B").ExpressedIn("b");
};

TEST_F(JointAccelerations, EachJointStoresTheEdgeFormOfItsQddot) {
  const JointValue qddot[] = {{"j1", 0.8}, {"j2", -0.6}};
  ASSERT_TRUE(g.SetJoints({}, {}, qddot));
  const FrameIndex l1 = g.topology().FindFrame("l1"), l2 = g.topology().FindFrame("l2");
  auto A1 = g.acceleration_value(l1), A2 = g.acceleration_value(l2);
  ASSERT_TRUE(A1 && A2);
  EXPECT_EQ(A1->linear, Vec::Zero());  // the child origin is on the axis
  EXPECT_LE((A1->angular - Vec(0, 0, 0.8)).norm(), 1e-15);
  EXPECT_LE((A2->linear - (-0.6) * Vec(1, 1, 0).normalized()).norm(), 1e-15);
  EXPECT_EQ(A2->angular, Vec::Zero());
  EXPECT_EQ(Qddot("j1"), 0.8);
  EXPECT_EQ(Qddot("j2"), -0.6);
  // The fixed joint's edge never carries one: the tool frame's relation has no acceleration.
  EXPECT_FALSE(g.acceleration_value(g.topology().FindFrame("t")));
}

TEST_F(JointAccelerations, ComposedAlongTheArmAsWorkedOutByHand) {
  const JointValue q[] = {{"j1", 0.7}, {"j2", 0.25}};
  const JointValue qdot[] = {{"j1", 1.5}, {"j2", -0.3}};
  const JointValue qddot[] = {{"j1", 0.8}, {"j2", -0.6}};
  ASSERT_TRUE(g.SetJoints(q, qdot, qddot));
  ExpectByHand(0.7, 1.5, 0.8, 0.25, -0.3, -0.6);
  // The inverse relation at the same point: a_CB = -a_BC + 2 w_BC x v_BC (not the negation).
  auto A = g.GetAcceleration(spec);
  auto V = g.GetTwist(spec);
  auto Ainv = g.GetAcceleration(TwistSpec::Of("e", "B").RelativeTo("L2").ExpressedIn("b"));
  ASSERT_TRUE(A && V && Ainv);
  EXPECT_LE((Ainv->linear - (-A->linear + 2 * V->angular.cross(V->linear))).norm(), 1e-13);
  EXPECT_LE((Ainv->angular + A->angular).norm(), 1e-15);
}

TEST_F(JointAccelerations, NeverGivenMeansNoAccelerationNamingTheEdge) {
  const JointValue q[] = {{"j1", 0.7}, {"j2", 0.25}};
  const JointValue qdot[] = {{"j1", 1.5}, {"j2", -0.3}};
  ASSERT_TRUE(g.SetJoints(q, qdot));  // q and qdot, no qddot: not an implicit zero
  ExpectNoAcceleration("l2");
  EXPECT_TRUE(std::isnan(Qddot("j1")));
  const JointValue qddot2[] = {{"j2", -0.6}};
  ASSERT_TRUE(g.SetJoints({}, {}, qddot2));
  ExpectNoAcceleration("l1");  // j1's edge, B -> {l1}
  auto A = g.GetAcceleration(TwistSpec::Of("e", "L2").RelativeTo("L1").ExpressedIn("b"));
  ASSERT_TRUE(A) << g.Describe(A.error(), spec);  // j2 alone on this path
  const JointValue qddot1[] = {{"j1", 0.0}};      // a zero given is a value
  ASSERT_TRUE(g.SetJoints({}, {}, qddot1));
  ExpectByHand(0.7, 1.5, 0.0, 0.25, -0.3, -0.6);
}

TEST_F(JointAccelerations, LaterPositionsAndVelocitiesKeepQddot) {
  const JointValue qddot[] = {{"j1", 0.8}, {"j2", -0.6}};
  ASSERT_TRUE(g.SetJoints({}, {}, qddot));
  ExpectByHand(0, 0, 0.8, 0, 0, -0.6);  // the initial state
  const JointValue qdot[] = {{"j1", 1.5}, {"j2", -0.3}};
  ASSERT_TRUE(g.SetJoints({}, qdot));  // qdot without qddot: qddot kept, the twist beside it new
  ExpectByHand(0, 1.5, 0.8, 0, -0.3, -0.6);
  const JointValue q[] = {{"j1", -1.1}, {"j2", 0.4}};
  ASSERT_TRUE(g.SetJoints(q, {}));
  ExpectByHand(-1.1, 1.5, 0.8, 0.4, -0.3, -0.6);
  // The real-time setters keep it too, and set it.
  const JointGroup all = g.AllJoints();
  const double qd2[] = {-0.5, 0.9}, qdd2[] = {0.3, 1.2}, q3[] = {0.2, -0.1};
  ASSERT_EQ(g.SetJointVelocities(all, qd2), ErrorCode::kOk);
  ExpectByHand(-1.1, -0.5, 0.8, 0.4, 0.9, -0.6);
  ASSERT_EQ(g.SetJointAccelerations(all, qdd2), ErrorCode::kOk);
  ExpectByHand(-1.1, -0.5, 0.3, 0.4, 0.9, 1.2);
  const double qd3[] = {2.0, -1.0}, qdd3[] = {-0.7, 0.05};
  ASSERT_EQ(g.SetJointState(all, q3, qd3, qdd3), ErrorCode::kOk);
  ExpectByHand(0.2, 2.0, -0.7, -0.1, -1.0, 0.05);
}

TEST_F(JointAccelerations, MimicsFollowTheirMastersQddot) {
  JointSpec m = Joint("m", JointType::kContinuous, "l2", "", "f", "F");
  m.axis = {1, 0, 0};
  m.mimic = "j1";
  m.multiplier = 2;
  ASSERT_TRUE(g.AddJoint(m));
  const FrameIndex f = g.topology().FindFrame("f");
  EXPECT_FALSE(g.acceleration_value(f));  // its master has none
  const JointValue qddot[] = {{"j1", 0.8}};
  ASSERT_TRUE(g.SetJoints({}, {}, qddot));
  auto A = g.acceleration_value(f);
  ASSERT_TRUE(A);
  EXPECT_LE((A->angular - Vec(1.6, 0, 0)).norm(), 1e-15);
  EXPECT_EQ(A->linear, Vec::Zero());
  // A mimic added after its master's qddot follows it at once.
  JointSpec m2 = Joint("m2", JointType::kPrismatic, "f", "", "k", "K");
  m2.axis = {0, 1, 0};
  m2.mimic = "j1";
  m2.multiplier = -0.5;
  ASSERT_TRUE(g.AddJoint(m2));
  auto A2 = g.acceleration_value(g.topology().FindFrame("k"));
  ASSERT_TRUE(A2);
  EXPECT_LE((A2->linear - Vec(0, -0.4, 0)).norm(), 1e-15);
  EXPECT_EQ(Qddot("m2"), -0.4);
  const std::string before = Dump(g);
  const JointValue direct[] = {{"m", 1.0}};
  auto r = g.SetJoints({}, {}, direct);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kMimicJoint);
  EXPECT_EQ(Dump(g), before);
  EXPECT_EQ(CheckInvariants(g), "");
}

TEST_F(JointAccelerations, RemovalForgetsIt) {
  const JointValue qddot[] = {{"j1", 0.8}, {"j2", -0.6}};
  ASSERT_TRUE(g.SetJoints({}, {}, qddot));
  ASSERT_TRUE(g.RemovePose("t", "l2"));  // the fixed joint, then j2 (its edge slot is reused)
  ASSERT_TRUE(g.RemovePose("l2", "l1"));
  JointSpec j2 = Joint("j2", JointType::kPrismatic, "l1", "", "l2", "L2");
  j2.p_origin = {0.5, 0.0, 0.0};
  j2.axis = {1, 1, 0};
  ASSERT_TRUE(g.AddJoint(j2));
  ExpectNoAcceleration("l2");  // a new joint: its qddot was never given
  EXPECT_EQ(CheckInvariants(g), "");
}

TEST_F(JointAccelerations, RejectionsByNameLeaveTheGraphUnchanged) {
  const JointValue q[] = {{"j1", 0.7}, {"j2", 0.25}};
  const JointValue qddot[] = {{"j1", 0.8}};
  ASSERT_TRUE(g.SetJoints(q, {}, qddot));
  const std::string before = Dump(g);
  const auto expect = [&](const BuildResult& r, ErrorCode code, std::string_view words) {
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, code) << r.error().message;
    EXPECT_NE(r.error().message.find(words), std::string::npos) << r.error().message;
    EXPECT_EQ(Dump(g), before);
  };
  const JointValue nan[] = {{"j2", 1.0}, {"j1", kNaN}};
  expect(g.SetJoints({}, {}, nan), ErrorCode::kInvalidNumber, "acceleration of joint j1");
  const JointValue inf[] = {{"j2", std::numeric_limits<double>::infinity()}};
  expect(g.SetJoints({}, {}, inf), ErrorCode::kInvalidNumber, "acceleration of joint j2");
  const JointValue unknown[] = {{"j1", 1.0}, {"nope", 1.0}};
  expect(g.SetJoints({}, {}, unknown), ErrorCode::kUnknownJoint, "nope");
  const JointValue fixed[] = {{"fx", 1.0}};
  expect(g.SetJoints({}, {}, fixed), ErrorCode::kUnknownJoint, "fixed");
  // invalid_number comes first, whichever list holds it.
  const JointValue unknown_q[] = {{"nope", 0.0}};
  expect(g.SetJoints(unknown_q, {}, nan), ErrorCode::kInvalidNumber, "acceleration of joint j1");
  // A position over its limit refuses the accelerations of the same set too.
  const JointValue over[] = {{"j2", 2.5}};
  const JointValue fine[] = {{"j1", -3.0}, {"j2", 4.0}};  // accelerations are not limited
  expect(g.SetJoints(over, {}, fine), ErrorCode::kJointLimit, "j2");
  // A stamp on timeless joints: refused, and the joints stay timeless.
  expect(g.SetJoints({}, {}, fine, Stamp::Nanoseconds(1)), ErrorCode::kStampMismatch, "timeless");
  ASSERT_TRUE(g.SetJoints({}, {}, fine));
  EXPECT_EQ(Qddot("j2"), 4.0);
}

TEST_F(JointAccelerations, RejectionsByGroupLeaveTheGraphUnchanged) {
  const JointGroup all = g.AllJoints();
  const double qddot[] = {0.8, -0.6};
  ASSERT_EQ(g.SetJointAccelerations(all, qddot), ErrorCode::kOk);
  const std::string before = Dump(g);
  const double nan[] = {0.1, kNaN}, q[] = {0.1, 0.2}, q_over[] = {0.1, 2.5}, qdot[] = {1, 2};
  UpdateError why;
  EXPECT_EQ(g.SetJointAccelerations(all, nan, &why), ErrorCode::kInvalidNumber);
  EXPECT_EQ(why.joint, 1u);
  EXPECT_EQ(why.value.role, coord::ValueRole::kJointAcceleration);
  EXPECT_NE(Describe(why).find("acceleration of joint 1 of the group"), std::string::npos)
      << Describe(why);
  EXPECT_EQ(Dump(g), before);
  why = UpdateError{};
  EXPECT_EQ(g.SetJointState(all, q, qdot, nan, &why), ErrorCode::kInvalidNumber);
  EXPECT_EQ(why.value.role, coord::ValueRole::kJointAcceleration);
  EXPECT_EQ(Dump(g), before);
  EXPECT_EQ(g.SetJointState(all, q_over, qdot, qddot), ErrorCode::kJointLimit);
  EXPECT_EQ(Dump(g), before);
  ASSERT_TRUE(g.RemovePose("t", "l2"));
  ASSERT_TRUE(g.RemovePose("l2", "l1"));  // j2 gone: the group is stale
  const std::string after_removal = Dump(g);
  EXPECT_EQ(g.SetJointAccelerations(all, qddot), ErrorCode::kUnknownJoint);
  EXPECT_EQ(Dump(g), after_removal);
}

// Stamped joints take qddot with a stamp only (the stamped samples' values: joint_time_test).
TEST(JointAccelerationsStamped, StampedJointsTakeQddotWithAStampOnly) {
  Graph g;
  JointSpec s;
  s.name = "j";
  s.type = JointType::kContinuous;
  s.parent = "b";
  s.parent_body = "B";
  s.child = "c";
  s.child_body = "C";
  s.axis = {0, 0, 1};
  ASSERT_TRUE(g.AddJoint(s));
  const JointValue q[] = {{"j", 0.5}}, qddot[] = {{"j", 1.0}};
  ASSERT_TRUE(g.SetJoints(q, {}, Stamp::Nanoseconds(10)));  // its edges are stamped now
  const std::string before = Dump(g);
  auto r = g.SetJoints({}, {}, qddot);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kStampMismatch);
  const double one[] = {1.0};
  EXPECT_EQ(g.SetJointAccelerations(g.AllJoints(), one), ErrorCode::kStampMismatch);
  EXPECT_EQ(Dump(g), before);
  auto A = g.GetAcceleration(TwistSpec::Of("c").RelativeTo("B").ExpressedIn("b"));
  ASSERT_FALSE(A);
  EXPECT_EQ(A.error().code, ErrorCode::kNoAcceleration);
  ASSERT_TRUE(g.SetJoints({}, {}, qddot, Stamp::Nanoseconds(20)));
  auto alpha = g.GetAngularAcceleration(TwistSpec::Of("", "C").RelativeTo("B").ExpressedIn("b"),
                                        At{Stamp::Nanoseconds(20)});
  ASSERT_TRUE(alpha);
  EXPECT_EQ(alpha->value.value, Vec(0, 0, 1));
  // The sample at 10 ns has none: no implicit zero between the two.
  auto between = g.GetAcceleration(TwistSpec::Of("c").RelativeTo("B").ExpressedIn("b"),
                                   At{Stamp::Nanoseconds(15)});
  ASSERT_FALSE(between);
  EXPECT_EQ(between.error().code, ErrorCode::kNoAcceleration);
}

TEST_F(JointAccelerations, CompiledQueriesSeeQddotWhenItIsGiven) {
  auto compiled = g.CompileAcceleration(spec);
  ASSERT_TRUE(compiled);
  Vec a, alpha;
  EXPECT_EQ(compiled->Evaluate(a, alpha), ErrorCode::kNoAcceleration);
  const JointGroup all = g.AllJoints();
  const double q[] = {0.7, 0.25}, qdot[] = {1.5, -0.3}, qddot[] = {0.8, -0.6};
  ASSERT_EQ(g.SetJointState(all, q, qdot, qddot), ErrorCode::kOk);
  ASSERT_EQ(compiled->Evaluate(a, alpha), ErrorCode::kOk);
  Vec a_hand, alpha_hand;
  ByHand(0.7, 1.5, 0.8, 0.25, -0.3, -0.6, a_hand, alpha_hand);
  EXPECT_LE((a - a_hand).norm(), 1e-13);
  EXPECT_LE((alpha - alpha_hand).norm(), 1e-13);
}

}  // namespace
}  // namespace semgraph::core
