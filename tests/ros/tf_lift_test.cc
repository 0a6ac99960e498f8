// tf transforms and joint states into a graph (ros/tf_lift.h): values against hand-computed
// compositions, every finding of the ROS spec's §5 with the graph unchanged, robot models.
#include "semgraph/ros/tf_lift.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <type_traits>

#include "semgraph/core/scene_graph_debug.h"
#include "semgraph/models/urdf.h"

namespace semgraph::ros {
namespace {

using core::ErrorCode;
using core::PoseSpec;
using Graph = core::SceneGraph<>;

constexpr std::int64_t kSec = 1'000'000'000;

TransformStamped Tf(std::string parent, std::string child, std::int64_t stamp_ns, Vector3 p = {},
                    Quaternion q = {}) {
  TransformStamped t;
  t.header.frame_id = std::move(parent);
  t.header.stamp = Time{stamp_ns / kSec, static_cast<std::uint32_t>(stamp_ns % kSec)};
  t.child_frame_id = std::move(child);
  t.transform.translation = p;
  t.transform.rotation = q;
  return t;
}

Quaternion AboutZ(double angle) { return {0, 0, std::sin(angle / 2), std::cos(angle / 2)}; }

TfLift<coord::QuaternionBackend> Lift(Graph& graph, LiftOptions options = {}) {
  auto plan = BodyPlan::Make(options);
  return TfLift<coord::QuaternionBackend>(graph, std::move(*plan));
}

/// Applies `t` and expects a refusal with `code`, the graph unchanged, one finding group.
void ExpectRefused(TfLift<coord::QuaternionBackend>& lift, Graph& graph, const TransformStamped& t,
                   bool is_static, ErrorCode code) {
  const std::string before = core::Dump(graph);
  const std::size_t groups = lift.findings().groups().size();
  EXPECT_EQ(lift.Apply(t, is_static, is_static ? "/tf_static" : "/tf", 7), LiftOutcome::kRefused);
  EXPECT_EQ(core::Dump(graph), before) << "a refused transform changed the graph";
  ASSERT_EQ(lift.findings().groups().size(), groups + 1);
  const FindingGroup& g = lift.findings().groups().back();
  EXPECT_EQ(g.code.name(), base::ToString(code)) << g.message;
  EXPECT_EQ(g.parent, LiftFrameName(t.header.frame_id));
  EXPECT_EQ(g.child, LiftFrameName(t.child_frame_id));
  EXPECT_EQ(g.topic, is_static ? "/tf_static" : "/tf");
  EXPECT_FALSE(g.message.empty());
}

// W: odom, B: base (static tree base -> camera), C: camera. odom -> base moves (stamped).
TEST(TfLift, StaticTreeIsOneBodyAndQueriesComposeTheTransforms) {
  Graph graph;
  auto lift = Lift(graph);
  lift.plan().AddStatic("base", "camera");
  TFMessage statics;
  statics.transforms.push_back(Tf("/base", "camera", 0, {0.1, 0, 0.5}, AboutZ(M_PI / 2)));
  lift.Apply(statics, true, "/tf_static", 1);
  TFMessage moving;
  moving.transforms.push_back(Tf("odom", "base", 10 * kSec, {1, 2, 0}, AboutZ(0)));
  moving.transforms.push_back(Tf("odom", "base", 11 * kSec, {2, 2, 0}, AboutZ(0)));
  lift.Apply(moving, false, "/tf", 2);
  EXPECT_EQ(lift.counts().applied, 3u);
  EXPECT_TRUE(lift.findings().empty());
  EXPECT_EQ(graph.body_name(graph.body_of(graph.FindFrame("camera"))), "base");
  EXPECT_EQ(graph.body_name(graph.body_of(graph.FindFrame("odom"))), "odom");
  // p_WoCo_W at t = 10.5 s (linear interpolation of the base halfway): (1.5, 2, 0) + (0.1, 0, 0.5).
  const auto X_WC = graph.GetPose(PoseSpec::Of("camera").RelativeTo("odom"),
                                  core::At(core::Stamp::Nanoseconds(10 * kSec + kSec / 2)));
  ASSERT_TRUE(X_WC) << graph.Describe(X_WC.error());
  const Eigen::Isometry3d X = X_WC->value.ToIsometry();
  EXPECT_NEAR((X.translation() - Eigen::Vector3d(1.6, 2, 0.5)).norm(), 0, 1e-12);
  // The camera's x axis is the odom y axis (a quarter turn about z).
  EXPECT_NEAR((X.linear().col(0) - Eigen::Vector3d::UnitY()).norm(), 0, 1e-12);
}

TEST(TfLift, OwnBodyMakesAStaticTransformATimelessInterBodyPose) {
  Graph graph;
  auto lift = Lift(graph, {StaticMode::kOwnBody, {}, {}});
  EXPECT_EQ(lift.Apply(Tf("base", "laser", 0, {0, 0, 1}), true, "/tf_static", 1),
            LiftOutcome::kApplied);
  EXPECT_NE(graph.body_of(graph.FindFrame("laser")), graph.body_of(graph.FindFrame("base")));
  // Updatable by a later static value (tf2 replaces it too).
  EXPECT_EQ(lift.Apply(Tf("base", "laser", 0, {0, 0, 2}), true, "/tf_static", 2),
            LiftOutcome::kApplied);
  const auto p = graph.GetPosition(PoseSpec::Of("laser").RelativeTo("base"));
  ASSERT_TRUE(p);
  EXPECT_EQ(p->value.z(), 2.0);
}

TEST(TfLift, EveryRefusalOfTheSpecIsAFindingAndChangesNothing) {
  Graph graph;
  auto lift = Lift(graph);
  lift.plan().AddStatic("base", "camera");
  ASSERT_EQ(lift.Apply(Tf("base", "camera", 0, {0, 0, 1}), true, "/tf_static", 1),
            LiftOutcome::kApplied);
  ASSERT_EQ(lift.Apply(Tf("odom", "base", 5 * kSec), false, "/tf", 2), LiftOutcome::kApplied);
  ASSERT_EQ(lift.Apply(Tf("map", "odom", 5 * kSec), false, "/tf", 2), LiftOutcome::kApplied);
  // tf2 re-parents a frame a second publisher claims: semgraph refuses.
  ExpectRefused(lift, graph, Tf("world", "base", 6 * kSec), false, ErrorCode::kMultiplePoseParents);
  ExpectRefused(lift, graph, Tf("base", "map", 6 * kSec), false, ErrorCode::kPoseCycle);
  ExpectRefused(lift, graph, Tf("base", "camera", 0, {0, 0, 2}), true,
                ErrorCode::kConstantPoseChange);
  ExpectRefused(lift, graph, Tf("odom", "odom", 6 * kSec), false, ErrorCode::kSelfEdge);
  ExpectRefused(lift, graph, Tf("odom", "base", 6 * kSec, {NAN, 0, 0}), false,
                ErrorCode::kInvalidNumber);
  ExpectRefused(lift, graph, Tf("odom", "base", 6 * kSec, {}, {0, 0, 0, 1.1}), false,
                ErrorCode::kInvalidRotation);
  ExpectRefused(lift, graph, Tf("odom", "", 6 * kSec), false, ErrorCode::kInvalidName);
  // Older than the window (10 s by default) behind the newest sample.
  ASSERT_EQ(lift.Apply(Tf("odom", "base", 30 * kSec), false, "/tf", 3), LiftOutcome::kApplied);
  ExpectRefused(lift, graph, Tf("odom", "base", 1 * kSec), false, ErrorCode::kStampTooOld);
  EXPECT_EQ(lift.counts().refused, 8u);
  EXPECT_EQ(lift.counts().transforms, 12u);
  EXPECT_EQ(core::CheckInvariants(graph), "");
}

TEST(TfLift, TwoPathsBetweenBodiesOfTheMapAreDuplicatePosePath) {
  // The map puts the unconnected frames arm and tip on one body ARM: base -> arm, then
  // camera (on base) -> tip is a second path between the bodies.
  Graph graph;
  auto lift = Lift(graph, {StaticMode::kSameBody, {{"ARM", {"arm", "tip"}}}, {}});
  lift.plan().AddStatic("base", "camera");
  ASSERT_EQ(lift.Apply(Tf("base", "camera", 0), true, "/tf_static", 1), LiftOutcome::kApplied);
  ASSERT_EQ(lift.Apply(Tf("base", "arm", 5 * kSec), false, "/tf", 2), LiftOutcome::kApplied);
  EXPECT_EQ(graph.body_name(graph.body_of(graph.FindFrame("arm"))), "ARM");
  ExpectRefused(lift, graph, Tf("camera", "tip", 6 * kSec), false, ErrorCode::kDuplicatePosePath);
}

TEST(TfLift, AFrameBothStaticAndDynamicIsRefused) {
  {  // own_body: a timeless edge then a stamped sample of it.
    Graph graph;
    auto lift = Lift(graph, {StaticMode::kOwnBody, {}, {}});
    ASSERT_EQ(lift.Apply(Tf("base", "arm", 0), true, "/tf_static", 1), LiftOutcome::kApplied);
    ExpectRefused(lift, graph, Tf("base", "arm", 3 * kSec, {1, 0, 0}), false,
                  ErrorCode::kStampMismatch);
  }
  {  // same_body: the frames are one body, so a moving value is a constant pose change.
    Graph graph;
    auto lift = Lift(graph);
    lift.plan().AddStatic("base", "arm");
    ASSERT_EQ(lift.Apply(Tf("base", "arm", 0), true, "/tf_static", 1), LiftOutcome::kApplied);
    ExpectRefused(lift, graph, Tf("base", "arm", 3 * kSec, {1, 0, 0}), false,
                  ErrorCode::kConstantPoseChange);
  }
}

TEST(TfLift, ALaterStaticLinkToAFrameOnAnotherBodyIsFrameBodyMismatch) {
  Graph graph;  // live: "camera" first seen moving, on its own body
  auto lift = Lift(graph);
  ASSERT_EQ(lift.Apply(Tf("odom", "camera", kSec), false, "/tf", 1), LiftOutcome::kApplied);
  ASSERT_EQ(lift.Apply(Tf("odom", "base", kSec), false, "/tf", 1), LiftOutcome::kApplied);
  lift.plan().AddStatic("base", "camera");
  ExpectRefused(lift, graph, Tf("base", "camera", 0), true, ErrorCode::kFrameBodyMismatch);
}

TEST(TfLift, NearlyUnitQuaternionsAreNormalizedAndCounted) {
  Graph graph;
  auto lift = Lift(graph);
  // |q|^2 = 1.0081: within tf2's 0.01, normalized (counted).
  const Quaternion q{0, 0, 0, 1.004};
  ASSERT_EQ(lift.Apply(Tf("odom", "base", kSec, {}, q), false, "/tf", 1), LiftOutcome::kApplied);
  ASSERT_EQ(lift.Apply(Tf("odom", "base", 2 * kSec, {}, {0, 0, 0, 1 + 1e-9}), false, "/tf", 1),
            LiftOutcome::kApplied);
  EXPECT_EQ(lift.counts().normalized, 1u);
  const auto X = graph.GetPose(PoseSpec::Of("base").RelativeTo("odom"),
                               core::At(core::Stamp::Nanoseconds(kSec)));
  ASSERT_TRUE(X);
  EXPECT_NEAR((X->value.ToIsometry().linear() - Eigen::Matrix3d::Identity()).norm(), 0, 1e-15);
}

TEST(TfLift, FindingsAreGroupedByCodeParentAndChild) {
  Graph graph;
  auto lift = Lift(graph);
  ASSERT_EQ(lift.Apply(Tf("odom", "base", kSec), false, "/tf", 1), LiftOutcome::kApplied);
  for (int i = 0; i < 3; ++i) {
    (void)lift.Apply(Tf("world", "base", (2 + i) * kSec), false, "/tf", 10 + i);
  }
  ASSERT_EQ(lift.findings().groups().size(), 1u);
  const FindingGroup& g = lift.findings().groups()[0];
  EXPECT_EQ(g.count, 3u);
  EXPECT_EQ(g.first_log_time_ns, 10);
  EXPECT_EQ(g.last_log_time_ns, 12);
  EXPECT_EQ(g.first_stamp_ns, 2 * kSec);
  EXPECT_EQ(g.last_stamp_ns, 4 * kSec);
  EXPECT_EQ(ToJsonLine(g).substr(0, 70),
            R"({"error": "multiple_pose_parents", "topic": "/tf", "parent": "world", )");
}

// A two-joint robot: base -(revolute z, 0.5 m up)-> link1 -(prismatic x, 1 m out)-> link2.
constexpr const char* kRobot = R"(<robot name="r">
  <link name="base"/><link name="link1"/><link name="link2"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="link1"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="prismatic"><parent link="link1"/><child link="link2"/>
    <origin xyz="1 0 0"/><axis xyz="1 0 0"/><limit lower="0" upper="1" effort="1" velocity="1"/></joint>
</robot>)";

TEST(TfLift, TransformsCoveredByTheModelAreComparedWithItsJoints) {
  Graph graph;
  auto robot = models::LoadUrdfString(graph, kRobot);
  ASSERT_TRUE(robot) << robot.error().message;
  auto lift = Lift(graph);
  lift.CoverModel(*robot);
  JointState js;
  js.header.stamp = Time{3, 0};
  js.name = {"j1", "j2"};
  js.position = {0.3, 0.2};
  lift.Apply(js, "/joint_states", 1);
  ASSERT_EQ(lift.counts().joint_states, 1u);
  // What robot_state_publisher would send at q = (0.3, 0.2), by hand.
  EXPECT_EQ(lift.Apply(Tf("base", "link1", 3 * kSec, {0, 0, 0.5}, AboutZ(0.3)), false, "/tf", 2),
            LiftOutcome::kCovered);
  EXPECT_EQ(lift.Apply(Tf("link1", "link2", 3 * kSec, {1.2, 0, 0}), false, "/tf", 2),
            LiftOutcome::kCovered);
  // 1e-5 m off: model_mismatch; the graph is unchanged.
  const std::string before = core::Dump(graph);
  EXPECT_EQ(lift.Apply(Tf("link1", "link2", 3 * kSec, {1.2 + 1e-5, 0, 0}), false, "/tf", 3),
            LiftOutcome::kMismatch);
  EXPECT_EQ(core::Dump(graph), before);
  ASSERT_EQ(lift.findings().groups().size(), 1u);
  EXPECT_EQ(lift.findings().groups()[0].code.name(), "model_mismatch");
  EXPECT_EQ(lift.counts().covered, 3u);
  EXPECT_EQ(lift.counts().mismatched, 1u);
  // An unknown joint name in a joint state: unknown_joint, nothing set.
  js.name = {"j1", "nope"};
  lift.Apply(js, "/joint_states", 4);
  EXPECT_EQ(lift.findings().groups().back().code.name(), "unknown_joint");
  js.name = {"j1"};
  lift.Apply(js, "/joint_states", 5);  // 1 name, 2 positions
  EXPECT_EQ(lift.findings().groups().back().code.name(), "invalid_number");
}

TEST(TfLift, ACoveredTransformBeforeItsJointStateIsComparedWhenTheJointStateArrives) {
  // As recorded: robot_state_publisher's /tf logged just before the /joint_states message it was
  // computed from. Compared with the joint state of its stamp, not extrapolated from older ones.
  Graph graph;
  auto robot = models::LoadUrdfString(graph, kRobot);
  ASSERT_TRUE(robot) << robot.error().message;
  auto lift = Lift(graph);
  lift.CoverModel(*robot);
  JointState js;
  js.name = {"j1", "j2"};
  js.header.stamp = Time{1, 0};
  js.position = {0.1, 0.0};
  lift.Apply(js, "/joint_states", 1);
  // At 2 s (q1 = 0.3): deferred, then equal to the model once the joint state of 2 s is in.
  EXPECT_EQ(lift.Apply(Tf("base", "link1", 2 * kSec, {0, 0, 0.5}, AboutZ(0.3)), false, "/tf", 2),
            LiftOutcome::kDeferred);
  // At 3 s, 1e-3 rad off the joint state of 3 s: a model_mismatch once that arrives.
  EXPECT_EQ(
      lift.Apply(Tf("base", "link1", 3 * kSec, {0, 0, 0.5}, AboutZ(0.5 + 1e-3)), false, "/tf", 3),
      LiftOutcome::kDeferred);
  js.header.stamp = Time{2, 0};
  js.position = {0.3, 0.0};
  lift.Apply(js, "/joint_states", 4);
  EXPECT_TRUE(lift.findings().empty());
  js.header.stamp = Time{3, 0};
  js.position = {0.5, 0.0};
  lift.Apply(js, "/joint_states", 5);
  ASSERT_EQ(lift.findings().groups().size(), 1u);
  EXPECT_EQ(lift.findings().groups()[0].code.name(), "model_mismatch");
  EXPECT_EQ(lift.findings().groups()[0].first_stamp_ns, 3 * kSec);
  EXPECT_EQ(lift.findings().groups()[0].first_log_time_ns, 3);
  // At 9 s, no joint state ever: compared at Flush, where the model has no pose at 9 s.
  EXPECT_EQ(lift.Apply(Tf("base", "link1", 9 * kSec, {0, 0, 0.5}, AboutZ(0.5)), false, "/tf", 6),
            LiftOutcome::kDeferred);
  EXPECT_EQ(lift.findings().groups().size(), 1u);
  lift.Flush();
  ASSERT_EQ(lift.findings().groups().size(), 2u);
  EXPECT_EQ(lift.findings().groups()[1].first_stamp_ns, 9 * kSec);
  EXPECT_EQ(lift.findings().groups()[1].topic, "/tf");
  EXPECT_EQ(lift.counts().covered, 3u);
  EXPECT_EQ(lift.counts().mismatched, 2u);
  EXPECT_EQ(lift.counts().applied, 0u);
}

TEST(TfLift, LaterSamplesOfAnEdgeGoByHandleAndRefusalsAreStillNamed) {
  // odom -> base at 100 s, 101 s, 102 s (the last two by handle), read back at each stamp; then
  // samples the graph refuses on that edge: older than the 10 s window, and a NaN.
  Graph graph;  // queried at the samples' stamps: exact whatever the interpolation
  auto lift = Lift(graph);
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(lift.Apply(Tf("odom", "base", (100 + k) * kSec, {1.0 * k, 0, 0}, AboutZ(0.1 * k)),
                         false, "/tf", k),
              LiftOutcome::kApplied);
  }
  for (int k = 0; k < 3; ++k) {
    const auto X = graph.GetPose(PoseSpec::Of("base").RelativeTo("odom"),
                                 core::At(core::Stamp::Nanoseconds((100 + k) * kSec)));
    ASSERT_TRUE(X);
    EXPECT_NEAR(X->value.ToIsometry().translation().x(), 1.0 * k, 1e-12);
    EXPECT_NEAR(Eigen::AngleAxisd(X->value.ToIsometry().linear()).angle(), 0.1 * k, 1e-12);
  }
  EXPECT_EQ(lift.counts().applied, 3u);
  ExpectRefused(lift, graph, Tf("odom", "base", 80 * kSec), false, ErrorCode::kStampTooOld);
  ExpectRefused(lift, graph, Tf("odom", "base", 103 * kSec, {std::nan(""), 0, 0}), false,
                ErrorCode::kInvalidNumber);
  // A static transform of the dynamic edge: not by handle; live, base is on a body of its own
  // already, so the static link to it is refused (spec §4).
  ExpectRefused(lift, graph, Tf("odom", "base", 0), true, ErrorCode::kFrameBodyMismatch);
  EXPECT_EQ(lift.counts().applied, 3u);
  EXPECT_EQ(lift.counts().refused, 3u);
}

