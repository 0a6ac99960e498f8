// Tests of core/src/joints.cc: joint edges take X_origin M(q) and the twist of qdot (checked
// against poses and twists built by hand with Eigen), limits, mimic joints, joint_edge
// protection, removal, every rejection with the graph unchanged (Dump), and the rules P1-P4,
// W1-W4 applied to joint edges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"

namespace semgraph::core {
namespace {

using Graph = SceneGraph<>;

Eigen::Quaterniond Rpy(double r, double p, double y) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()));
}

JointSpec Joint(std::string_view name, JointType type, std::string_view parent,
                std::string_view parent_body, std::string_view child, std::string_view child_body) {
  JointSpec s;
  s.name = name;
  s.type = type;
  s.parent = parent;
  s.parent_body = parent_body;
  s.child = child;
  s.child_body = child_body;
  if (type == JointType::kRevolute || type == JointType::kPrismatic) {
    s.lower = -2;
    s.upper = 2;
  }
  return s;
}

Eigen::Isometry3d PoseOf(const Graph& g, std::string_view of, std::string_view wrt) {
  auto X = g.GetPose(PoseSpec::Of(of).RelativeTo(wrt));
  EXPECT_TRUE(X.has_value()) << of << " wrt " << wrt;
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  if (!X) return out;
  out.linear() = X->value.rotation.toRotationMatrix();
  out.translation() = X->value.translation;
  return out;
}

void ExpectNear(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double tol = 1e-12) {
  EXPECT_LE((a.matrix() - b.matrix()).cwiseAbs().maxCoeff(), tol) << a.matrix() << "\nvs\n"
                                                                  << b.matrix();
}

// A two-link arm: base B -{j1 revolute about z}-> L1 -{j2 prismatic along x}-> L2.
class ArmTest : public ::testing::Test {
 protected:
  void SetUp() override {
    JointSpec j1 = Joint("j1", JointType::kRevolute, "b", "B", "l1", "L1");
    j1.q_origin = Rpy(0.1, -0.2, 0.3);
    j1.p_origin = {0.0, 0.0, 0.4};
    j1.axis = {0, 0, 2};  // normalized to z
    ASSERT_TRUE(g.AddJoint(j1)) << g.AddJoint(j1).error().message;
    JointSpec j2 = Joint("j2", JointType::kPrismatic, "l1", "", "l2", "L2");
    j2.p_origin = {0.5, 0.0, 0.0};
    j2.axis = {1, 1, 0};
    j2.lower = -0.1;
    j2.upper = 0.3;
    ASSERT_TRUE(g.AddJoint(j2));
  }
  Eigen::Isometry3d X1(double q) const {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() =
        (Rpy(0.1, -0.2, 0.3) * Eigen::AngleAxisd(q, Eigen::Vector3d::UnitZ())).toRotationMatrix();
    X.translation() = Eigen::Vector3d(0, 0, 0.4);
    return X;
  }
  Eigen::Isometry3d X2(double q) const {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() = Eigen::Vector3d(0.5, 0, 0) + q * Eigen::Vector3d(1, 1, 0).normalized();
    return X;
  }
  Graph g;
};

TEST_F(ArmTest, PosesFollowTheJointPositions) {
  EXPECT_EQ(g.num_joints(), 2u);
  ExpectNear(PoseOf(g, "l2", "b"), X1(0) * X2(0));
  const JointValue q[] = {{"j1", 0.7}, {"j2", 0.25}};
  ASSERT_TRUE(g.SetJoints(q, {}));
  ExpectNear(PoseOf(g, "l1", "b"), X1(0.7));
  ExpectNear(PoseOf(g, "l2", "b"), X1(0.7) * X2(0.25));
  ExpectNear(PoseOf(g, "b", "l2"), (X1(0.7) * X2(0.25)).inverse());
}

