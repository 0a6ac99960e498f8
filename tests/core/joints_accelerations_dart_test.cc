// Joint accelerations (joints.h, scene_graph.h SetJoints with accelerations, SetJointState with
// qddot) against DART (libdart-dev), a peer nobody here wrote. DART builds a Skeleton: a welded
// base and a serial chain of revolute and prismatic joints with random origins and axes; its
// state (q, qdot, qddot) gives, by DART's own forward kinematics, the classical acceleration of
// any point of any link relative to any other link in any frame's coordinates
// (BodyNode::getLinearAcceleration with an offset, getAngularAcceleration).
//
// The graph gets the same chain as joints: link frame l<i> on body L<i>, joint j<i> from l<i-1>
// to l<i> with X_origin = DART's parent-to-joint transform and the same axis (the joint frame is
// the child link's frame in both). Point frames e<k> are fixed on random links (SimpleFrames in
// DART). The state is given by name (SetJoints) or through a group (SetJointState with qddot),
// and queries AccelerationCoord(e|C, D, [r]) for random links C, D (either order: inversions),
// random points e (on C or not: the point of C that coincides with e) and random frames r are
// compared with DART's answers. This checks the edge form of each joint's acceleration (a =
// axis qddot for prismatic joints, alpha = axis qddot for revolute ones) and, through the
// composition, that the twist stored beside it is the joint's current one.
#include <gtest/gtest.h>

#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/PrismaticJoint.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/SimpleFrame.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/WeldJoint.hpp>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "support/tolerance.h"
#include "support/world_scene.h"

namespace semgraph::core {
namespace {

using dart::dynamics::BodyNode;
using dart::dynamics::Frame;
using dart::dynamics::PrismaticJoint;
using dart::dynamics::RevoluteJoint;
using dart::dynamics::SimpleFrame;
using dart::dynamics::Skeleton;
using dart::dynamics::WeldJoint;
using semgraph::testing::Near;
using semgraph::testing::RandomUnitQuaternion;
using semgraph::testing::RandomVector;
using Vec = Eigen::Vector3d;

// O(1) lengths, rates and accelerations over up to 7 joints: 1e-9 leaves margin over rounding
// and catches any missing term (each of order 0.1 and up).
constexpr double kTol = 1e-9;

std::string L(int i) { return "l" + std::to_string(i); }
std::string Bd(int i) { return "L" + std::to_string(i); }
std::string J(int i) { return "j" + std::to_string(i); }
std::string E(int k) { return "e" + std::to_string(k); }

double Uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

/// A random serial chain in DART and, as joints, in a scene graph.
template <class B>
class Chain {
 public:
  Chain(std::uint64_t seed, int joints, int points) : rng_(seed), skel_(Skeleton::create("chain")) {
    links_.push_back(skel_->createJointAndBodyNodePair<WeldJoint>(nullptr).second);
    EXPECT_TRUE(g_.AddBody(Bd(0)));
    EXPECT_TRUE(g_.AddFrame(L(0), Bd(0)));
    for (int i = 1; i <= joints; ++i) AddJoint(i);
    for (int k = 0; k < points; ++k) {
      const int b = Link();
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.linear() = RandomUnitQuaternion(rng_).toRotationMatrix();
      X.translation() = RandomVector(rng_, 1.0);
      points_.push_back(std::make_shared<SimpleFrame>(links_[b], E(k), X));
      EXPECT_TRUE(g_.AddPose(PoseSpec::Of(E(k), Bd(b)).RelativeTo(L(b), Bd(b)),
                             Eigen::Matrix3d(X.linear()), Vec(X.translation())));
    }
  }

  int links() const { return static_cast<int>(links_.size()); }
  int Link() { return static_cast<int>(rng_() % static_cast<std::uint64_t>(links())); }
  std::mt19937_64& rng() { return rng_; }
  SceneGraph<B>& graph() { return g_; }

  /// A random state, in DART and in the graph (by name, or through the group of all joints).
  void SetRandomState(bool by_group) {
    const int n = links() - 1;
    Eigen::VectorXd q(n), qdot(n), qddot(n);
    for (int i = 0; i < n; ++i) {
      q(i) = Uniform(rng_, -1.5, 1.5);
      qdot(i) = Uniform(rng_, -2.0, 2.0);
      qddot(i) = Uniform(rng_, -3.0, 3.0);
    }
    skel_->setPositions(q);
    skel_->setVelocities(qdot);
    skel_->setAccelerations(qddot);
    if (by_group) {
      const JointGroup all = g_.AllJoints();
      ASSERT_EQ(all.size(), static_cast<std::size_t>(n));
      ASSERT_EQ(g_.SetJointState(all, std::span<const double>(q.data(), n),
                                 std::span<const double>(qdot.data(), n),
                                 std::span<const double>(qddot.data(), n)),
                ErrorCode::kOk);
      return;
    }
    std::vector<std::string> names;
    for (int i = 1; i <= n; ++i) names.push_back(J(i));
    std::vector<JointValue> qv, qdotv, qddotv;
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      qv.push_back({names[k], q(i)});
      qdotv.push_back({names[k], qdot(i)});
      qddotv.push_back({names[k], qddot(i)});
    }
    ASSERT_TRUE(g_.SetJoints(qv, qdotv, qddotv));
  }

  /// Frame index f: links first, then the point frames.
  const Frame* DartFrame(int f) const {
    return f < links() ? static_cast<const Frame*>(links_[static_cast<std::size_t>(f)])
                       : points_[static_cast<std::size_t>(f - links())].get();
  }
  std::string FrameName(int f) const { return f < links() ? L(f) : E(f - links()); }
  int Frames() const { return links() + static_cast<int>(points_.size()); }