TEST(TfLift, JointStatesAreSkippedWithoutJoints) {
  Graph graph;
  auto lift = Lift(graph);
  JointState js;
  js.name = {"j"};
  js.position = {1};
  lift.Apply(js, "/joint_states", 1);
  EXPECT_EQ(lift.counts().joint_states_skipped, 1u);
  EXPECT_TRUE(lift.findings().empty());
}

// ---------------------------------------------------------------- messages with covariance

/// A symmetric positive definite 6x6 with off-diagonal terms (A A^T + diag), row-major as ROS.
Covariance36 RosCovariance(double scale) {
  Eigen::Matrix<double, 6, 6> A;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) A(i, j) = scale * std::sin(1.0 + 7 * i + 3 * j);
  }
  const Eigen::Matrix<double, 6, 6> S =
      A * A.transpose() + scale * Eigen::Matrix<double, 6, 6>::Identity();
  Covariance36 c;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) c[static_cast<std::size_t>(6 * i + j)] = S(i, j);
  }
  return c;
}

Eigen::Matrix<double, 6, 6> Matrix(const Covariance36& c) {
  Eigen::Matrix<double, 6, 6> S;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) S(i, j) = c[static_cast<std::size_t>(6 * i + j)];
  }
  return S;
}

Time At(std::int64_t ns) { return Time{ns / kSec, static_cast<std::uint32_t>(ns % kSec)}; }

