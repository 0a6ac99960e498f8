// Mode `linear` equals tf2's BufferCore::lookupTransform on the same random stamped data
// (docs/time.md): interpolation at random times, latest common time (tf2's ros::Time(0)), and the
// fixed-frame (time travel) variant. tf2 is the peer: Debian's libtf2-dev, a test-only
// dependency (skipped when it is not installed).
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "support/tolerance.h"
#if defined(SEMGRAPH_HAVE_TF2)
#include "tf2_time_peer.h"
#endif

namespace semgraph::core {
namespace {

#if defined(SEMGRAPH_HAVE_TF2)
using semgraph::testing::ExpectNear;
using semgraph_test::tf2time::Pose7;
using Graph = SceneGraph<coord::QuaternionBackend>;

struct Scene {
  Graph g = *Graph::Create(
      TimeOptions{Duration::Seconds(100), Interpolation::kLinear, DuplicatePolicy::kReplace, 1024});
  semgraph_test::tf2time::Buffer tf;
  int frames = 0;
};

// A random tree f0 .. f(n-1) (parent of fi: a random earlier frame), each frame on its own body;
// every link stamped with 3..8 random samples in [1 s, 2 s] (first exactly 1 s, last in
// [1.8, 2] s), or static for every fourth link.
void Build(Scene& s, std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  s.frames = n;
  ASSERT_TRUE(s.g.AddBody("B0").has_value());
  ASSERT_TRUE(s.g.AddFrame("f0", "B0").has_value());
  for (int i = 1; i < n; ++i) {
    const int parent = static_cast<int>(rng() % static_cast<unsigned>(i));
    const std::string f = "f" + std::to_string(i), p = "f" + std::to_string(parent),
                      body = "B" + std::to_string(i);
    const bool is_static = i % 4 == 0;
    const int samples = is_static ? 1 : 3 + static_cast<int>(rng() % 6);
    std::vector<std::int64_t> stamps{1000000000};
    for (int k = 1; k < samples; ++k)
      stamps.push_back(1000000000 + static_cast<std::int64_t>(rng() % 800000000));
    if (samples > 1) stamps.push_back(1800000000 + static_cast<std::int64_t>(rng() % 200000001));
    for (std::int64_t t : stamps) {
      const Eigen::Quaterniond q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
      const Eigen::Vector3d x(u(rng), u(rng), u(rng));
      const PoseSpec spec = PoseSpec::Of(f, body).RelativeTo(p);
      if (is_static) {
        ASSERT_TRUE(s.g.AddPose(spec, q, x).has_value());
      } else {
        ASSERT_TRUE(s.g.AddPose(spec, q, x, Stamp::Nanoseconds(t)).has_value());
      }
      ASSERT_TRUE(
          s.tf.Set(p, f, Pose7{q.w(), q.x(), q.y(), q.z(), x.x(), x.y(), x.z()}, t, is_static));
    }
  }
}

void ExpectSame(const Graph::Pose& X, const Pose7& Y) {
  ExpectNear(X.value.rotation, Eigen::Quaterniond(Y.qw, Y.qx, Y.qy, Y.qz), 1e-9);
  ExpectNear(X.value.translation, Eigen::Vector3d(Y.x, Y.y, Y.z), 1e-9);
}

TEST(TimeTf2Test, LinearModeEqualsLookupTransform) {
  std::mt19937_64 rng(2024);
  for (int scene = 0; scene < 10; ++scene) {
    Scene s;
    Build(s, rng, 12);
    int compared = 0;
    for (int k = 0; k < 60; ++k) {
      const std::string a = "f" + std::to_string(rng() % 12), b = "f" + std::to_string(rng() % 12);
      const std::int64_t t = 1000000000 + static_cast<std::int64_t>(rng() % 800000001);
      Pose7 Y;
      ASSERT_TRUE(s.tf.Lookup(b, a, t, Y));
      auto X = s.g.GetPose(PoseSpec::Of(a).RelativeTo(b), At{Stamp::Nanoseconds(t)});
      ASSERT_TRUE(X.has_value()) << s.g.Describe(X.error());
      ExpectSame(X->value, Y);
      // Compiled, same policy.
      auto c = s.g.CompilePose(PoseSpec::Of(a).RelativeTo(b));
      Graph::Backend::PoseCoords Z;
      TimeReport r;
      ASSERT_EQ(c->Evaluate(Z, At{Stamp::Nanoseconds(t)}, r), ErrorCode::kOk);
      ExpectSame(Graph::Pose{X->value.semantics, Z}, Y);
      ++compared;
    }
    EXPECT_EQ(compared, 60);
  }
}

TEST(TimeTf2Test, LatestCommonEqualsTimeZero) {
  std::mt19937_64 rng(77);
  for (int scene = 0; scene < 10; ++scene) {
    Scene s;
    Build(s, rng, 10);
    for (int k = 0; k < 40; ++k) {
      const std::string a = "f" + std::to_string(rng() % 10), b = "f" + std::to_string(rng() % 10);
      Pose7 Y;
      std::int64_t tf_stamp = 0;
      ASSERT_TRUE(s.tf.Lookup(b, a, 0, Y, &tf_stamp));
      auto X = s.g.GetPose(PoseSpec::Of(a).RelativeTo(b), LatestCommon{});
      ASSERT_TRUE(X.has_value());
      ExpectSame(X->value, Y);
      if (X->time.time) {
        EXPECT_EQ(X->time.time->nanoseconds(), tf_stamp) << a << " wrt " << b;
      }
    }
  }
}

TEST(TimeTf2Test, TimeTravelEqualsTheFixedFrameLookup) {
  std::mt19937_64 rng(99);
  for (int scene = 0; scene < 10; ++scene) {
    Scene s;
    Build(s, rng, 10);
    for (int k = 0; k < 40; ++k) {
      const std::string a = "f" + std::to_string(rng() % 10), b = "f" + std::to_string(rng() % 10),
                        x = "f" + std::to_string(rng() % 10);
      const std::int64_t t1 = 1000000000 + static_cast<std::int64_t>(rng() % 800000001);
      const std::int64_t t2 = 1000000000 + static_cast<std::int64_t>(rng() % 800000001);
      Pose7 Y;
      ASSERT_TRUE(s.tf.LookupFixed(b, t2, a, t1, x, Y));
      auto X = s.g.GetPose(PoseSpec::Of(a).RelativeTo(b),
                           TimeTravel{Stamp::Nanoseconds(t1), Stamp::Nanoseconds(t2), x});
      ASSERT_TRUE(X.has_value()) << s.g.Describe(X.error());
      ExpectSame(X->value, Y);
    }
  }
}
#else
TEST(TimeTf2Test, SkippedWithoutTf2) { GTEST_SKIP() << "libtf2-dev not found at configure time"; }
#endif

}  // namespace
}  // namespace semgraph::core
