// Tests of models/src/urdf.cc: the URDF mapping (links, joints, fixed, floating, mimic),
// poses checked by hand on the mobile manipulator, prefixes for two robots of one model, a
// robot in a world with a camera and an object, grasping by removal and re-add, and every
// rejection (invalid_model with the parser's message, duplicate_joint / _body / _frame in that
// order) with the graph unchanged.
#include "semgraph/models/urdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "semgraph/core/scene_graph_debug.h"

namespace semgraph::models {
namespace {

using core::ErrorCode;
using core::JointValue;
using core::PoseSpec;
using core::TwistSpec;
using Graph = core::SceneGraph<>;

// The robot models ship in models/urdf; the broken ones are test data.
std::string Model(const std::string& file) {
  const bool robot =
      file == "arm6.urdf" || file == "arm7.urdf" || file == "mobile_manipulator.urdf";
  return std::string(robot ? SEMGRAPH_ROBOT_MODELS : SEMGRAPH_TEST_MODELS) + "/" + file;
}

Eigen::Vector3d Position(const Graph& g, std::string_view of, std::string_view wrt) {
  auto p = g.GetPosition(PoseSpec::Of(of).RelativeTo(wrt));
  EXPECT_TRUE(p.has_value()) << of << " wrt " << wrt;
  return p ? p->value : Eigen::Vector3d::Constant(std::nan(""));
}

TEST(Urdf, LinksBecomeBodiesWithOneFrameAndJointsJoinTheLinkFrames) {
  Graph g;
  auto robot = LoadUrdfFile(g, Model("arm7.urdf"));
  ASSERT_TRUE(robot) << robot.error().message;
  EXPECT_EQ(robot->name, "arm7");
  EXPECT_EQ(robot->root, "link0");
  EXPECT_EQ(g.num_bodies(), 9u);
  EXPECT_EQ(g.num_frames(), 9u);
  EXPECT_EQ(g.num_pose_edges(), 8u);
  EXPECT_EQ(g.num_twist_edges(), 8u);
  EXPECT_EQ(g.num_joints(), 8u);
  const std::vector<std::string> joints = {"joint1", "joint2", "joint3", "joint4",
                                           "joint5", "joint6", "joint7"};
  EXPECT_EQ(robot->joints, joints);
  EXPECT_EQ(robot->fixed_joints, std::vector<std::string>{"flange_joint"});
  EXPECT_EQ(robot->group.size(), 7u);
  for (const std::string& l : robot->links) {
    EXPECT_EQ(g.body_name(g.body_of(g.FindFrame(l))), l);
    EXPECT_EQ(g.tree_root(g.FindFrame(l)), g.FindFrame("link0"));
  }
  // Initial state: 0 clamped into the limits (joint4's range is [-3.0718, -0.0698]).
  EXPECT_EQ(g.joint_position(*g.FindJoint("joint4")), -0.0698);
  EXPECT_EQ(g.joint_position(*g.FindJoint("joint1")), 0.0);
  EXPECT_EQ(CheckInvariants(g), "");
}

TEST(Urdf, MobileManipulatorPosesByHand) {
  Graph g;
  auto robot = LoadUrdfFile(g, "file://" + Model("mobile_manipulator.urdf"));
  ASSERT_TRUE(robot) << robot.error().message;
  EXPECT_EQ(robot->root, "base_footprint");
  // Independent movable joints, depth-first, siblings by name; the mimic apart.
  const std::vector<std::string> joints = {"left_wheel_joint",  "lift_joint",       "arm_joint1",
                                           "arm_joint2",        "arm_joint3",       "arm_joint4",
                                           "left_finger_joint", "right_wheel_joint"};
  EXPECT_EQ(robot->joints, joints);
  EXPECT_EQ(robot->mimic_joints, std::vector<std::string>{"right_finger_joint"});
  EXPECT_EQ(robot->fixed_joints.size(), 6u);
  // q = 0: x offsets 0.05 + 0.1 + 0.35 + 0.3 + 0.08 + 0.12 = 1.0; z 0.1 + 0.3 + 0.05 + 0.1.
  EXPECT_LE((Position(g, "tcp", "base_footprint") - Eigen::Vector3d(1.0, 0, 0.55)).norm(), 1e-12);
  // Lift up 0.2 m, shoulder pitched +90 degrees about y: the 0.85 m beyond it points down (-z).
  const JointValue q[] = {
      {"lift_joint", 0.2}, {"arm_joint2", M_PI / 2}, {"left_finger_joint", 0.03}};
  ASSERT_TRUE(g.SetJoints(q, {}));
  EXPECT_LE((Position(g, "tcp", "base_footprint") - Eigen::Vector3d(0.15, 0, -0.1)).norm(), 1e-12);
  // The right finger mimics the left one with multiplier -1: the fingers open symmetrically.
  EXPECT_EQ(g.joint_position(*g.FindJoint("right_finger_joint")), -0.03);
  EXPECT_LE((Position(g, "left_finger", "gripper_base") - Eigen::Vector3d(0.05, 0.04, 0)).norm(),
            1e-15);
  EXPECT_LE((Position(g, "right_finger", "gripper_base") - Eigen::Vector3d(0.05, -0.04, 0)).norm(),
            1e-15);
  const JointValue mimic[] = {{"right_finger_joint", 0.0}};
  EXPECT_EQ(g.SetJoints(mimic, {}).error().code, ErrorCode::kMimicJoint);
  // A wheel turns about its own z (the URDF axis, in the child frame).
  const JointValue wheel[] = {{"left_wheel_joint", 10.0}};
  const JointValue spin[] = {{"left_wheel_joint", 2.0}};
  ASSERT_TRUE(g.SetJoints(wheel, spin));
  auto w = g.GetAngularVelocity(
      TwistSpec::Of("left_wheel", "left_wheel").RelativeTo("base_link").ExpressedIn("base_link"));
  ASSERT_TRUE(w);
  // The wheel's z is the base's +y (rpy -pi/2 about x): z_wheel = R_x(-pi/2) z = (0, 1, 0)
  // (to the 12 digits of the file's pi/2).
  EXPECT_LE((w->value - Eigen::Vector3d(0, 2.0, 0)).norm(), 1e-10);
}

TEST(Urdf, FloatingJointsAreOrdinaryEdges) {
  Graph g;
  auto robot = LoadUrdfFile(g, Model("floating.urdf"));
  ASSERT_TRUE(robot) << robot.error().message;
  EXPECT_EQ(robot->floating_joints, std::vector<std::string>{"drone wrt world_anchor"});
  EXPECT_EQ(g.num_joints(), 1u);
  EXPECT_EQ(g.FindJoint("drone_free").error().code, ErrorCode::kUnknownJoint);
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("drone").RelativeTo("world_anchor"),
                        Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 2, 3)));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("drone").RelativeTo("world_anchor").ExpressedIn("drone"),
                         Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d::Zero()));
  EXPECT_LE((Position(g, "gimbal", "world_anchor") - Eigen::Vector3d(1.1, 2, 2.95)).norm(), 1e-15);
  auto handle = g.FindPoseEdge("drone", "world_anchor");
  EXPECT_TRUE(handle);
}