PoseWithCovarianceStamped AmclPose(std::int64_t stamp_ns, double x, double yaw, double scale) {
  PoseWithCovarianceStamped m;
  m.header.frame_id = "map";
  m.header.stamp = At(stamp_ns);
  m.pose.pose.position = {x, 2.0, 0.0};
  const Quaternion q = AboutZ(yaw);
  m.pose.pose.orientation = q;
  m.pose.covariance = RosCovariance(scale);
  return m;
}

Odometry Odom(std::int64_t stamp_ns, double yaw) {
  Odometry m;
  m.header.frame_id = "odom";
  m.header.stamp = At(stamp_ns);
  m.child_frame_id = "base_link";
  m.pose.pose.position = {1.0, -0.5, 0.0};
  m.pose.pose.orientation = AboutZ(yaw);
  m.pose.covariance = RosCovariance(0.01);
  m.twist.twist.linear = {0.4, 0.1, 0.0};
  m.twist.twist.angular = {0.0, 0.0, 0.3};
  m.twist.covariance = RosCovariance(0.002);
  return m;
}

std::string BodyOfFrame(const Graph& graph, std::string_view frame) {
  return std::string(graph.body_name(graph.body_of(graph.FindFrame(frame))));
}

// The edge's covariance is the message's 6x6 for {child} wrt {header} in [header] (docs:
// Σ_c = Σ), at each stamp; between two stamps the interpolation of the two samples'.
TEST(TfLift, PoseWithCovarianceStampedIsAStampedSampleWithTheMessageCovariance) {
  Graph graph;
  auto lift = Lift(graph);
  const auto m1 = AmclPose(1 * kSec, 1.0, 0.3, 0.01);
  const auto m2 = AmclPose(2 * kSec, 1.5, 0.5, 0.03);
  EXPECT_EQ(lift.Apply(m1, "base_footprint", "/amcl_pose", 5), LiftOutcome::kApplied);
  EXPECT_EQ(lift.Apply(m2, "/base_footprint", "/amcl_pose", 6), LiftOutcome::kApplied);
  EXPECT_EQ(lift.counts().poses_with_covariance, 2u);
  EXPECT_TRUE(lift.findings().empty());
  const PoseSpec spec = PoseSpec::Of("base_footprint").RelativeTo("map").ExpressedIn("map");
  for (const auto* m : {&m1, &m2}) {
    const auto r = graph.GetPoseWithCovariance(
        spec, core::At(core::Stamp::Nanoseconds(ToNanoseconds(m->header.stamp))));
    ASSERT_TRUE(r) << graph.Describe(r.error(), spec);
    const Eigen::Isometry3d X = r->value.value.ToIsometry();
    EXPECT_NEAR(X.translation().x(), m->pose.pose.position.x, 1e-12);
    EXPECT_NEAR(X.translation().y(), 2.0, 1e-12);
    const auto& q = m->pose.pose.orientation;
    EXPECT_NEAR(
        Eigen::Quaterniond(X.linear()).angularDistance(Eigen::Quaterniond(q.w, q.x, q.y, q.z)), 0.0,
        1e-12);
    EXPECT_LE((r->value.covariance - Matrix(m->pose.covariance)).cwiseAbs().maxCoeff(), 1e-12)
        << r->value.covariance;
  }
  // Halfway: (S1 + S2) / 2, by hand.
  const auto half =
      graph.GetPoseWithCovariance(spec, core::At(core::Stamp::Nanoseconds(1500000000)));
  ASSERT_TRUE(half);
  const Eigen::Matrix<double, 6, 6> S_half =
      0.5 * (Matrix(m1.pose.covariance) + Matrix(m2.pose.covariance));
  EXPECT_LE((half->value.covariance - S_half).cwiseAbs().maxCoeff(), 1e-12);
}

