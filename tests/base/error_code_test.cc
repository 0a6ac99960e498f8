// Tests for semgraph/base/error_code.h: every code has the spec's snake_case name, and
// ToString / ErrorCodeFromString are inverse to each other.
#include "semgraph/base/error_code.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace semgraph::base {
namespace {

// Every enumerator with its wire name, in enum order. The names come from the rules
// (docs/rules.md §8), including semantic_mismatch (this layer) and query_invalidated.
const std::vector<std::pair<ErrorCode, std::string_view>>& AllCodes() {
  static const std::vector<std::pair<ErrorCode, std::string_view>> codes = {
      {ErrorCode::kOk, "ok"},
      {ErrorCode::kSemanticMismatch, "semantic_mismatch"},
      {ErrorCode::kInvalidName, "invalid_name"},
      {ErrorCode::kInvalidNumber, "invalid_number"},
      {ErrorCode::kInvalidRotation, "invalid_rotation"},
      {ErrorCode::kDuplicateBody, "duplicate_body"},
      {ErrorCode::kDuplicateFrame, "duplicate_frame"},
      {ErrorCode::kUnknownBody, "unknown_body"},
      {ErrorCode::kUnknownFrame, "unknown_frame"},
      {ErrorCode::kFrameWithoutBody, "frame_without_body"},
      {ErrorCode::kFrameBodyMismatch, "frame_body_mismatch"},
      {ErrorCode::kSelfEdge, "self_edge"},
      {ErrorCode::kRepresentationConstraint, "representation_constraint"},
      {ErrorCode::kPoseNotConvertible, "pose_not_convertible"},
      {ErrorCode::kConstantPoseChange, "constant_pose_change"},
      {ErrorCode::kMultiplePoseParents, "multiple_pose_parents"},
      {ErrorCode::kPoseCycle, "pose_cycle"},
      {ErrorCode::kDuplicatePosePath, "duplicate_pose_path"},
      {ErrorCode::kTwistMergeConflict, "twist_merge_conflict"},
      {ErrorCode::kTwistSameBody, "twist_same_body"},
      {ErrorCode::kTwistNotConvertible, "twist_not_convertible"},
      {ErrorCode::kMultipleTwistParents, "multiple_twist_parents"},
      {ErrorCode::kDuplicateTwistPath, "duplicate_twist_path"},
      {ErrorCode::kNoSuchEdge, "no_such_edge"},
      {ErrorCode::kNoPosePath, "no_pose_path"},
      {ErrorCode::kNoTwistPath, "no_twist_path"},
      {ErrorCode::kQueryInvalidated, "query_invalidated"},
      {ErrorCode::kStampMismatch, "stamp_mismatch"},
      {ErrorCode::kStampTooOld, "stamp_too_old"},
      {ErrorCode::kDuplicateStamp, "duplicate_stamp"},
      {ErrorCode::kExtrapolation, "extrapolation"},
      {ErrorCode::kStale, "stale"},
      {ErrorCode::kInvalidModel, "invalid_model"},
      {ErrorCode::kDuplicateJoint, "duplicate_joint"},
      {ErrorCode::kUnknownJoint, "unknown_joint"},
      {ErrorCode::kJointLimit, "joint_limit"},
      {ErrorCode::kMimicJoint, "mimic_joint"},
      {ErrorCode::kJointEdge, "joint_edge"},
      {ErrorCode::kInvalidCovariance, "invalid_covariance"},
      {ErrorCode::kSelfWrench, "self_wrench"},
      {ErrorCode::kWrenchNotConvertible, "wrench_not_convertible"},
      {ErrorCode::kDuplicateWrench, "duplicate_wrench"},
      {ErrorCode::kNoWrench, "no_wrench"},
      {ErrorCode::kNoAcceleration, "no_acceleration"},
      {ErrorCode::kAccelerationNotConvertible, "acceleration_not_convertible"},
  };
  return codes;
}

TEST(ErrorCode, TableAboveListsEveryEnumeratorInOrder) {
  ASSERT_EQ(AllCodes().size(), static_cast<std::size_t>(kNumErrorCodes));
  for (int i = 0; i < kNumErrorCodes; ++i) {
    EXPECT_EQ(static_cast<int>(AllCodes()[static_cast<std::size_t>(i)].first), i);
  }
}

TEST(ErrorCode, EveryCodeHasTheSpecName) {
  for (const auto& [code, name] : AllCodes()) {
    EXPECT_EQ(ToString(code), name) << "code " << static_cast<int>(code);
  }
}

TEST(ErrorCode, EveryNameMapsBackToItsCode) {
  for (const auto& [code, name] : AllCodes()) {
    const auto parsed = ErrorCodeFromString(name);
    ASSERT_TRUE(parsed.has_value()) << name;
    EXPECT_EQ(*parsed, code) << name;
  }
}

TEST(ErrorCode, RoundTripsEveryCode) {
  for (int i = 0; i < kNumErrorCodes; ++i) {
    const auto code = static_cast<ErrorCode>(i);
    EXPECT_EQ(ErrorCodeFromString(ToString(code)), code) << i;
  }
}

TEST(ErrorCode, NamesAreDistinctLowerSnakeCase) {
  std::set<std::string_view> seen;
  for (int i = 0; i < kNumErrorCodes; ++i) {
    const std::string_view name = ToString(static_cast<ErrorCode>(i));
    EXPECT_TRUE(seen.insert(name).second) << "duplicate name " << name;
    ASSERT_FALSE(name.empty());
    EXPECT_NE(name.front(), '_') << name;
    EXPECT_NE(name.back(), '_') << name;
    EXPECT_EQ(name.find("__"), std::string_view::npos) << name;
    for (char c : name) EXPECT_TRUE((c >= 'a' && c <= 'z') || c == '_') << name;
  }
}

TEST(ErrorCode, EveryCodeNamedInTheSpecExists) {
  // The codes of the scene graph's rules (docs/rules.md §1-§4, §8), spelled as there.
  for (std::string_view name : {"duplicate_body",
                                "duplicate_frame",
                                "unknown_body",
                                "frame_without_body",
                                "frame_body_mismatch",
                                "invalid_name",
                                "multiple_pose_parents",
                                "pose_cycle",
                                "self_edge",
                                "duplicate_pose_path",
                                "constant_pose_change",
                                "pose_not_convertible",
                                "twist_not_convertible",
                                "multiple_twist_parents",
                                "twist_same_body",
                                "duplicate_twist_path",
                                "twist_merge_conflict",
                                "no_such_edge",
                                "invalid_number",
                                "invalid_rotation",
                                "unknown_frame",
                                "no_pose_path",
                                "no_twist_path",
                                "representation_constraint"}) {
    EXPECT_TRUE(ErrorCodeFromString(name).has_value()) << name;
  }
}

TEST(ErrorCode, RejectsUnknownNames) {
  EXPECT_FALSE(ErrorCodeFromString("").has_value());
  EXPECT_FALSE(ErrorCodeFromString("pose-cycle").has_value());
  EXPECT_FALSE(ErrorCodeFromString("Pose_Cycle").has_value());
  EXPECT_FALSE(ErrorCodeFromString("POSE_CYCLE").has_value());
  EXPECT_FALSE(ErrorCodeFromString("pose_cycle ").has_value());
  EXPECT_FALSE(ErrorCodeFromString("kPoseCycle").has_value());
  EXPECT_FALSE(ErrorCodeFromString("unknown_error").has_value());
}

TEST(ErrorCode, OutOfRangeValueHasAFallbackName) {
  EXPECT_EQ(ToString(static_cast<ErrorCode>(kNumErrorCodes)), "unknown_error");
  EXPECT_EQ(ToString(static_cast<ErrorCode>(255)), "unknown_error");
}

TEST(ErrorCode, OkIsZero) {
  static_assert(static_cast<int>(ErrorCode::kOk) == 0);
  static_assert(sizeof(ErrorCode) == 1);
  EXPECT_EQ(ToString(ErrorCode{}), "ok");
}

TEST(ErrorCode, ToStringReturnsStaticStorage) {
  const std::string_view first = ToString(ErrorCode::kPoseCycle);
  const std::string_view second = ToString(ErrorCode::kPoseCycle);
  EXPECT_EQ(first.data(), second.data());
}

}  // namespace
}  // namespace semgraph::base