TEST(Urdf, TwoPrefixedRobotsOfOneModelLoadSideBySide) {
  Graph g;
  auto left = LoadUrdfFile(g, Model("arm6.urdf"), "left/");
  auto right = LoadUrdfFile(g, Model("arm6.urdf"), "right/");
  ASSERT_TRUE(left && right);
  EXPECT_EQ(left->root, "left/base_link");
  EXPECT_EQ(right->joints.front(), "right/shoulder_pan_joint");
  EXPECT_EQ(g.num_joints(), 14u);
  // Both on one table: two ordinary poses, then queries across the robots.
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("left/base_link").RelativeTo("table", "Table"),
                        Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0.5, 0)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("right/base_link").RelativeTo("table"),
                        Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, -0.5, 0)));
  const double q[] = {0.3, -1.0, 1.2, 0.4, 0.5, -0.6};
  ASSERT_EQ(g.SetJointPositions(left->group, q), ErrorCode::kOk);
  // Only the left robot moved: the right tool is where the right robot's zero pose puts it.
  const Eigen::Vector3d right_tool = Position(g, "right/tool0", "right/base_link");
  const Eigen::Vector3d left_tool = Position(g, "left/tool0", "left/base_link");
  EXPECT_GT((right_tool - left_tool).norm(), 1e-3);
  ASSERT_EQ(g.SetJointPositions(right->group, q), ErrorCode::kOk);
  EXPECT_LE((Position(g, "right/tool0", "right/base_link") - left_tool).norm(), 1e-12);
  // Across robots: the left tool relative to the right tool equals the offset of the bases.
  auto p = g.GetPosition(PoseSpec::Of("left/tool0").RelativeTo("right/tool0").ExpressedIn("table"));
  ASSERT_TRUE(p);
  EXPECT_LE((p->value - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);
}

