// The real-time setters' verdict in numbers (core/update_error.h): for each rule a setter
// checks, a value that breaks it in a known component, and the detail the setter reports
// (input, component, the number, the limit) against the numbers written here by hand: the
// documented limits (1e12, 1e-6), |q| - 1 and max |M^T M - I| worked out for the input. The
// graph is unchanged by every refusal, and `why` is reset by the next accepted update.
#include "semgraph/core/update_error.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"

namespace semgraph::core {
namespace {

using coord::ValueProblem;
using coord::ValueRole;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

void ExpectDetail(const UpdateError& why, ErrorCode code, ValueProblem problem, ValueRole role,
                  int component, double magnitude, double limit) {
  EXPECT_EQ(why.code, code);
  EXPECT_EQ(why.value.problem, problem);
  EXPECT_EQ(why.value.role, role);
  EXPECT_EQ(int(why.value.component), component);
  if (std::isnan(magnitude)) {
    EXPECT_TRUE(std::isnan(why.value.magnitude));
  } else {
    EXPECT_DOUBLE_EQ(why.value.magnitude, magnitude);
  }
  EXPECT_EQ(why.limit, limit);
}

template <class B>
class UpdateErrorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(g_.AddPose(PoseSpec::Of("e", "E").RelativeTo("b", "B"), Quaterniond::Identity(),
                           Vector3d(1, 0, 0)));
    ASSERT_TRUE(g_.AddTwist(TwistSpec::Of("e", "E").RelativeTo("B").ExpressedIn("e"),
                            Vector3d(1, 0, 0), Vector3d::Zero()));
    pose_ = *g_.FindPoseEdge("e", "b");
    twist_ = *g_.FindTwistEdge("e", "B");
    before_ = Dump(g_);
  }
  void ExpectUnchanged() { EXPECT_EQ(Dump(g_), before_); }
  SceneGraph<B> g_;
  PoseHandle pose_;
  TwistHandle twist_;
  std::string before_;
};

using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(UpdateErrorTest, Backends);

TYPED_TEST(UpdateErrorTest, PositionTooLargeOrNotFinite) {
  UpdateError why;
  EXPECT_EQ(this->g_.SetPose(this->pose_, Quaterniond::Identity(), Vector3d(0, -2e12, 0), &why),
            ErrorCode::kInvalidNumber);
  ExpectDetail(why, ErrorCode::kInvalidNumber, ValueProblem::kTooLarge, ValueRole::kPosition, 1,
               -2e12, 1e12);
  EXPECT_EQ(Describe(why), "position component 1 is -2e+12 (magnitude above 1e+12)");
  EXPECT_EQ(this->g_.SetPose(this->pose_, Matrix3d::Identity(), Vector3d(0, 0, kNaN), &why),
            ErrorCode::kInvalidNumber);
  ExpectDetail(why, ErrorCode::kInvalidNumber, ValueProblem::kNotFinite, ValueRole::kPosition, 2,
               kNaN, 0);
  this->ExpectUnchanged();
}

TYPED_TEST(UpdateErrorTest, RotationsOffUnitOrReflected) {
  UpdateError why;
  // |(2, 0, 0, 0)| - 1 = 1.
  EXPECT_EQ(this->g_.SetPose(this->pose_, Quaterniond(2, 0, 0, 0), Vector3d::Zero(), &why),
            ErrorCode::kInvalidRotation);
  ExpectDetail(why, ErrorCode::kInvalidRotation, ValueProblem::kQuaternionNorm,
               ValueRole::kQuaternion, 0, 1.0, 1e-6);
  EXPECT_EQ(Describe(why), "quaternion norm differs from 1 by 1 (more than 1e-06)");
  // Components in w x y z order: x is 1.
  EXPECT_EQ(this->g_.SetPose(this->pose_, Quaterniond(1, kInf, 0, 0), Vector3d::Zero(), &why),
            ErrorCode::kInvalidNumber);
  ExpectDetail(why, ErrorCode::kInvalidNumber, ValueProblem::kNotFinite, ValueRole::kQuaternion, 1,
               kInf, 0);
  // (2I)^T (2I) - I = 3I: off by 3.
  EXPECT_EQ(
      this->g_.SetPose(this->pose_, Matrix3d(2 * Matrix3d::Identity()), Vector3d::Zero(), &why),
      ErrorCode::kInvalidRotation);
  ExpectDetail(why, ErrorCode::kInvalidRotation, ValueProblem::kNotOrthonormal,
               ValueRole::kRotationMatrix, 0, 3.0, 1e-6);
  // diag(1, 1, -1): orthonormal, determinant -1.
  EXPECT_EQ(this->g_.SetPose(this->pose_, Matrix3d(Vector3d(1, 1, -1).asDiagonal()),
                             Vector3d::Zero(), &why),
            ErrorCode::kInvalidRotation);
  ExpectDetail(why, ErrorCode::kInvalidRotation, ValueProblem::kReflection,
               ValueRole::kRotationMatrix, 0, -1.0, 0);
  this->ExpectUnchanged();
}