TEST_F(ArmTest, TwistsFollowTheJointVelocities) {
  const JointValue q[] = {{"j1", -0.4}, {"j2", 0.1}};
  const JointValue qdot[] = {{"j1", 1.5}, {"j2", -0.3}};
  ASSERT_TRUE(g.SetJoints(q, qdot));
  // The edges: (0, z 1.5) at l1 in [l1]; (u (-0.3), 0) at l2 in [l2].
  auto V1 = g.GetTwist(TwistSpec::Of("l1").RelativeTo("B").ExpressedIn("l1"));
  ASSERT_TRUE(V1);
  EXPECT_LE((V1->angular - Eigen::Vector3d(0, 0, 1.5)).norm(), 1e-15);
  EXPECT_LE(V1->linear.norm(), 1e-15);
  auto V2 = g.GetTwist(TwistSpec::Of("l2").RelativeTo("L1").ExpressedIn("l2"));
  ASSERT_TRUE(V2);
  EXPECT_LE((V2->linear - (-0.3) * Eigen::Vector3d(1, 1, 0).normalized()).norm(), 1e-15);
  EXPECT_LE(V2->angular.norm(), 1e-15);
  // Composite, at l2 in [b], by hand: w = R_b1 z 1.5; v = w x (p_l2 - p_l1) + R_b2 u qdot2.
  const Eigen::Isometry3d Xb1 = X1(-0.4), Xb2 = X1(-0.4) * X2(0.1);
  const Eigen::Vector3d w = Xb1.linear() * Eigen::Vector3d(0, 0, 1.5);
  const Eigen::Vector3d v = w.cross(Xb2.translation() - Xb1.translation()) +
                            Xb2.linear() * (-0.3 * Eigen::Vector3d(1, 1, 0).normalized());
  auto V = g.GetTwist(TwistSpec::Of("l2").RelativeTo("B").ExpressedIn("b"));
  ASSERT_TRUE(V);
  EXPECT_LE((V->angular - w).norm(), 1e-14);
  EXPECT_LE((V->linear - v).norm(), 1e-14);
}

TEST_F(ArmTest, InitialStateIsZeroClampedIntoTheLimits) {
  JointSpec j3 = Joint("j3", JointType::kPrismatic, "l2", "", "l3", "L3");
  j3.lower = 0.2;
  j3.upper = 0.5;
  ASSERT_TRUE(g.AddJoint(j3));
  EXPECT_EQ(g.joint_position(*g.FindJoint("j3")), 0.2);
  EXPECT_EQ(g.joint_velocity(*g.FindJoint("j3")), 0.0);
  ExpectNear(PoseOf(g, "l3", "l2"), Eigen::Isometry3d(Eigen::Translation3d(0.2, 0, 0)));
}

TEST_F(ArmTest, LimitsAreCheckedWithASlackOf1e9AndValuesStoredAsGiven) {
  const std::string before = Dump(g);
  const JointValue over[] = {{"j1", 0.5}, {"j2", 0.3 + 2e-9}};
  auto r = g.SetJoints(over, {});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kJointLimit);
  EXPECT_NE(r.error().message.find("j2"), std::string::npos) << r.error().message;
  EXPECT_EQ(Dump(g), before);  // all or nothing: j1 unchanged too
  const JointValue within[] = {{"j2", 0.3 + 0.5e-9}};
  ASSERT_TRUE(g.SetJoints(within, {}));
  EXPECT_EQ(g.joint_position(*g.FindJoint("j2")), 0.3 + 0.5e-9);
}