// Odometry: the pose as above; the twist of base_link's body wrt odom's body at base_link's
// origin in [base_link] with the message's twist covariance; in [odom] rotated by hand:
// v_odom = R v, S_odom = blockdiag(R, R) S blockdiag(R, R)^T.
TEST(TfLift, OdometryIsAPoseAndATwistWithTheirCovariances) {
  Graph graph;
  auto lift = Lift(graph);
  const double yaw = 0.7;
  const auto m = Odom(3 * kSec, yaw);
  EXPECT_EQ(lift.Apply(m, "/odom", 9), LiftOutcome::kApplied);
  EXPECT_EQ(lift.counts().odometry, 1u);
  EXPECT_TRUE(lift.findings().empty());
  const auto at = core::At(core::Stamp::Nanoseconds(3 * kSec));
  const PoseSpec pose_spec = PoseSpec::Of("base_link").RelativeTo("odom").ExpressedIn("odom");
  const auto pose = graph.GetPoseWithCovariance(pose_spec, at);
  ASSERT_TRUE(pose) << graph.Describe(pose.error(), pose_spec);
  EXPECT_LE((pose->value.covariance - Matrix(m.pose.covariance)).cwiseAbs().maxCoeff(), 1e-12);
  const std::string odom_body = BodyOfFrame(graph, "odom");
  const std::string base_body = BodyOfFrame(graph, "base_link");
  EXPECT_NE(odom_body, base_body);
  const auto in_child =
      core::TwistSpec::Of("base_link", base_body).RelativeTo(odom_body).ExpressedIn("base_link");
  const auto twist = graph.GetTwistWithCovariance(in_child, at);
  ASSERT_TRUE(twist) << graph.Describe(twist.error(), in_child);
  EXPECT_LE((twist->value.value.linear - Eigen::Vector3d(0.4, 0.1, 0.0)).norm(), 1e-12);
  EXPECT_LE((twist->value.value.angular - Eigen::Vector3d(0.0, 0.0, 0.3)).norm(), 1e-12);
  const Eigen::Matrix<double, 6, 6> S = Matrix(m.twist.covariance);
  EXPECT_LE((twist->value.covariance - S).cwiseAbs().maxCoeff(), 1e-12) << twist->value.covariance;
  // In [odom]: rotated by R_odom_base (about z by yaw), by hand.
  const auto in_odom =
      core::TwistSpec::Of("base_link", base_body).RelativeTo(odom_body).ExpressedIn("odom");
  const auto rotated = graph.GetTwistWithCovariance(in_odom, at);
  ASSERT_TRUE(rotated) << graph.Describe(rotated.error(), in_odom);
  const double c = std::cos(yaw), s = std::sin(yaw);
  Eigen::Matrix3d R;
  R << c, -s, 0, s, c, 0, 0, 0, 1;
  Eigen::Matrix<double, 6, 6> R6 = Eigen::Matrix<double, 6, 6>::Zero();
  R6.topLeftCorner<3, 3>() = R;
  R6.bottomRightCorner<3, 3>() = R;
  EXPECT_LE((rotated->value.value.linear - Eigen::Vector3d(0.4 * c - 0.1 * s, 0.4 * s + 0.1 * c, 0))
                .norm(),
            1e-12);
  // First order, by hand: R' = Exp(dθ) R (dθ: the pose's rotation error, in [odom], the
  // rotational block of the pose covariance), so d(R v) = R dv - [R v]x dθ; the pose's and the
  // twist's errors independent.
  const Eigen::Vector3d Rv = R * Eigen::Vector3d(0.4, 0.1, 0.0);
  const Eigen::Vector3d Rw = R * Eigen::Vector3d(0.0, 0.0, 0.3);
  const auto cross = [](const Eigen::Vector3d& u) {
    Eigen::Matrix3d K;
    K << 0, -u.z(), u.y(), u.z(), 0, -u.x(), -u.y(), u.x(), 0;
    return K;
  };
  Eigen::Matrix<double, 6, 3> J_theta;
  J_theta << -cross(Rv), -cross(Rw);
  const Eigen::Matrix3d S_theta = Matrix(m.pose.covariance).bottomRightCorner<3, 3>();
  const Eigen::Matrix<double, 6, 6> S_odom =
      R6 * S * R6.transpose() + J_theta * S_theta * J_theta.transpose();
  EXPECT_LE((rotated->value.covariance - S_odom).cwiseAbs().maxCoeff(), 1e-12)
      << rotated->value.covariance << "\n\n"
      << S_odom;
}

