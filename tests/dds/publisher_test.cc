// Publisher (semgraph/dds/publisher.h), WaitForMirrors: without a mirror it times out and
// names the counts; once a mirror exists (here in the same process) every writer has matched
// it, and a value set then is in the mirror's graph.
#include "semgraph/dds/publisher.h"

#include <gtest/gtest.h>

#include <chrono>

#include "dds_isolation.h"
#include "scenes.h"
#include "semgraph/dds/mirror.h"

namespace semgraph::dds_test {
namespace {

using namespace std::chrono_literals;

TEST(PublisherTest, WaitForMirrorsTimesOutWithoutOneAndReturnsOnceOneMatched) {
  constexpr std::uint32_t kDomain = 27;
  core::SceneGraph<> g;
  ASSERT_TRUE(BuildRobot(g));
  auto pub = dds::Publisher::Create(g, {"arm", kDomain});
  ASSERT_TRUE(pub) << pub.error();
  const auto t0 = std::chrono::steady_clock::now();
  const auto none = (*pub)->WaitForMirrors(1, 150ms);
  ASSERT_FALSE(none);
  EXPECT_GE(std::chrono::steady_clock::now() - t0, 150ms);
  EXPECT_EQ(none.error(), "0 mirror(s) matched of 1 expected within 150 ms");

  auto mirror = dds::Mirror::Create({"m", kDomain, {}, {}, {}, {}});
  ASSERT_TRUE(mirror) << mirror.error();
  ASSERT_TRUE((*pub)->WaitForMirrors(1, 20s));
  ASSERT_TRUE((*pub)->PublishStructure());
  auto edge = g.FindPoseEdge("l1", "b");
  ASSERT_TRUE(edge);
  ASSERT_EQ((*pub)->SetPose(*edge, Rz(0.25), {0, 0, 0.5}), base::ErrorCode::kOk);
  // The mirror's graph: l1 wrt b is the value set (Rz(0.25), (0, 0, 0.5)).
  const auto has = [&] {
    bool ok = false;
    (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
      const auto X = m.GetPose(core::PoseSpec::Of("l1").RelativeTo("b"));
      ok = X && (X->value.translation - Eigen::Vector3d(0, 0, 0.5)).norm() < 1e-15 &&
           X->value.rotation.angularDistance(Rz(0.25)) < 1e-15;
    });
    return ok;
  };
  EXPECT_TRUE((*mirror)->WaitUntil(has, 20s));
}

}  // namespace
}  // namespace semgraph::dds_test