TEST(Urdf, RobotWorldCameraAndObjectWithAGrasp) {
  Graph g;
  auto robot = LoadUrdfFile(g, Model("arm7.urdf"));
  ASSERT_TRUE(robot);
  // The base in the world, a camera on the base, an object seen by the camera.
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("link0").RelativeTo("world", "World"),
                        Eigen::Quaterniond::Identity(), Eigen::Vector3d(2, 1, 0.8)));
  const Eigen::Quaterniond q_cam(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("camera", "Camera").RelativeTo("link0"), q_cam,
                        Eigen::Vector3d(0.5, 0, 1.2)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("cup", "Cup").RelativeTo("camera"),
                        Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1, 0.0, 0.9)));
  // The cup in the base: camera at z 1.2 looking down (x flipped), 0.9 m in front: z 0.3.
  EXPECT_LE((Position(g, "cup", "link0") - Eigen::Vector3d(0.6, 0, 0.3)).norm(), 1e-12);
  EXPECT_LE((Position(g, "cup", "world") - Eigen::Vector3d(2.6, 1, 1.1)).norm(), 1e-12);
  // Move the arm; query the flange relative to the cup, by composing through the base.
  const double q[] = {0.1, 0.4, -0.2, -1.8, 0.3, 2.0, 0.5};
  ASSERT_EQ(g.SetJointPositions(robot->group, q), ErrorCode::kOk);
  auto flange_in_base = g.GetPose(PoseSpec::Of("flange").RelativeTo("link0"));
  auto cup_in_base = g.GetPose(PoseSpec::Of("cup").RelativeTo("link0"));
  auto flange_in_cup = g.GetPose(PoseSpec::Of("flange").RelativeTo("cup"));
  ASSERT_TRUE(flange_in_base && cup_in_base && flange_in_cup);
  const Eigen::Vector3d expected =
      cup_in_base->value.rotation.inverse() *
      (flange_in_base->value.translation - cup_in_base->value.translation);
  EXPECT_LE((flange_in_cup->value.translation - expected).norm(), 1e-12);
  // Grasp: remove the cup's pose wrt the camera, add it wrt the flange where it is now.
  const Eigen::Vector3d cup_world = Position(g, "cup", "world");
  auto cup_in_flange = g.GetPose(PoseSpec::Of("cup").RelativeTo("flange"));
  ASSERT_TRUE(cup_in_flange);
  ASSERT_TRUE(g.RemovePose("cup", "camera"));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("cup").RelativeTo("flange"), cup_in_flange->value.rotation,
                        cup_in_flange->value.translation));
  // Held: the cup does not move relative to the flange; the base does not move in the world.
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("cup").RelativeTo("flange").ExpressedIn("cup"),
                         Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("link0").RelativeTo("World").ExpressedIn("link0"),
                         Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  EXPECT_LE((Position(g, "cup", "world") - cup_world).norm(), 1e-12);
  // Now the cup moves with the arm.
  const double q2[] = {0.6, 0.4, -0.2, -1.8, 0.3, 2.0, 0.5};
  ASSERT_EQ(g.SetJointPositions(robot->group, q2), ErrorCode::kOk);
  EXPECT_GT((Position(g, "cup", "world") - cup_world).norm(), 1e-2);
  EXPECT_LE((Position(g, "cup", "flange") - cup_in_flange->value.translation).norm(), 1e-12);
  // The cup's velocity in the world follows from the joints: only joint1 turns, about the
  // base's z through the base origin: v = w x (p_cup - p_base).
  const double qdot[] = {0.5, 0, 0, 0, 0, 0, 0};
  ASSERT_EQ(g.SetJointVelocities(robot->group, qdot), ErrorCode::kOk);
  auto V = g.GetTwist(TwistSpec::Of("cup").RelativeTo("World").ExpressedIn("world"));
  ASSERT_TRUE(V);
  const Eigen::Vector3d w(0, 0, 0.5);
  EXPECT_LE((V->angular - w).norm(), 1e-12);
  EXPECT_LE((V->linear - w.cross(Position(g, "cup", "world") - Eigen::Vector3d(2, 1, 0.8))).norm(),
            1e-12);
  EXPECT_EQ(CheckInvariants(g), "");
}

