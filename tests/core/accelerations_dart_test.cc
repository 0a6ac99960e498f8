// Accelerations in the scene graph (scene_graph.h "accelerations", accelerations.h) against
// DART (libdart-dev), a peer nobody here wrote. DART builds a random frame tree whose frames
// move relative to their parents (SimpleFrame::setClassicDerivatives: v, w, classical a and
// alpha of the child's origin relative to the parent, in the parent's coordinates) and answers,
// for any two frames, the classical acceleration of any point of one relative to the other in
// any frame's coordinates (getLinearAcceleration, getAngularAcceleration).
//
// The graph gets the same tree: frame f<i> on body B<i>, a pose edge f<p> -> f<i>, and one twist
// edge per DART edge with its acceleration, given four ways at random: along the edge as DART
// has it (AddTwist with an acceleration, in [f<p>]); against it (the parent relative to the
// child at f<p>'s origin in [f<i>], on a frame g<i> of B<p> at f<p>, the numbers read from
// DART); or the twist alone followed by AddAcceleration at a random frame's origin in a random
// frame (numbers from DART), of B<i> wrt B<p> or of B<p> wrt B<i> (against the edge). Queries at
// random point frames (fixed on random bodies), for random pairs of bodies, in random frames,
// are compared with DART's answers: composition, Coriolis terms, inversion, changes of point and
// frame, and the conversion of the adds are all checked against the peer.
#include <gtest/gtest.h>

#include <dart/dynamics/Frame.hpp>
#include <dart/dynamics/SimpleFrame.hpp>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "support/tolerance.h"
#include "support/world_scene.h"

namespace semgraph::core {
namespace {

using dart::dynamics::Frame;
using dart::dynamics::SimpleFrame;
using semgraph::testing::Near;
using semgraph::testing::RandomUnitQuaternion;
using semgraph::testing::RandomVector;
using Vec = Eigen::Vector3d;

// O(1) values over a handful of edges: 1e-9 leaves margin over rounding and catches any
// missing term (each of order 0.1 and up).
constexpr double kTol = 1e-9;

std::string F(int i) { return "f" + std::to_string(i); }
std::string Bd(int i) { return "B" + std::to_string(i); }
std::string Q(int j) { return "q" + std::to_string(j); }

/// A random DART frame tree (node 0 = DART's world) and the same tree in a scene graph.
template <class B>
class Scene {
 public:
  Scene(std::uint64_t seed, int nodes, bool chain, int points) : rng_(seed) {
    frames_.push_back(Frame::World());
    parent_.push_back(-1);
    EXPECT_TRUE(g_.AddBody(Bd(0)));
    EXPECT_TRUE(g_.AddFrame(F(0), Bd(0)));
    for (int i = 1; i < nodes; ++i) {
      const int p = chain ? i - 1 : static_cast<int>(rng_() % static_cast<std::uint64_t>(i));
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.linear() = RandomUnitQuaternion(rng_).toRotationMatrix();
      X.translation() = RandomVector(rng_, 1.0);
      auto f = std::make_shared<SimpleFrame>(frames_[p], F(i), X);
      const Vec v = RandomVector(rng_, 1.0), w = RandomVector(rng_, 1.0),
                a = RandomVector(rng_, 1.0), alpha = RandomVector(rng_, 1.0);
      f->setClassicDerivatives(v, w, a, alpha);
      frames_.push_back(f.get());
      owned_.push_back(std::move(f));
      parent_.push_back(p);
      EXPECT_TRUE(g_.AddPose(PoseSpec::Of(F(i), Bd(i)).RelativeTo(F(p), Bd(p)),
                             Eigen::Matrix3d(X.linear()), Vec(X.translation())));
      AddEdge(i, p, v, w, a, alpha);
    }
    // Point frames fixed on random bodies.
    for (int j = 0; j < points; ++j) {
      const int k = Node();
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.linear() = RandomUnitQuaternion(rng_).toRotationMatrix();
      X.translation() = RandomVector(rng_, 1.5);
      EXPECT_TRUE(g_.AddPose(PoseSpec::Of(Q(j), Bd(k)).RelativeTo(F(k), Bd(k)),
                             Eigen::Matrix3d(X.linear()), Vec(X.translation())));
      point_world_.push_back(frames_[k]->getWorldTransform() * X);
    }
  }

