// The body of each tf frame (ros/body_plan.h): modes, the bodies map, frames in the graph.
#include "semgraph/ros/body_plan.h"

#include <gtest/gtest.h>

namespace semgraph::ros {
namespace {

BodyPlan Plan(LiftOptions options) {
  auto plan = BodyPlan::Make(options);
  EXPECT_TRUE(plan) << (plan ? "" : plan.error());
  return std::move(*plan);
}

const BodyPlan::ExistingBody kNone = [](std::string_view) -> std::optional<std::string> {
  return std::nullopt;
};

TEST(LiftFrameName, RemovesOneLeadingSlashAsTf2Does) {
  EXPECT_EQ(LiftFrameName("/base_link"), "base_link");
  EXPECT_EQ(LiftFrameName("base_link"), "base_link");
  EXPECT_EQ(LiftFrameName("//x"), "/x");
  EXPECT_EQ(LiftFrameName("/"), "");
  EXPECT_EQ(LiftFrameName(""), "");
}

// Static tree: base -> laser, base -> camera -> optical; odom -> base is dynamic (not here).
TEST(BodyPlan, SameBodyNamesAStaticTreeAfterItsRoot) {
  BodyPlan plan = Plan({});
  plan.AddStatic("base", "laser");
  plan.AddStatic("base", "camera");
  plan.AddStatic("camera", "optical");
  for (const char* f : {"base", "laser", "camera", "optical"}) {
    EXPECT_EQ(plan.BodyOf(f, kNone), "base") << f;
  }
  EXPECT_EQ(plan.BodyOf("odom", kNone), "odom");  // not static: its own body
  EXPECT_TRUE(plan.JoinsBodies("laser"));
}

TEST(BodyPlan, OwnBodyPutsEveryFrameOnItsOwnBody) {
  BodyPlan plan = Plan({StaticMode::kOwnBody, {}});
  plan.AddStatic("base", "laser");
  EXPECT_EQ(plan.BodyOf("laser", kNone), "laser");
  EXPECT_EQ(plan.BodyOf("base", kNone), "base");
  EXPECT_FALSE(plan.JoinsBodies("laser"));
}

TEST(BodyPlan, TheFirstStaticParentWins) {
  BodyPlan plan = Plan({});
  plan.AddStatic("a", "c");
  plan.AddStatic("b", "c");  // refused later by the graph (multiple_pose_parents)
  EXPECT_EQ(plan.StaticParent("c"), "a");
  EXPECT_EQ(plan.BodyOf("c", kNone), "a");
}

TEST(BodyPlan, AMapOverridesListedFramesAndUnlistedStaticChildrenFollowTheirParent) {
  // Map: the gripper's frames on body G; in own_body mode an unlisted static child of a listed
  // frame still joins its parent's body (the map's rule), other frames keep their own.
  BodyPlan plan = Plan({StaticMode::kOwnBody, {{"G", {"/gripper", "fingertip"}}}});
  plan.AddStatic("gripper", "tcp");     // tcp unlisted: on G
  plan.AddStatic("flange", "gripper");  // gripper listed: G, not flange's body
  EXPECT_EQ(plan.BodyOf("gripper", kNone), "G");
  EXPECT_EQ(plan.BodyOf("fingertip", kNone), "G");
  EXPECT_EQ(plan.BodyOf("tcp", kNone), "G");
  EXPECT_EQ(plan.BodyOf("flange", kNone), "flange");
  EXPECT_FALSE(plan.JoinsBodies("gripper"));
  EXPECT_TRUE(plan.JoinsBodies("tcp"));
}

TEST(BodyPlan, FramesInTheGraphKeepTheirBody) {
  BodyPlan plan = Plan({});
  plan.AddStatic("base_link", "camera");
  const BodyPlan::ExistingBody graph = [](std::string_view f) -> std::optional<std::string> {
    if (f == "base_link") return std::string("robot");
    return std::nullopt;
  };
  EXPECT_EQ(plan.BodyOf("camera", graph), "robot");
  EXPECT_EQ(plan.BodyOf("base_link", graph), "robot");
}

TEST(BodyPlan, AStaticLoopEndsTheWalk) {
  BodyPlan plan = Plan({});
  plan.AddStatic("a", "b");
  plan.AddStatic("b", "a");
  EXPECT_EQ(plan.BodyOf("a", kNone), "a");
  EXPECT_EQ(plan.BodyOf("b", kNone), "b");
}

TEST(BodyPlan, RefusesAFrameListedUnderTwoBodies) {
  const auto plan = BodyPlan::Make({StaticMode::kSameBody, {{"A", {"x"}}, {"B", {"/x"}}}});
  ASSERT_FALSE(plan);
  EXPECT_NE(plan.error().find("frame x is listed under bodies A and B"), std::string::npos)
      << plan.error();
  EXPECT_FALSE(BodyPlan::Make({StaticMode::kSameBody, {{"", {"x"}}}}));
  EXPECT_FALSE(BodyPlan::Make({StaticMode::kSameBody, {{"A", {"/"}}}}));
}

TEST(StaticMode, NamesRoundTrip) {
  for (StaticMode m : {StaticMode::kSameBody, StaticMode::kOwnBody}) {
    EXPECT_EQ(StaticModeFromString(ToString(m)), m);
  }
  EXPECT_FALSE(StaticModeFromString("same"));
}

}  // namespace
}  // namespace semgraph::ros