  /// GetAcceleration(e|L<C>, L<D>, [r]) (e, r: frame indices) against DART.
  void ExpectAsDart(int e, int C, int D, int r) {
    const std::string fe = FrameName(e), fr = FrameName(r), c = Bd(C), d = Bd(D);
    SCOPED_TRACE(fe + "|" + c + " wrt " + d + " in [" + fr + "]");
    const TwistSpec spec = TwistSpec::Of(fe, c).RelativeTo(d).ExpressedIn(fr);
    auto A = g_.GetAcceleration(spec);
    ASSERT_TRUE(A) << g_.Describe(A.error(), spec);
    const BodyNode* bc = links_[static_cast<std::size_t>(C)];
    const BodyNode* bd = links_[static_cast<std::size_t>(D)];
    const Frame* rf = DartFrame(r);
    const Vec offset = DartFrame(e)->getTransform(bc).translation();  // e's origin in [L<C>]
    EXPECT_TRUE(Near(A->linear, bc->getLinearAcceleration(offset, bd, rf), kTol));
    EXPECT_TRUE(Near(A->angular, bc->getAngularAcceleration(bd, rf), kTol));
    // The twist beside it too (the acceleration's composition needs the current twist).
    auto V = g_.GetTwist(spec);
    ASSERT_TRUE(V);
    EXPECT_TRUE(Near(V->linear, bc->getLinearVelocity(offset, bd, rf), kTol));
    EXPECT_TRUE(Near(V->angular, bc->getAngularVelocity(bd, rf), kTol));
  }

  int kinds[2] = {0, 0};  // revolute, prismatic joints made

 private:
  void AddJoint(int i) {
    const bool prismatic = rng_() % 2 == 0;
    ++kinds[prismatic ? 1 : 0];
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = RandomUnitQuaternion(rng_).toRotationMatrix();
    X.translation() = RandomVector(rng_, 1.0);
    Vec axis = RandomVector(rng_, 1.0);
    if (axis.norm() < 0.1) axis = Vec::UnitZ();
    BodyNode* parent = links_.back();
    BodyNode* child = nullptr;
    const std::string jn = J(i), bn = Bd(i);
    if (prismatic) {
      PrismaticJoint::Properties p;
      p.mName = jn;
      p.mAxis = axis.normalized();
      p.mT_ParentBodyToJoint = X;
      child = skel_
                  ->createJointAndBodyNodePair<PrismaticJoint>(parent, p,
                                                               BodyNode::AspectProperties(bn))
                  .second;
    } else {
      RevoluteJoint::Properties p;
      p.mName = jn;
      p.mAxis = axis.normalized();
      p.mT_ParentBodyToJoint = X;
      child =
          skel_
              ->createJointAndBodyNodePair<RevoluteJoint>(parent, p, BodyNode::AspectProperties(bn))
              .second;
    }
    links_.push_back(child);
    JointSpec s;
    s.name = jn;
    s.type = prismatic ? JointType::kPrismatic : JointType::kRevolute;
    const std::string pl = L(i - 1), pb = Bd(i - 1), cl = L(i);
    s.parent = pl;
    s.parent_body = pb;
    s.child = cl;
    s.child_body = bn;
    s.R_origin = Eigen::Matrix3d(X.linear());
    s.p_origin = X.translation();
    s.axis = axis;  // not normalized: the graph normalizes it
    s.lower = -2;
    s.upper = 2;
    EXPECT_TRUE(g_.AddJoint(s));
  }

  std::mt19937_64 rng_;
  std::shared_ptr<Skeleton> skel_;
  std::vector<BodyNode*> links_;
  std::vector<std::shared_ptr<SimpleFrame>> points_;
  SceneGraph<B> g_;
};

template <class B>
class JointsAccelerationsDart : public ::testing::Test {};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(JointsAccelerationsDart, Backends);

TYPED_TEST(JointsAccelerationsDart, ToolRelativeToBaseAtRandomPointsInRandomFrames) {
  int kinds[2] = {0, 0};
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    Chain<TypeParam> s(seed, 2 + static_cast<int>(seed % 6), 6);
    s.SetRandomState(/*by_group=*/seed % 2 == 0);
    const int tool = s.links() - 1;
    for (int k = 0; k < 10; ++k) {
      const int e = static_cast<int>(s.rng()() % static_cast<std::uint64_t>(s.Frames()));
      const int r = static_cast<int>(s.rng()() % static_cast<std::uint64_t>(s.Frames()));
      s.ExpectAsDart(e, tool, 0, r);
      s.ExpectAsDart(e, 0, tool, r);
    }
    for (int w = 0; w < 2; ++w) kinds[w] += s.kinds[w];
  }
  EXPECT_GT(kinds[0], 10);
  EXPECT_GT(kinds[1], 10);
}

TYPED_TEST(JointsAccelerationsDart, RandomLinkPairsOverSuccessiveStates) {
  for (std::uint64_t seed = 100; seed < 110; ++seed) {
    Chain<TypeParam> s(seed, 6, 5);
    for (int state = 0; state < 4; ++state) {  // each state replaces the last one's values
      s.SetRandomState(/*by_group=*/state % 2 == 1);
      for (int k = 0; k < 15; ++k) {
        const int e = static_cast<int>(s.rng()() % static_cast<std::uint64_t>(s.Frames()));
        const int r = static_cast<int>(s.rng()() % static_cast<std::uint64_t>(s.Frames()));
        s.ExpectAsDart(e, s.Link(), s.Link(), r);
      }
    }
  }
}

}  // namespace
}  // namespace semgraph::core