  int size() const { return static_cast<int>(frames_.size()); }
  int parent(int i) const { return parent_[i]; }
  int Node() { return static_cast<int>(rng_() % static_cast<std::uint64_t>(size())); }
  std::mt19937_64& rng() { return rng_; }
  const SceneGraph<B>& graph() const { return g_; }
  int ways[4] = {0, 0, 0, 0};  // edges given along, against, by AddAcceleration along, against

  /// GetAcceleration(point q<j>|B<C>, B<D>, [f<r>]) against DART.
  void ExpectAsDart(int j, int C, int D, int r) {
    SCOPED_TRACE("q" + std::to_string(j) + "|B" + std::to_string(C) + " wrt B" + std::to_string(D) +
                 " in [f" + std::to_string(r) + "]");
    const std::string q = Q(j), c = Bd(C), d = Bd(D), fr = F(r);
    const TwistSpec spec = TwistSpec::Of(q, c).RelativeTo(d).ExpressedIn(fr);
    auto A = g_.GetAcceleration(spec);
    ASSERT_TRUE(A) << g_.Describe(A.error(), spec);
    const Vec p_We = point_world_[j].translation();
    const Eigen::Isometry3d X_WC = frames_[C]->getWorldTransform();
    const Vec offset = X_WC.linear().transpose() * (p_We - X_WC.translation());
    EXPECT_TRUE(
        Near(A->linear, frames_[C]->getLinearAcceleration(offset, frames_[D], frames_[r]), kTol));
    EXPECT_TRUE(Near(A->angular, frames_[C]->getAngularAcceleration(frames_[D], frames_[r]), kTol));
    auto lin = g_.GetLinearAcceleration(spec);
    ASSERT_TRUE(lin);
    EXPECT_EQ(lin->value, A->linear);
    auto ang = g_.GetAngularAcceleration(TwistSpec::Of("", c).RelativeTo(d).ExpressedIn(fr));
    ASSERT_TRUE(ang) << g_.Describe(ang.error(), spec);
    EXPECT_TRUE(Near(ang->value, A->angular, kTol));
  }

 private:
  // The twist edge of DART edge p -> i, with its acceleration, in one of four ways.
  void AddEdge(int i, int p, const Vec& v, const Vec& w, const Vec& a, const Vec& alpha) {
    const int way = static_cast<int>(rng_() % 4);
    ++ways[way];
    const std::string fi = F(i), fp = F(p), bi = Bd(i), bp = Bd(p);
    if (way == 0) {  // along: at f<i>'s origin, in [f<p>], as DART has it
      EXPECT_TRUE(g_.AddTwist(TwistSpec::Of(fi, bi).RelativeTo(bp).ExpressedIn(fp), v, w,
                              AccelerationInput{a, alpha}));
    } else if (way == 1) {  // against: B<p> relative to B<i> at f<p>'s origin, in [f<i>]
      // On a frame g<i> of B<p> at f<p> (W1: f<p> may have a twist parent already).
      const std::string gi = "g" + std::to_string(i);
      EXPECT_TRUE(g_.AddPose(PoseSpec::Of(gi, bp).RelativeTo(fp, bp),
                             Eigen::Quaterniond::Identity(), Vec::Zero()));
      const Frame* c = frames_[p];
      const Frame* d = frames_[i];
      EXPECT_TRUE(g_.AddTwist(TwistSpec::Of(gi, bp).RelativeTo(bi).ExpressedIn(fi),
                              c->getLinearVelocity(Vec::Zero(), d, d), c->getAngularVelocity(d, d),
                              AccelerationInput{c->getLinearAcceleration(Vec::Zero(), d, d),
                                                c->getAngularAcceleration(d, d)}));
    } else {  // the twist alone, then the acceleration at a random frame's origin in [f<r>]:
      // of B<i> wrt B<p> (way 2, along the edge) or of B<p> wrt B<i> (way 3, against it).
      EXPECT_TRUE(g_.AddTwist(TwistSpec::Of(fi, bi).RelativeTo(bp).ExpressedIn(fp), v, w));
      const int k = static_cast<int>(rng_() % static_cast<std::uint64_t>(size()));
      const int r = static_cast<int>(rng_() % static_cast<std::uint64_t>(size()));
      const int of = way == 2 ? i : p, wrt = way == 2 ? p : i;
      const Eigen::Isometry3d X_WO = frames_[of]->getWorldTransform();
      const Vec offset = X_WO.linear().transpose() *
                         (frames_[k]->getWorldTransform().translation() - X_WO.translation());
      const std::string fk = F(k), fr = F(r), b_of = Bd(of), b_wrt = Bd(wrt);
      const TwistSpec spec = TwistSpec::Of(fk, b_of).RelativeTo(b_wrt).ExpressedIn(fr);
      auto added = g_.AddAcceleration(
          spec, frames_[of]->getLinearAcceleration(offset, frames_[wrt], frames_[r]),
          frames_[of]->getAngularAcceleration(frames_[wrt], frames_[r]));
      EXPECT_TRUE(added) << ToString(added.error().code) << ": " << added.error().message;
    }
  }