TEST_F(ArmTest, ContinuousJointsAreUnlimited) {
  JointSpec j3 = Joint("j3", JointType::kContinuous, "l2", "", "l3", "L3");
  j3.lower = 5;  // ignored
  j3.upper = -5;
  ASSERT_TRUE(g.AddJoint(j3));
  const JointValue q[] = {{"j3", 100.0}};
  ASSERT_TRUE(g.SetJoints(q, {}));
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(100.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  ExpectNear(PoseOf(g, "l3", "l2"), X, 1e-12);
}

TEST_F(ArmTest, StateSetErrorsInOrderWithTheGraphUnchanged) {
  JointSpec fixed = Joint("mount", JointType::kFixed, "l2", "", "tool", "Tool");
  ASSERT_TRUE(g.AddJoint(fixed));
  JointSpec mimic = Joint("m", JointType::kRevolute, "b", "", "l9", "L9");
  mimic.mimic = "j1";
  ASSERT_TRUE(g.AddJoint(mimic));
  const std::string before = Dump(g);
  const auto expect = [&](ErrorCode code, std::vector<JointValue> q, std::vector<JointValue> qdot) {
    auto r = g.SetJoints(q, qdot);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, code) << r.error().message;
    EXPECT_EQ(Dump(g), before);
  };
  const double nan = std::nan("");
  expect(ErrorCode::kInvalidNumber, {{"nope", 0.0}, {"j2", 9.0}}, {{"j1", nan}});
  expect(ErrorCode::kUnknownJoint, {{"m", 0.0}, {"j2", 9.0}, {"nope", 0.0}}, {});
  expect(ErrorCode::kUnknownJoint, {{"mount", 0.0}}, {});
  expect(ErrorCode::kMimicJoint, {{"j2", 9.0}}, {{"m", 1.0}});
  expect(ErrorCode::kJointLimit, {{"j1", 0.5}, {"j2", -0.2}}, {});
  // The real-time setters, same order.
  const JointGroup all = g.AllJoints();
  ASSERT_EQ(all.size(), 2u);
  const double q_bad[] = {0.0, 9.0}, q_nan[] = {nan, 0.0};
  EXPECT_EQ(g.SetJointPositions(all, q_bad), ErrorCode::kJointLimit);
  EXPECT_EQ(g.SetJointPositions(all, q_nan), ErrorCode::kInvalidNumber);
  EXPECT_EQ(Dump(g), before);
  const std::string_view mimic_names[] = {"m"};
  EXPECT_EQ(g.MakeJointGroup(mimic_names).error().code, ErrorCode::kMimicJoint);
  const std::string_view twice[] = {"j1", "j1"};
  EXPECT_EQ(g.MakeJointGroup(twice).error().code, ErrorCode::kDuplicateJoint);
  const std::string_view fixed_names[] = {"mount"};
  EXPECT_EQ(g.MakeJointGroup(fixed_names).error().code, ErrorCode::kUnknownJoint);
}

TEST_F(ArmTest, AJointStateKeepsTheFieldsItIsNotGiven) {
  const JointValue q[] = {{"j1", 0.3}};
  const JointValue qdot[] = {{"j1", 2.0}};
  ASSERT_TRUE(g.SetJoints(q, qdot));
  const JointValue q2[] = {{"j1", 0.6}};
  ASSERT_TRUE(g.SetJoints(q2, {}));
  EXPECT_EQ(g.joint_velocity(*g.FindJoint("j1")), 2.0);
  const JointGroup all = g.AllJoints();
  const double v[] = {-1.0, 0.5};
  ASSERT_EQ(g.SetJointVelocities(all, v), ErrorCode::kOk);
  EXPECT_EQ(g.joint_position(*g.FindJoint("j1")), 0.6);
  EXPECT_EQ(g.joint_velocity(*g.FindJoint("j2")), 0.5);
}

TEST_F(ArmTest, MimicJointsFollowTheirMasterAtAllTimes) {
  const JointValue q0[] = {{"j1", 0.5}};
  const JointValue qdot0[] = {{"j1", 0.25}};
  ASSERT_TRUE(g.SetJoints(q0, qdot0));
  JointSpec m = Joint("finger", JointType::kPrismatic, "l2", "", "f", "F");
  m.mimic = "j1";
  m.multiplier = -2;
  m.offset = 0.1;
  m.lower = 0;  // a mimic's own limits are not checked
  m.upper = 0;
  ASSERT_TRUE(g.AddJoint(m));
  const JointHandle f = *g.FindJoint("finger");
  EXPECT_DOUBLE_EQ(g.joint_position(f), -2 * 0.5 + 0.1);  // initially too
  EXPECT_DOUBLE_EQ(g.joint_velocity(f), -0.5);
  const JointGroup all = g.AllJoints();
  const double q[] = {1.25, 0.0}, qdot[] = {-1.0, 0.0};
  ASSERT_EQ(g.SetJointState(all, q, qdot), ErrorCode::kOk);
  EXPECT_DOUBLE_EQ(g.joint_position(f), -2.4);
  EXPECT_DOUBLE_EQ(g.joint_velocity(f), 2.0);
  ExpectNear(PoseOf(g, "f", "l2"), Eigen::Isometry3d(Eigen::Translation3d(-2.4, 0, 0)));
  auto V = g.GetTwist(TwistSpec::Of("f").RelativeTo("L2").ExpressedIn("f"));
  ASSERT_TRUE(V);
  EXPECT_LE((V->linear - Eigen::Vector3d(2, 0, 0)).norm(), 1e-15);
}

