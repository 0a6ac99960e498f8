// The acceleration operations of coord/dynamics_operations.h against DART (libdart-dev), a peer
// nobody here wrote. DART builds frame trees whose frames move relative to their parents
// (SimpleFrame::setClassicDerivatives: v, w, classical a, alpha of the child's origin relative
// to the parent, in the parent's coordinates) and answers, for any two frames, the classical
// acceleration of any point of one relative to the other in any frame's coordinates
// (getLinearAcceleration(offset, relativeTo, inCoordinatesOf), getAngularAcceleration).
//
// semgraph's side uses only the edges' values as given to DART (and the frames' poses, for the
// lever arms and rotations): each edge's acceleration and twist are re-expressed in [r]
// (ChangeCoordinateFrame), moved to the point e (ChangePoint, with w for the centripetal term),
// inverted where the path runs against the edge (Inverse: not a negation), and composed along
// the path (Compose, with the Coriolis terms), every step semantically checked: the result's
// semantics must come out as AccelerationCoord(e|C, D, [r]).
//
// Trees: random trees and chains, every edge in both directions, random pairs of frames, random
// points, random coordinate frames; the world frame is one of the nodes.
#include <gtest/gtest.h>

#include <dart/dynamics/Frame.hpp>
#include <dart/dynamics/SimpleFrame.hpp>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "semgraph/coord/dynamics_operations.h"
#include "semgraph/coord/quaternion_backend.h"
#include "semgraph/semantics/describe.h"
#include "support/tolerance.h"
#include "support/world_scene.h"

namespace semgraph::coord {
namespace {

using dart::dynamics::Frame;
using dart::dynamics::SimpleFrame;
using semantics::Body;
using semantics::NameTable;
using semantics::OrientationFrame;
using semantics::Point;
using semgraph::testing::Near;
using semgraph::testing::RandomUnitQuaternion;
using semgraph::testing::RandomVector;
using Vec = Eigen::Vector3d;
using Q = QuaternionBackend;

// Values are O(1) (unit rotations, lever arms within a few metres, rates within [-1, 1] per
// edge, a handful of edges): 1e-9 leaves orders of margin over rounding and catches any missing
// term (each is of order 0.1 and up).
constexpr double kTol = 1e-9;

/// A random frame tree in DART and its names in semgraph. Node 0 is DART's world frame; node i
/// has frame "f<i>" (origin point and axes) on body "B<i>", and a parent parent_[i] < i.
class Tree {
 public:
  Tree(std::uint64_t seed, int nodes, bool chain) : rng_(seed) {
    frames_.push_back(Frame::World());
    parent_.push_back(-1);
    for (int i = 0; i < nodes; ++i) Intern(i);
    e_ = Point(*names_.Intern("e"));
    q_ = Point(*names_.Intern("q"));
    for (int i = 1; i < nodes; ++i) {
      const int p = chain ? i - 1 : static_cast<int>(rng_() % static_cast<std::uint64_t>(i));
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.linear() = RandomUnitQuaternion(rng_).toRotationMatrix();
      X.translation() = RandomVector(rng_, 1.0);
      auto f = std::make_shared<SimpleFrame>(frames_[p], "f" + std::to_string(i), X);
      Edge edge{RandomVector(rng_, 1.0), RandomVector(rng_, 1.0), RandomVector(rng_, 1.0),
                RandomVector(rng_, 1.0)};
      f->setClassicDerivatives(edge.v, edge.w, edge.a, edge.alpha);
      frames_.push_back(f.get());
      owned_.push_back(std::move(f));
      parent_.push_back(p);
      edges_.push_back(edge);
    }
  }

  int size() const { return static_cast<int>(frames_.size()); }
  int parent(int i) const { return parent_[i]; }
  std::mt19937_64& rng() { return rng_; }
  const NameTable& names() const { return names_; }
  Point e() const { return e_; }
  Point q() const { return q_; }
  Body body(int i) const { return bodies_[i]; }
  Point origin(int i) const { return frame_names_[i].origin(); }
  OrientationFrame axes(int i) const { return frame_names_[i].axes(); }
  const Frame* frame(int i) const { return frames_[i]; }
  Eigen::Matrix3d R_W(int i) const { return frames_[i]->getWorldTransform().linear(); }
  Vec p_W(int i) const { return frames_[i]->getWorldTransform().translation(); }