  std::mt19937_64 rng_;
  SceneGraph<B> g_;
  std::vector<Frame*> frames_;
  std::vector<std::shared_ptr<SimpleFrame>> owned_;
  std::vector<int> parent_;
  std::vector<Eigen::Isometry3d> point_world_;
};

template <class B>
class AccelerationsDart : public ::testing::Test {};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(AccelerationsDart, Backends);

TYPED_TEST(AccelerationsDart, EveryEdgeInBothDirectionsAtRandomPointsInRandomFrames) {
  int ways[4] = {0, 0, 0, 0};
  for (std::uint64_t seed = 1; seed <= 15; ++seed) {
    Scene<TypeParam> s(seed, 8, /*chain=*/false, 6);
    for (int child = 1; child < s.size(); ++child) {
      for (int k = 0; k < 3; ++k) {
        const int j = static_cast<int>(s.rng()() % 6), r = s.Node();
        s.ExpectAsDart(j, child, s.parent(child), r);
        s.ExpectAsDart(j, s.parent(child), child, r);
      }
    }
    for (int w = 0; w < 4; ++w) ways[w] += s.ways[w];
  }
  for (int w = 0; w < 4; ++w) EXPECT_GT(ways[w], 10) << "way " << w;
}

TYPED_TEST(AccelerationsDart, RandomPairsInRandomTrees) {
  for (std::uint64_t seed = 100; seed < 115; ++seed) {
    Scene<TypeParam> s(seed, 10, /*chain=*/false, 8);
    for (int k = 0; k < 30; ++k) {
      const int j = static_cast<int>(s.rng()() % 8);
      const int C = s.Node(), D = s.Node(), r = s.Node();
      s.ExpectAsDart(j, C, D, r);
    }
  }
}

TYPED_TEST(AccelerationsDart, BothEndsOfLongChains) {
  for (std::uint64_t seed = 200; seed < 210; ++seed) {
    Scene<TypeParam> s(seed, 9, /*chain=*/true, 4);
    const int tip = s.size() - 1;
    for (int k = 0; k < 5; ++k) {
      const int j = static_cast<int>(s.rng()() % 4), r = s.Node();
      s.ExpectAsDart(j, tip, 0, r);
      s.ExpectAsDart(j, 0, tip, r);
      s.ExpectAsDart(j, tip, 1, r);
      s.ExpectAsDart(j, 2, tip - 1, r);
    }
  }
}

}  // namespace
}  // namespace semgraph::core