TEST_F(ArmTest, AddJointErrorsInTheSpecOrderLeaveTheGraphUnchanged) {
  JointSpec f = Joint("mount", JointType::kFixed, "l2", "", "tool", "Tool");
  ASSERT_TRUE(g.AddJoint(f));
  const std::string before = Dump(g);
  const auto expect = [&](ErrorCode code, const JointSpec& s) {
    auto r = g.AddJoint(s);
    ASSERT_FALSE(r) << s.name;
    EXPECT_EQ(r.error().code, code) << r.error().message;
    EXPECT_EQ(Dump(g), before) << r.error().message;
    EXPECT_EQ(CheckInvariants(g), "");
  };
  JointSpec s = Joint("j3", JointType::kRevolute, "l2", "", "l3", "L3");
  JointSpec bad = s;
  bad.name = "";
  expect(ErrorCode::kInvalidName, bad);
  bad = s;
  bad.child = "bad\nname";
  bad.p_origin.x() = std::nan("");  // names first
  expect(ErrorCode::kInvalidName, bad);
  bad = s;
  bad.p_origin.x() = std::nan("");
  bad.axis.setZero();
  expect(ErrorCode::kInvalidNumber, bad);
  bad = s;
  bad.q_origin = Eigen::Quaterniond(2, 0, 0, 0);
  expect(ErrorCode::kInvalidRotation, bad);
  bad = s;
  bad.upper = std::numeric_limits<double>::infinity();
  expect(ErrorCode::kInvalidNumber, bad);
  bad = s;
  bad.axis = {0, 1e-13, 0};
  bad.name = "j1";  // invalid_model before duplicate_joint
  expect(ErrorCode::kInvalidModel, bad);
  bad = s;
  bad.lower = 1;
  bad.upper = 0.5;
  expect(ErrorCode::kInvalidModel, bad);
  bad = s;
  bad.mimic = "nope";
  expect(ErrorCode::kInvalidModel, bad);
  bad.mimic = "mount";
  expect(ErrorCode::kInvalidModel, bad);
  bad = s;
  bad.name = "j1";
  expect(ErrorCode::kDuplicateJoint, bad);
  bad = s;
  bad.child_body = "L2";  // l3 is new, so this is fine... but P == C:
  expect(ErrorCode::kTwistSameBody, bad);
  bad = s;
  bad.child_body = "";
  expect(ErrorCode::kFrameWithoutBody, bad);
  bad = s;
  bad.parent_body = "B";
  expect(ErrorCode::kFrameBodyMismatch, bad);
  bad = s;
  bad.child = "l2";
  bad.child_body = "";
  expect(ErrorCode::kSelfEdge, bad);
  bad = s;  // the edge b -> l1 is j1's
  bad.parent = "b";
  bad.child = "l1";
  bad.child_body = "";
  expect(ErrorCode::kJointEdge, bad);
  bad = s;  // l1 has a pose parent
  bad.child = "l1";
  bad.child_body = "";
  bad.parent = "tool";
  expect(ErrorCode::kMultiplePoseParents, bad);
  bad = s;  // b is the root above l2
  bad.child = "b";
  bad.child_body = "";
  expect(ErrorCode::kPoseCycle, bad);
  // P3: a new tree with a frame of L2 on it, joined to l2's tree.
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("y", "L2").RelativeTo("x", "X"),
                        Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero()));
  const std::string before2 = Dump(g);
  bad = s;
  bad.child = "x";
  bad.child_body = "";
  auto r = g.AddJoint(bad);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kDuplicatePosePath) << r.error().message;
  EXPECT_EQ(Dump(g), before2);
}