void ExpectRejected(Graph& g, ErrorCode code, const std::string& file, std::string_view prefix,
                    const std::string& in_message) {
  const std::string before = Dump(g);
  auto r = LoadUrdfFile(g, file, prefix);
  ASSERT_FALSE(r) << file;
  EXPECT_EQ(r.error().code, code) << r.error().message;
  EXPECT_NE(r.error().message.find(in_message), std::string::npos) << r.error().message;
  EXPECT_EQ(Dump(g), before);
}

TEST(Urdf, BadModelsAreInvalidModelAndCreateNothing) {
  Graph g;
  ASSERT_TRUE(LoadUrdfFile(g, Model("arm6.urdf")));
  ExpectRejected(g, ErrorCode::kInvalidModel, Model("malformed.urdf"), "x_",
                 "urdfdom could not parse it: ");
  ExpectRejected(g, ErrorCode::kInvalidModel, Model("planar.urdf"), "x_",
                 "planar joints are not supported");
  ExpectRejected(g, ErrorCode::kInvalidModel, Model("zero_axis.urdf"), "x_",
                 "axis has no direction");
  ExpectRejected(g, ErrorCode::kInvalidModel, Model("bad_limits.urdf"), "x_",
                 "above the upper limit");
  ExpectRejected(g, ErrorCode::kInvalidModel, Model("bad_mimic.urdf"), "x_",
                 "mimics joint missing");
  ExpectRejected(g, ErrorCode::kInvalidModel, Model("no_such_file.urdf"), "x_",
                 "cannot read the file");
  ExpectRejected(g, ErrorCode::kInvalidModel, "package://arm/urdf/arm6.urdf", "x_", "package://");
  ExpectRejected(g, ErrorCode::kInvalidModel, Model("arm7.urdf"), "bad\nprefix/", "link name");
  // invalid_model comes before the name clashes (planar.urdf's names would not clash anyway).
  ExpectRejected(g, ErrorCode::kInvalidModel, Model("planar.urdf"), "", "planar");
  // A URDF string that urdfdom refuses (two roots).
  const std::string before = Dump(g);
  auto r = LoadUrdfString(g, "<robot name='r'><link name='p'/><link name='q'/></robot>", "s_");
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidModel);
  EXPECT_EQ(Dump(g), before);
}

TEST(Urdf, NameClashesInTheSpecOrder) {
  Graph g;
  ASSERT_TRUE(LoadUrdfFile(g, Model("arm6.urdf")));
  ExpectRejected(g, ErrorCode::kDuplicateJoint, Model("arm6.urdf"), "", "shoulder_pan_joint");
  // A body named like a link of arm7 (but no joint clash): duplicate_body.
  ASSERT_TRUE(g.AddBody("link3"));
  ASSERT_TRUE(g.AddFrame("flange", "tool0"));
  ExpectRejected(g, ErrorCode::kDuplicateBody, Model("arm7.urdf"), "", "body link3");
  // A frame only: duplicate_frame.
  Graph h;
  ASSERT_TRUE(h.AddFrame("link5", "").has_value() == false);
  ASSERT_TRUE(h.AddBody("Elsewhere"));
  ASSERT_TRUE(h.AddFrame("link5", "Elsewhere"));
  ExpectRejected(h, ErrorCode::kDuplicateFrame, Model("arm7.urdf"), "", "frame link5");
  // With a prefix the same model loads.
  EXPECT_TRUE(LoadUrdfFile(h, Model("arm7.urdf"), "a_"));
}

}  // namespace
}  // namespace semgraph::models