/// Applies `m` (an Odometry, or a pose of base_footprint) and expects a refusal with `code`
/// naming the topic, the stamp and the frames, the graph unchanged.
template <class M>
void ExpectCovarianceRefused(TfLift<coord::QuaternionBackend>& lift, Graph& graph, const M& m,
                             ErrorCode code, std::string_view words) {
  const std::string before = core::Dump(graph);
  const std::size_t groups = lift.findings().groups().size();
  const std::uint64_t refused = lift.counts().covariance_refused;
  if constexpr (std::is_same_v<M, Odometry>) {
    EXPECT_EQ(lift.Apply(m, "/odom", 11), LiftOutcome::kRefused);
  } else {
    EXPECT_EQ(lift.Apply(m, "base_footprint", "/amcl_pose", 11), LiftOutcome::kRefused);
  }
  EXPECT_EQ(core::Dump(graph), before) << "a refused message changed the graph";
  EXPECT_EQ(lift.counts().covariance_refused, refused + 1);
  ASSERT_EQ(lift.findings().groups().size(), groups + 1);
  const FindingGroup& g = lift.findings().groups().back();
  EXPECT_EQ(g.code.name(), base::ToString(code)) << g.message;
  EXPECT_EQ(g.topic, (std::is_same_v<M, Odometry> ? "/odom" : "/amcl_pose"));
  EXPECT_EQ(g.first_stamp_ns, ToNanoseconds(m.header.stamp));
  EXPECT_EQ(g.first_log_time_ns, 11);
  EXPECT_EQ(g.parent, LiftFrameName(m.header.frame_id));
  EXPECT_NE(g.message.find(words), std::string::npos) << g.message;
}