TEST_F(ArmTest, TheJointsTwistEdgeIsCheckedAgainstW1AndW3) {
  // W1: the child frame already has a twist parent.
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("o", "O").RelativeTo("W").ExpressedIn("o"),
                         Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  std::string before = Dump(g);
  JointSpec s = Joint("j3", JointType::kRevolute, "l2", "", "o", "");
  auto r = g.AddJoint(s);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kMultipleTwistParents) << r.error().message;
  EXPECT_EQ(Dump(g), before);
  // W3: a twist edge L2 -> {y}|B in another tree; a joint L2 -> B' merging y's tree... Here:
  // an ordinary twist of body B wrt L2 at a new frame y of B (tree {y}); then a joint from l2
  // (body L2) to a frame z of B joined... bodies L2 and B are already joined in the TG of b's
  // tree by the joints; a joint from {l2}|L2 to a new frame of B would break P3 first. Use a
  // second tree instead: {u}|U with twist U ~> {v}|V, then joint {v}|V -> {w}|U? That is
  // W3 within the merged TG: U and V already joined.
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("v", "V").RelativeTo("u", "U"), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d::Zero()));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("v").RelativeTo("U").ExpressedIn("v"),
                         Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  ASSERT_TRUE(g.AddFrame("w", "U"));
  before = Dump(g);
  JointSpec w3 = Joint("jw", JointType::kRevolute, "w", "", "p", "V2");
  ASSERT_TRUE(g.AddJoint(w3));  // fine: V2 is new
  // Twist path U - V exists in the tree of u; a joint from a V frame in another tree to a U
  // frame: make {k}|V root tree and joint {k}|V -> {w2}|U with w2 a new frame: TG union has
  // U-V connected: duplicate_twist_path.
  ASSERT_TRUE(g.AddFrame("k", "V"));
  before = Dump(g);
  JointSpec dup = Joint("jd", JointType::kRevolute, "k", "", "u", "");
  r = g.AddJoint(dup);  // would link tree(k) (no TG) and tree(u) (TG: U-V, U-V2): U-V again
  ASSERT_FALSE(r);
  // P3 comes first here (V would have frames in both trees), as for a pose add.
  EXPECT_EQ(r.error().code, ErrorCode::kDuplicatePosePath) << r.error().message;
  EXPECT_EQ(Dump(g), before);
  // A pure W3 case: body D with a twist edge D ~> {h}|H in H's tree, and a joint from a frame
  // of D... P3 forbids D having frames in both. A joint {d}|D (new tree) -> {h0}|H where TG of
  // h0's tree already joins D and H through a twist edge whose tail D has no frame there.
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("h", "H").RelativeTo("h0", "H0"),
                        Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero()));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("h").RelativeTo("D").ExpressedIn("h"),
                         Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("h2", "H").RelativeTo("h"), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d::Zero()));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("h2").RelativeTo("H0").ExpressedIn("h2"),
                         Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  before = Dump(g);
  JointSpec w3b =
      Joint("jh", JointType::kRevolute, "d", "D", "h0", "");  // D - H0: D-H-H0 already joined
  r = g.AddJoint(w3b);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kDuplicateTwistPath) << r.error().message;
  EXPECT_EQ(Dump(g), before);
  EXPECT_EQ(CheckInvariants(g), "");
}