TYPED_TEST(UpdateErrorTest, TwistsAndTheCodesWithoutNumbers) {
  UpdateError why;
  EXPECT_EQ(this->g_.SetTwist(this->twist_, Vector3d::Zero(), Vector3d(0, 0, 3e12), &why),
            ErrorCode::kInvalidNumber);
  ExpectDetail(why, ErrorCode::kInvalidNumber, ValueProblem::kTooLarge, ValueRole::kAngularVelocity,
               2, 3e12, 1e12);
  EXPECT_EQ(this->g_.SetTwist(this->twist_, Vector3d(kNaN, 0, 0), Vector3d::Zero(), &why),
            ErrorCode::kInvalidNumber);
  ExpectDetail(why, ErrorCode::kInvalidNumber, ValueProblem::kNotFinite, ValueRole::kLinearVelocity,
               0, kNaN, 0);
  this->ExpectUnchanged();
  // A timeless edge refuses a stamp: the code, no number.
  EXPECT_EQ(this->g_.SetPose(this->pose_, Quaterniond::Identity(), Vector3d::Zero(),
                             Stamp::Nanoseconds(5), &why),
            ErrorCode::kStampMismatch);
  ExpectDetail(why, ErrorCode::kStampMismatch, ValueProblem::kNone, ValueRole::kPosition, 0, 0.0,
               0);
  EXPECT_EQ(Describe(why), "stamp_mismatch");
  EXPECT_EQ(this->g_.SetTwist(TwistHandle{}, Vector3d::Zero(), Vector3d::Zero(), &why),
            ErrorCode::kNoSuchEdge);
  EXPECT_EQ(why.code, ErrorCode::kNoSuchEdge);
  // An accepted update resets the report.
  EXPECT_EQ(this->g_.SetPose(this->pose_, Quaterniond::Identity(), Vector3d(0, 0, 1e12), &why),
            ErrorCode::kOk);
  ExpectDetail(why, ErrorCode::kOk, ValueProblem::kNone, ValueRole::kPosition, 0, 0.0, 0);
}

TYPED_TEST(UpdateErrorTest, ConvertingHandlesReportTheInputTheyWereGiven) {
  ASSERT_TRUE(this->g_.AddFrame("r", "E"));
  ASSERT_TRUE(this->g_.AddPose(PoseSpec::Of("r").RelativeTo("e"), Quaterniond::Identity(),
                               Vector3d(0, 1, 0)));
  auto twist = this->g_.FindTwistEdge("e", "B", "r");
  ASSERT_TRUE(twist);
  UpdateError why;
  EXPECT_EQ(this->g_.SetTwist(*twist, Vector3d(0, kInf, 0), Vector3d::Zero(), &why),
            ErrorCode::kInvalidNumber);
  ExpectDetail(why, ErrorCode::kInvalidNumber, ValueProblem::kNotFinite, ValueRole::kLinearVelocity,
               1, kInf, 0);
  auto pose = this->g_.FindPoseEdge(PoseSpec::Of("e").RelativeTo("b").ExpressedIn("b"));
  ASSERT_TRUE(pose);
  EXPECT_EQ(this->g_.SetPose(*pose, Quaterniond(0.5, 0, 0, 0), Vector3d::Zero(), &why),
            ErrorCode::kInvalidRotation);
  ExpectDetail(why, ErrorCode::kInvalidRotation, ValueProblem::kQuaternionNorm,
               ValueRole::kQuaternion, 0, 0.5, 1e-6);
}

