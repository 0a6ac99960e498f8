// The numbers in the core's messages (core/src/describe.cc, coord::FormatNumber): every number
// is printed with the fewest digits that read back exactly, so a message never shows a rounded
// value that is not the offending or stored one.
#include <gtest/gtest.h>

#include <string>

#include "semgraph/core/scene_graph.h"

namespace semgraph::core {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(Describe, ConstantPoseChangeShowsTheStoredPositionExactly) {
  SceneGraph<> g;
  const Vector3d p(0.1, 0.1 + 0.2, 1.0 / 3.0);
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("a2", "A").RelativeTo("a", "A"), Quaterniond::Identity(), p));
  const auto r = g.AddPose(PoseSpec::Of("a2").RelativeTo("a"), Quaterniond::Identity(), Vector3d(1, 2, 3));
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kConstantPoseChange);
  // Before: "[0.1, 0.3, 0.333333333]" (9 digits), which is not the stored value.
  EXPECT_TRUE(Contains(r.error().message, "(position [0.1, 0.30000000000000004, 0.3333333333333333])"))
      << r.error().message;
}

TEST(Describe, InvalidNumberShowsTheOffendingValueExactly) {
  SceneGraph<> g;
  const auto r = g.AddPose(PoseSpec::Of("a", "A").RelativeTo("w", "W"), Quaterniond::Identity(),
                           Vector3d(1000000000000.5, 0, 0));
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidNumber);
  // Before: "position component 0 is 1e+12 (magnitude above 1e+12)".
  EXPECT_TRUE(Contains(r.error().message, "position component 0 is 1000000000000.5 (magnitude above 1e+12)"))
      << r.error().message;
}

}  // namespace
}  // namespace semgraph::core