TEST_F(ArmTest, JointEdgesAreDrivenByTheStateOnly) {
  const std::string before = Dump(g);
  const auto expect = [&](const BuildResult& r) {
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, ErrorCode::kJointEdge) << r.error().message;
    EXPECT_NE(r.error().message.find("j1"), std::string::npos) << r.error().message;
    EXPECT_EQ(Dump(g), before);
  };
  // A restatement of the very value is refused too.
  auto X = g.GetPose(PoseSpec::Of("l1").RelativeTo("b"));
  expect(g.AddPose(PoseSpec::Of("l1").RelativeTo("b"), X->value.rotation, X->value.translation));
  // Another form that converts to the joint's edge.
  expect(g.AddPose(PoseSpec::Of("l1").RelativeTo("b").ExpressedIn("l1"),
                   Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero()));
  expect(g.AddTwist(TwistSpec::Of("l1").RelativeTo("B").ExpressedIn("l1"), Eigen::Vector3d::Zero(),
                    Eigen::Vector3d::Zero()));
  expect(g.RemoveTwist("l1", "B"));
  EXPECT_EQ(g.FindPoseEdge("l1", "b").error().code, ErrorCode::kJointEdge);
  EXPECT_EQ(g.FindTwistEdge("l1", "B").error().code, ErrorCode::kJointEdge);
  // Adds that would create another edge are judged by the rules as usual.
  auto r = g.AddPose(PoseSpec::Of("l1").RelativeTo("w", "W"), Eigen::Quaterniond::Identity(),
                     Eigen::Vector3d::Zero());
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kMultiplePoseParents);
  r = g.AddTwist(TwistSpec::Of("l1").RelativeTo("W").ExpressedIn("l1"), Eigen::Vector3d::Zero(),
                 Eigen::Vector3d::Zero());
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kMultipleTwistParents);
  EXPECT_EQ(Dump(g), before);
  // Removing a wrong edge is no_such_edge first.
  EXPECT_EQ(g.RemovePose("l1", "l2").error().code, ErrorCode::kNoSuchEdge);
}

TEST_F(ArmTest, RemovingTheJointsPoseEdgeRemovesTheJoint) {
  const JointValue q[] = {{"j1", 0.3}};
  ASSERT_TRUE(g.SetJoints(q, {}));
  const JointHandle j1 = *g.FindJoint("j1");
  const JointGroup all = g.AllJoints();
  auto compiled = g.CompilePose(PoseSpec::Of("l2").RelativeTo("b"));
  ASSERT_TRUE(compiled);
  ASSERT_TRUE(g.RemovePose("l1", "b"));
  EXPECT_EQ(g.num_joints(), 1u);
  EXPECT_EQ(g.FindJoint("j1").error().code, ErrorCode::kUnknownJoint);
  EXPECT_FALSE(g.twist_parent(g.FindFrame("l1")).is_valid());
  EXPECT_FALSE(g.pose_parent(g.FindFrame("l1")).is_valid());
  EXPECT_TRUE(std::isnan(g.joint_position(j1)));
  const double v[] = {0.0, 0.0};
  EXPECT_EQ(g.SetJointPositions(all, v), ErrorCode::kUnknownJoint);
  coord::QuaternionBackend::PoseCoords X;
  EXPECT_EQ(compiled->Evaluate(X), ErrorCode::kQueryInvalidated);
  EXPECT_EQ(CheckInvariants(g), "");
  // Its frames can now be related by ordinary edges, and its name is free again.
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("l1").RelativeTo("b"), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d(1, 2, 3)));
  ASSERT_TRUE(g.RemovePose("l1", "b"));
  JointSpec again = Joint("j1", JointType::kContinuous, "b", "", "l1", "");
  ASSERT_TRUE(g.AddJoint(again));
  EXPECT_EQ(g.num_joints(), 2u);
  EXPECT_NE(*g.FindJoint("j1"), j1);  // a new generation: old handles stay refused
}

TEST_F(ArmTest, AMasterWithMimicsCannotBeRemoved) {
  JointSpec m = Joint("m", JointType::kRevolute, "l2", "", "f", "F");
  m.mimic = "j2";
  ASSERT_TRUE(g.AddJoint(m));
  const std::string before = Dump(g);
  auto r = g.RemovePose("l2", "l1");
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kJointEdge);
  EXPECT_EQ(Dump(g), before);
  ASSERT_TRUE(g.RemovePose("f", "l2"));  // the mimic first
  ASSERT_TRUE(g.RemovePose("l2", "l1"));
  EXPECT_EQ(g.num_joints(), 1u);
}