  /// The acceleration and twist of the edge into `child` (child relative to its parent), at
  /// the point e (world position p_We), in [r]: the edge's values as given to DART, moved by
  /// the checked operations.
  struct Motion {
    Acceleration A;
    Twist V;
  };
  Motion EdgeAt(int child, const Vec& p_We, int r) const {
    const int p = parent_[child];
    const Edge& edge = edges_[child - 1];
    // As given: at the child's origin, in the parent's axes.
    const Acceleration A_P =
        *MakeAcceleration({origin(child), body(child), body(p), axes(p)}, edge.a, edge.alpha);
    const Twist V_P = *MakeTwist({origin(child), body(child), body(p), axes(p)}, edge.v, edge.w);
    // [p] wrt [r], expressed in [r]: R[r<-p].
    const Eigen::Matrix3d R_rp = R_W(r).transpose() * R_W(p);
    const auto O_rp = *MakeOrientation<Q>({axes(p), body(p), axes(r), body(r), axes(r)}, R_rp);
    const Acceleration A_r = Must(ChangeCoordinateFrame(A_P, O_rp));
    const Twist V_r = Must(ChangeCoordinateFrame(V_P, O_rp));
    // The child's origin wrt e, in [r].
    const Position p_e_child = *MakePosition({origin(child), body(child), e_, body(child), axes(r)},
                                             R_W(r).transpose() * (p_W(child) - p_We));
    return {Must(ChangePoint(A_r, p_e_child, AngularOf(V_r))), Must(ChangePoint(V_r, p_e_child))};
  }

  /// AccelerationCoord(e|C, D, [r]) and its twist, along the tree path from C up to the common
  /// ancestor and down to D.
  Motion Along(int C, int D, const Vec& p_We, int r) const {
    std::vector<int> up, down;  // edges (by child) from C upwards, from D upwards
    for (int i = C; i != -1; i = parent_[i]) up.push_back(i);
    for (int i = D; i != -1; i = parent_[i]) down.push_back(i);
    while (!up.empty() && !down.empty() && up.back() == down.back()) {
      up.pop_back();
      down.pop_back();
    }
    // Start from C relative to C: zero.
    Motion m{*MakeAcceleration({e_, body(C), body(C), axes(r)}, Vec::Zero(), Vec::Zero()),
             *MakeTwist({e_, body(C), body(C), axes(r)}, Vec::Zero(), Vec::Zero())};
    const auto step = [&](const Motion& next) {  // m = C rel X, next = X rel Y -> C rel Y
      const Acceleration A = Must(Compose(m.A, next.A, m.V, AngularOf(next.V)));
      m = {A, Must(Compose(m.V, next.V))};
    };
    for (int child : up) step(EdgeAt(child, p_We, r));  // child rel parent
    for (auto it = down.rbegin(); it != down.rend(); ++it) {
      const Motion edge = EdgeAt(*it, p_We, r);  // child rel parent: traversed against it
      step({Must(Inverse(edge.A, edge.V)), Inverse(edge.V)});
    }
    return m;
  }

  template <class T>
  T Must(const Result<T>& r) const {
    if (!r) {
      ADD_FAILURE() << "refused: " << Describe(r.error(), names_);
      return T{};
    }
    return *r;
  }

 private:
  struct Edge {
    Vec v, w, a, alpha;
  };
  void Intern(int i) {
    frame_names_.emplace_back(*names_.Intern("f" + std::to_string(i)));
    bodies_.emplace_back(*names_.Intern("B" + std::to_string(i)));
  }

