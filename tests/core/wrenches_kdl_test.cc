// The wrenches in the graph (wrenches.h) against KDL (liborocos-kdl-dev), a peer nobody here
// wrote: random pose trees (each frame on its own body, or on its parent's body), wrenches given
// at random points in random frames, queried at other points in other frames, one wrench, its
// reaction, and net wrenches. KDL's answer: each wrench carried to the world frame with
// Frame * Wrench (KDL::Frame composed along the tree path from the root), summed there, and
// carried to the query's point and axes with Frame::Inverse() * Wrench. Both backends; one-shot
// and compiled queries.
#include <gtest/gtest.h>

#include <kdl/frames.hpp>
#include <random>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "support/tolerance.h"
#include "support/world_scene.h"

namespace semgraph::core {
namespace {

using semgraph::testing::Near;
using semgraph::testing::RandomUnitQuaternion;
using semgraph::testing::RandomVector;
using semgraph::testing::UniformIndex;
using Vec = Eigen::Vector3d;

constexpr int kTrees = 40;
constexpr int kFrames = 10;
constexpr int kQueries = 30;
constexpr double kTol = 1e-8;  // forces O(10), lever arms O(10), trees up to 10 deep

KDL::Vector ToKdl(const Vec& v) { return KDL::Vector(v.x(), v.y(), v.z()); }
Vec FromKdl(const KDL::Vector& v) { return Vec(v.x(), v.y(), v.z()); }
KDL::Frame ToKdl(const Eigen::Quaterniond& q, const Vec& p) {
  return KDL::Frame(KDL::Rotation::Quaternion(q.x(), q.y(), q.z(), q.w()), ToKdl(p));
}

struct Given {
  int on, by, point, frame;  // bodies and frames by index
  Vec f, m;
};

template <class B>
class WrenchesKdl : public ::testing::Test {
 protected:
  std::mt19937_64 rng_{4242};
};
struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(WrenchesKdl, Backends, BackendName);

TYPED_TEST(WrenchesKdl, RandomTreesMatchFrameTimesWrench) {
  auto& rng = this->rng_;
  for (int tree = 0; tree < kTrees; ++tree) {
    SceneGraph<TypeParam> g;
    std::vector<std::string> frame(kFrames), body(kFrames);
    std::vector<int> body_of(kFrames);
    std::vector<KDL::Frame> X_W(kFrames);  // world pose of each frame (frame 0 is the world)
    frame[0] = "f0";
    body[0] = "B0";
    body_of[0] = 0;
    ASSERT_TRUE(g.AddBody("B0"));
    ASSERT_TRUE(g.AddFrame("f0", "B0"));
    for (int i = 1; i < kFrames; ++i) {
      const int parent = UniformIndex(rng, i);
      frame[i] = "f" + std::to_string(i);
      // A third of the frames are on their parent's body (same-body edges).
      body_of[i] = UniformIndex(rng, 3) == 0 ? body_of[parent] : i;
      body[i] = "B" + std::to_string(body_of[i]);
      const Eigen::Quaterniond q = RandomUnitQuaternion(rng);
      const Vec p = RandomVector(rng, 2.0);
      ASSERT_TRUE(
          g.AddPose(PoseSpec::Of(frame[i], body[i]).RelativeTo(frame[parent], body[parent]), q, p));
      X_W[i] = X_W[parent] * ToKdl(q, p);
    }
    // Wrenches between random pairs of distinct bodies, each given once (either direction).
    std::vector<Given> given;
    for (int k = 0; k < 6; ++k) {
      Given w{body_of[UniformIndex(rng, kFrames)],
              body_of[UniformIndex(rng, kFrames)],
              UniformIndex(rng, kFrames),
              UniformIndex(rng, kFrames),
              RandomVector(rng, 10.0),
              RandomVector(rng, 10.0)};
      if (w.on == w.by) continue;
      bool seen = false;
      for (const Given& o : given)
        seen |= (o.on == w.on && o.by == w.by) || (o.on == w.by && o.by == w.on);
      if (seen) continue;
      const std::string on = "B" + std::to_string(w.on), by = "B" + std::to_string(w.by);
      ASSERT_TRUE(g.AddWrench(
          WrenchSpec::On(on).By(by).At(frame[w.point]).ExpressedIn(frame[w.frame]), w.f, w.m));
      given.push_back(w);
    }
    if (given.empty()) continue;
    // KDL: the wrench about the world origin in world axes. G = (axes of [r], origin of e).
    const auto world = [&](const Given& w) {
      const KDL::Frame G(X_W[w.frame].M, X_W[w.point].p);
      return G * KDL::Wrench(ToKdl(w.f), ToKdl(w.m));
    };
    for (int k = 0; k < kQueries; ++k) {
      const int e = UniformIndex(rng, kFrames), r = UniformIndex(rng, kFrames);
      const Given& w =
          given[static_cast<std::size_t>(UniformIndex(rng, static_cast<int>(given.size())))];
      const KDL::Frame Q(X_W[r].M, X_W[e].p);  // the query's axes and point
      const std::string on = "B" + std::to_string(w.on), by = "B" + std::to_string(w.by);
      // The stored wrench and its reaction.
      const KDL::Wrench kW = Q.Inverse() * world(w);
      auto W = g.GetWrench(WrenchSpec::On(on).By(by).At(frame[e]).ExpressedIn(frame[r]));
      ASSERT_TRUE(W) << g.Describe(W.error(), WrenchSpec::On(on).By(by));
      EXPECT_TRUE(Near(W->force, FromKdl(kW.force), kTol));
      EXPECT_TRUE(Near(W->moment, FromKdl(kW.torque), kTol));
      auto R = g.GetWrench(WrenchSpec::On(by).By(on).At(frame[e]).ExpressedIn(frame[r]));
      ASSERT_TRUE(R);
      EXPECT_TRUE(Near(R->force, -FromKdl(kW.force), kTol));
      EXPECT_TRUE(Near(R->moment, -FromKdl(kW.torque), kTol));
      // The net wrench on w.on: every given wrench on it, minus every given wrench by it.
      KDL::Wrench net = KDL::Wrench::Zero();
      for (const Given& o : given) {
        if (o.on == w.on) net = net + world(o);
        if (o.by == w.on) net = net - world(o);
      }
      net = Q.Inverse() * net;
      const WrenchSpec net_spec = WrenchSpec::On(on).At(frame[e]).ExpressedIn(frame[r]);
      auto N = g.GetWrench(net_spec);
      ASSERT_TRUE(N);
      EXPECT_TRUE(Near(N->force, FromKdl(net.force), kTol));
      EXPECT_TRUE(Near(N->moment, FromKdl(net.torque), kTol));
      auto compiled = g.CompileWrench(net_spec);
      ASSERT_TRUE(compiled);
      Vec f, m;
      ASSERT_EQ(compiled->Evaluate(f, m), ErrorCode::kOk);
      EXPECT_TRUE(Near(f, FromKdl(net.force), kTol));
      EXPECT_TRUE(Near(m, FromKdl(net.torque), kTol));
    }
  }
}

}  // namespace
}  // namespace semgraph::core