// J qdot + (the non-joint twists on the path) = the twist query, in every direction and for any
// point and frame; columns in path order from the reference body; mimic merged.
TEST_F(ArmTest, JacobiansTimesVelocitiesAreTwistsInEveryDirection) {
  JointSpec m = Joint("m", JointType::kRevolute, "l2", "", "f", "F");
  m.mimic = "j1";
  m.multiplier = 0.5;
  m.axis = {0, 1, 0};
  m.p_origin = {0.2, 0, 0.1};
  ASSERT_TRUE(g.AddJoint(m));
  // A non-joint twist edge: the world W -> {b}|B (a moving base), and a camera frame on L1.
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("b").RelativeTo("w", "W"), Rpy(0.2, 0.1, -0.3),
                        Eigen::Vector3d(1, 2, 3)));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("b").RelativeTo("W").ExpressedIn("b"),
                         Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(-0.05, 0.02, 0.04)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("cam", "L1").RelativeTo("l1"), Rpy(1, 0, 0),
                        Eigen::Vector3d(0, 0.3, 0)));
  const JointValue q[] = {{"j1", 0.4}, {"j2", 0.2}};
  const JointValue qdot[] = {{"j1", 0.7}, {"j2", -0.3}};
  ASSERT_TRUE(g.SetJoints(q, qdot));
  const auto expect = [&](const TwistSpec& spec, std::vector<std::string> columns,
                          bool base_twist) {
    auto J = g.GetJacobian(spec);
    auto V = g.GetTwist(spec);
    ASSERT_TRUE(J && V);
    std::vector<std::string> names;
    Eigen::VectorXd qd(static_cast<Eigen::Index>(J->joints.size()));
    for (std::size_t c = 0; c < J->joints.size(); ++c) {
      names.emplace_back(g.joint_name(J->joints[c]));
      qd(static_cast<Eigen::Index>(c)) = g.joint_velocity(J->joints[c]);
    }
    EXPECT_EQ(names, columns);
    Eigen::Matrix<double, 6, 1> Jq = J->J * qd;
    if (base_twist) {  // the non-joint edge W -> {b}, as a twist query of B wrt W at the same
                       // point/frame
      TwistSpec only_base = spec;
      const bool forward = spec.ref_body == "W";
      only_base.body = forward ? "B" : "W";
      only_base.ref_body = forward ? "W" : "B";
      auto Vb = g.GetTwist(only_base);
      ASSERT_TRUE(Vb);
      // The twist of C wrt D = (C wrt B) + (B wrt W) when D = W; the other way round when C = W.
      Jq.head<3>() += Vb->linear;
      Jq.tail<3>() += Vb->angular;
    }
    EXPECT_LE((Jq.head<3>() - V->linear).norm(), 1e-12) << spec.point << " wrt " << spec.ref_body;
    EXPECT_LE((Jq.tail<3>() - V->angular).norm(), 1e-12) << spec.point << " wrt " << spec.ref_body;
    auto C = g.CompileJacobian(spec);
    ASSERT_TRUE(C);
    JacobianMatrix Jc(6, static_cast<Eigen::Index>(C->num_columns()));
    ASSERT_EQ(C->Evaluate(Jc), ErrorCode::kOk);
    EXPECT_LE((Jc - J->J).cwiseAbs().maxCoeff(), 1e-14);
  };
  expect(TwistSpec::Of("f").RelativeTo("B").ExpressedIn("b"), {"j1", "j2"}, false);
  expect(TwistSpec::Of("f").RelativeTo("B").ExpressedIn("cam"), {"j1", "j2"}, false);
  expect(TwistSpec::Of("cam", "F").RelativeTo("B").ExpressedIn("f"), {"j1", "j2"}, false);
  // Reversed: the base relative to the finger; columns from F's side: m (as j1) first, then j2.
  expect(TwistSpec::Of("b").RelativeTo("F").ExpressedIn("l2"), {"j1", "j2"}, false);
  expect(TwistSpec::Of("l1").RelativeTo("L2").ExpressedIn("w"), {"j2"}, false);
  // Through the non-joint edge.
  expect(TwistSpec::Of("f").RelativeTo("W").ExpressedIn("w"), {"j1", "j2"}, true);
  // No joints on the path: zero columns.
  auto none = g.GetJacobian(TwistSpec::Of("l2").RelativeTo("L2").ExpressedIn("b"));
  ASSERT_TRUE(none);
  EXPECT_EQ(none->J.cols(), 0);
  // The errors of a twist query.
  EXPECT_EQ(g.GetJacobian(TwistSpec::Of("nope").RelativeTo("B").ExpressedIn("b")).error().code,
            ErrorCode::kUnknownFrame);
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("x", "X").RelativeTo("y", "Y"), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d::Zero()));
  EXPECT_EQ(g.GetJacobian(TwistSpec::Of("x").RelativeTo("B").ExpressedIn("x")).error().code,
            ErrorCode::kNoTwistPath);
}