TEST(TfLift, BadCovariancesAreFindingsAndLeaveTheGraphUnchanged) {
  Graph graph;
  auto lift = Lift(graph);
  ASSERT_EQ(lift.Apply(AmclPose(1 * kSec, 1.0, 0.1, 0.01), "base_footprint", "/amcl_pose", 1),
            LiftOutcome::kApplied);
  ASSERT_EQ(lift.Apply(Odom(1 * kSec, 0.2), "/odom", 1), LiftOutcome::kApplied);

  auto nan = AmclPose(2 * kSec, 1.0, 0.1, 0.01);
  nan.pose.covariance[7] = std::nan("");
  ExpectCovarianceRefused(lift, graph, nan, ErrorCode::kInvalidNumber, "pose covariance");

  auto asymmetric = AmclPose(3 * kSec, 1.0, 0.1, 0.01);
  asymmetric.pose.covariance[1] += 0.5;  // (0, 1) but not (1, 0)
  ExpectCovarianceRefused(lift, graph, asymmetric, ErrorCode::kInvalidCovariance,
                          "pose covariance");

  auto negative = AmclPose(4 * kSec, 1.0, 0.1, 0.01);
  negative.header.frame_id = "world";  // another group than the asymmetric one's
  negative.pose.covariance = {};
  negative.pose.covariance[35] = -1.0;  // an eigenvalue of -1
  ExpectCovarianceRefused(lift, graph, negative, ErrorCode::kInvalidCovariance, "pose covariance");

  auto bad_quaternion = AmclPose(5 * kSec, 1.0, 0.1, 0.01);
  bad_quaternion.pose.pose.orientation = {0, 0, 0, 2};
  ExpectCovarianceRefused(lift, graph, bad_quaternion, ErrorCode::kInvalidRotation, "orientation");

  // The odometry twist's covariance bad: its pose is not added either.
  auto bad_twist = Odom(2 * kSec, 0.2);
  bad_twist.twist.covariance[0] = -3.0;
  ExpectCovarianceRefused(lift, graph, bad_twist, ErrorCode::kInvalidCovariance,
                          "twist covariance");
  auto nan_twist = Odom(3 * kSec, 0.2);
  nan_twist.twist.twist.angular.z = std::numeric_limits<double>::infinity();
  ExpectCovarianceRefused(lift, graph, nan_twist, ErrorCode::kInvalidNumber, "twist");

  // A graph rule: base_footprint already has its pose wrt map; one wrt odom is refused.
  auto second_parent = AmclPose(1 * kSec, 9.0, 0.1, 0.01);
  second_parent.header.frame_id = "odom";
  ExpectCovarianceRefused(lift, graph, second_parent, ErrorCode::kMultiplePoseParents, "pose");
  EXPECT_EQ(lift.counts().poses_with_covariance, 1u);
  EXPECT_EQ(lift.counts().odometry, 1u);
}

}  // namespace
}  // namespace semgraph::ros