TEST(UpdateErrorJoints, TheFirstJointThatBreaksTheRuleWithItsLimit) {
  SceneGraph<> g;
  const char* links[] = {"l0", "l1", "l2", "l3"};
  const char* bodies[] = {"L0", "L1", "L2", "L3"};
  for (int i = 0; i < 3; ++i) {
    JointSpec s;
    const std::string name = "j" + std::to_string(i);
    s.name = name;
    s.type = JointType::kRevolute;
    s.parent = links[i];
    s.parent_body = bodies[i];
    s.child = links[i + 1];
    s.child_body = bodies[i + 1];
    s.axis = {0, 0, 1};
    s.lower = -1;
    s.upper = 1 + i;  // 1, 2, 3
    ASSERT_TRUE(g.AddJoint(s));
  }
  const JointGroup group = g.AllJoints();
  ASSERT_EQ(group.size(), 3u);
  const std::string before = Dump(g);
  UpdateError why;
  // Joint 1 (upper 2) and joint 2 (lower -1) break their limits: the first is reported.
  const std::array<double, 3> q{0.5, 2.5, -4};
  EXPECT_EQ(g.SetJointPositions(group, q, &why), ErrorCode::kJointLimit);
  ExpectDetail(why, ErrorCode::kJointLimit, ValueProblem::kOutsideLimits, ValueRole::kJointPosition,
               0, 2.5, 2);
  EXPECT_EQ(why.joint, 1u);
  EXPECT_EQ(Describe(why),
            "position of joint 1 of the group is 2.5, above the joint's upper limit 2");
  const std::array<double, 3> low{0.5, 1.5, -4};
  EXPECT_EQ(g.SetJointPositions(group, low, &why), ErrorCode::kJointLimit);
  EXPECT_EQ(why.joint, 2u);
  EXPECT_EQ(why.limit, -1.0);
  EXPECT_EQ(Describe(why),
            "position of joint 2 of the group is -4, below the joint's lower limit -1");
  // invalid_number comes before joint_limit, and names the velocity.
  const std::array<double, 3> qdot{0, 0, kNaN};
  EXPECT_EQ(g.SetJointState(group, q, qdot, &why), ErrorCode::kInvalidNumber);
  ExpectDetail(why, ErrorCode::kInvalidNumber, ValueProblem::kNotFinite, ValueRole::kJointVelocity,
               0, kNaN, 0);
  EXPECT_EQ(why.joint, 2u);
  EXPECT_EQ(Describe(why), "velocity of joint 2 of the group is nan (must be finite)");
  EXPECT_EQ(Dump(g), before);
  // A timeless joint refuses a stamped state: the code only.
  const std::array<double, 3> ok{0, 0, 0};
  EXPECT_EQ(g.SetJointPositions(group, ok, &why), ErrorCode::kOk);
  EXPECT_EQ(why.code, ErrorCode::kOk);
  EXPECT_EQ(g.SetJointPositions(group, ok, Stamp::Nanoseconds(1), &why), ErrorCode::kStampMismatch);
  EXPECT_EQ(why.code, ErrorCode::kStampMismatch);
  EXPECT_EQ(why.value.problem, ValueProblem::kNone);
}

TEST(UpdateErrorLimits, LimitOfNamesTheDocumentedBounds) {
  EXPECT_EQ(coord::LimitOf(ValueProblem::kTooLarge), 1e12);
  EXPECT_EQ(coord::LimitOf(ValueProblem::kQuaternionNorm), 1e-6);
  EXPECT_EQ(coord::LimitOf(ValueProblem::kNotOrthonormal), 1e-6);
  EXPECT_EQ(coord::LimitOf(ValueProblem::kNotRigidTransform), 1e-6);
  EXPECT_EQ(coord::LimitOf(ValueProblem::kNotFinite), 0.0);
  EXPECT_EQ(coord::LimitOf(ValueProblem::kReflection), 0.0);
}

}  // namespace
}  // namespace semgraph::core