// Repair (repair.cc) may re-root a pose tree by reversing edges; never through a joint's edge.
TEST_F(ArmTest, RepairDoesNotRerootThroughAJoint) {
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("x", "X").RelativeTo("l2"), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d(0, 0, 1)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("y", "Y"), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d::Zero()));
  const std::string before = Dump(g);
  // z has a pose parent; the inverse (x wrt z) too, and re-rooting x's tree would reverse j2, j1.
  auto r = g.AddPose(PoseSpec::Of("z").RelativeTo("x"), Eigen::Quaterniond::Identity(),
                     Eigen::Vector3d::Zero(), RepairPolicy{});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kMultiplePoseParents);
  EXPECT_EQ(Dump(g), before);
  EXPECT_EQ(CheckInvariants(g), "");
}

TEST(Joints, SinCosAgreesWithLibm) {
  double worst = 0;
  for (int i = -200000; i <= 200000; ++i) {
    const double x = i * 5.00123e-4;  // [-100, 100], not aligned with multiples of pi/2
    double s, c;
    internal::SinCos(x, s, c);
    worst = std::max({worst, std::abs(s - std::sin(x)), std::abs(c - std::cos(x))});
  }
  for (double x : {0.0, -0.0, M_PI / 4, M_PI / 2, M_PI, 1e-300, 5e4 + 0.3, 1e5, 2e5, 1e12}) {
    double s, c;
    internal::SinCos(x, s, c);
    worst = std::max({worst, std::abs(s - std::sin(x)), std::abs(c - std::cos(x))});
  }
  EXPECT_LE(worst, 4e-16);
}

TEST(Joints, HomogeneousBackendStoresTheSameValues) {
  SceneGraph<coord::HomogeneousBackend> h;
  Graph q;
  for (auto* add : {+[](SceneGraph<coord::HomogeneousBackend>& g) {
         JointSpec s = Joint("j", JointType::kRevolute, "a", "A", "b", "B");
         s.axis = {0.3, -0.2, 0.9};
         s.q_origin = Rpy(0.3, 0.2, 0.1);
         s.p_origin = {1, 2, 3};
         return bool(g.AddJoint(s));
       }}) {
    ASSERT_TRUE(add(h));
  }
  JointSpec s = Joint("j", JointType::kRevolute, "a", "A", "b", "B");
  s.axis = {0.3, -0.2, 0.9};
  s.q_origin = Rpy(0.3, 0.2, 0.1);
  s.p_origin = {1, 2, 3};
  ASSERT_TRUE(q.AddJoint(s));
  const JointValue v[] = {{"j", 1.1}};
  ASSERT_TRUE(h.SetJoints(v, {}));
  ASSERT_TRUE(q.SetJoints(v, {}));
  auto Xh = h.GetPose(PoseSpec::Of("b").RelativeTo("a"));
  auto Xq = q.GetPose(PoseSpec::Of("b").RelativeTo("a"));
  ASSERT_TRUE(Xh && Xq);
  EXPECT_LE((Xh->value.matrix() -
             (Eigen::Translation3d(Xq->value.translation) * Xq->value.rotation).matrix())
                .cwiseAbs()
                .maxCoeff(),
            1e-12);
}

}  // namespace
}  // namespace semgraph::core