  std::mt19937_64 rng_;
  NameTable names_;
  Point e_, q_;
  std::vector<semantics::Frame> frame_names_;
  std::vector<Body> bodies_;
  std::vector<Frame*> frames_;
  std::vector<std::shared_ptr<SimpleFrame>> owned_;
  std::vector<int> parent_;
  std::vector<Edge> edges_;
};

/// Compares semgraph's AccelerationCoord(e|C, D, [r]) with DART's answer for the same query.
void ExpectAsDart(Tree& t, int C, int D, const Vec& p_We, int r) {
  SCOPED_TRACE("C = f" + std::to_string(C) + ", D = f" + std::to_string(D) + ", [r] = f" +
               std::to_string(r));
  const Tree::Motion m = t.Along(C, D, p_We, r);
  ASSERT_EQ(m.A.semantics, (AccelerationSemantics{t.e(), t.body(C), t.body(D), t.axes(r)}))
      << Describe(m.A.semantics, t.names());
  const Vec offset = t.R_W(C).transpose() * (p_We - t.p_W(C));  // e in C's coordinates
  const Vec a = t.frame(C)->getLinearAcceleration(offset, t.frame(D), t.frame(r));
  const Vec alpha = t.frame(C)->getAngularAcceleration(t.frame(D), t.frame(r));
  EXPECT_TRUE(Near(m.A.linear, a, kTol));
  EXPECT_TRUE(Near(m.A.angular, alpha, kTol));
  // The twist the composition carried along agrees with DART too.
  EXPECT_TRUE(
      Near(m.V.linear, t.frame(C)->getLinearVelocity(offset, t.frame(D), t.frame(r)), kTol));
  EXPECT_TRUE(Near(m.V.angular, t.frame(C)->getAngularVelocity(t.frame(D), t.frame(r)), kTol));
}

int RandomNode(Tree& t) {
  return static_cast<int>(t.rng()() % static_cast<std::uint64_t>(t.size()));
}

TEST(DynamicsDart, EveryEdgeInBothDirectionsAtRandomPointsInRandomFrames) {
  int checked = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    Tree t(seed, 8, /*chain=*/false);
    for (int child = 1; child < t.size(); ++child) {
      for (int k = 0; k < 3; ++k) {
        const Vec p_We = RandomVector(t.rng(), 2.0);
        const int r = RandomNode(t);
        ExpectAsDart(t, child, t.parent(child), p_We, r);
        ExpectAsDart(t, t.parent(child), child, p_We, r);
        checked += 2;
      }
    }
  }
  EXPECT_EQ(checked, 20 * 7 * 3 * 2);
}

TEST(DynamicsDart, RandomPairsInRandomTrees) {
  for (std::uint64_t seed = 100; seed < 120; ++seed) {
    Tree t(seed, 10, /*chain=*/false);
    for (int k = 0; k < 30; ++k) {
      ExpectAsDart(t, RandomNode(t), RandomNode(t), RandomVector(t.rng(), 2.0), RandomNode(t));
    }
  }
}

TEST(DynamicsDart, BothEndsOfLongChains) {
  for (std::uint64_t seed = 200; seed < 210; ++seed) {
    Tree t(seed, 9, /*chain=*/true);
    const int tip = t.size() - 1;
    for (int k = 0; k < 5; ++k) {
      const Vec p_We = RandomVector(t.rng(), 3.0);
      const int r = RandomNode(t);
      ExpectAsDart(t, tip, 0, p_We, r);  // the tip relative to the world, and back
      ExpectAsDart(t, 0, tip, p_We, r);
      ExpectAsDart(t, tip, 1, p_We, r);
      ExpectAsDart(t, 2, tip - 1, p_We, r);
    }
  }
}

TEST(DynamicsDart, ChangesOfPointAndFrameOfAComposedAcceleration) {
  // One acceleration, computed at C's origin in C's axes, then moved to random points and
  // re-expressed in random frames by the checked operations alone.
  for (std::uint64_t seed = 300; seed < 310; ++seed) {
    Tree t(seed, 8, /*chain=*/false);
    for (int k = 0; k < 20; ++k) {
      const int C = RandomNode(t), D = RandomNode(t), r = RandomNode(t);
      const Tree::Motion m = t.Along(C, D, t.p_W(C), C);  // at e = C's origin, in [C]
      const Vec p_We = RandomVector(t.rng(), 2.0);
      const Eigen::Matrix3d R_rc = t.R_W(r).transpose() * t.R_W(C);
      const auto O_rc =
          *MakeOrientation<Q>({t.axes(C), t.body(C), t.axes(r), t.body(r), t.axes(r)}, R_rc);
      const Acceleration A_r = t.Must(ChangeCoordinateFrame(m.A, O_rc));
      const AngularVelocity w_r = t.Must(ChangeCoordinateFrame(AngularOf(m.V), O_rc));
      // The composition ran at e = C's origin; move the result to q.
      const Point q = t.q();
      const Position p_qe = *MakePosition({t.e(), t.body(C), q, t.body(C), t.axes(r)},
                                          t.R_W(r).transpose() * (t.p_W(C) - p_We));
      const Acceleration A_q = t.Must(ChangePoint(A_r, p_qe, w_r));
      ASSERT_EQ(A_q.semantics, (AccelerationSemantics{q, t.body(C), t.body(D), t.axes(r)}));
      const Vec offset = t.R_W(C).transpose() * (p_We - t.p_W(C));
      EXPECT_TRUE(Near(A_q.linear,
                       t.frame(C)->getLinearAcceleration(offset, t.frame(D), t.frame(r)), kTol));
      EXPECT_TRUE(
          Near(A_q.angular, t.frame(C)->getAngularAcceleration(t.frame(D), t.frame(r)), kTol));
    }
  }
}

}  // namespace
}  // namespace semgraph::coord
