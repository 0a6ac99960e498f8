// The pose edges' J S J^T in lane pairs (covariance_pairs.h) against the dense form
// (coord/jacobians.h EdgeOnPoseInZ and AddPropagated): by hand, a lever arm turning an angular
// variance into a linear one; on random edges, every combination of the moves flags with d = 0
// (the answer's frames e, f, a, b, r below the edge or not) and random covariances, one edge and
// sums of many; DirectSink sends the d != 0 edges through the dense form. A planted error (the
// lever arm reversed in the cross terms) fails.
#include "semgraph/core/covariance_pairs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "semgraph/core/propagate.h"
#include "support/tolerance.h"
#include "support/world_scene.h"

namespace semgraph::core::internal {
namespace {

namespace jac = coord::jacobians;
using semgraph::testing::RandomUnitQuaternion;
using semgraph::testing::RandomVector;
using Vec = Eigen::Vector3d;

coord::Covariance6 RandomCovariance(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  jac::Matrix6 L;
  for (int i = 0; i < 36; ++i) L(i / 6, i % 6) = n(rng);
  return L * L.transpose();
}

jac::PoseInZ RandomQuery(std::mt19937_64& rng) {
  jac::PoseInZ q;
  q.R_RZ = RandomUnitQuaternion(rng).toRotationMatrix();
  q.p_ZoEo_Z = RandomVector(rng, 2.0);
  q.p_ZoFo_Z = RandomVector(rng, 2.0);
  q.O_Z = RandomUnitQuaternion(rng).toRotationMatrix();
  return q;
}

jac::PoseMoves MovesOf(unsigned bits) {
  return {(bits & 1U) != 0, (bits & 2U) != 0, (bits & 4U) != 0, (bits & 8U) != 0,
          (bits & 16U) != 0};
}

// Entry by entry, relative to the largest entry.
::testing::AssertionResult Same(const coord::Covariance6& x, const coord::Covariance6& y,
                                double tol = 1e-13) {
  const double scale = std::max(1.0, y.cwiseAbs().maxCoeff());
  const double err = (x - y).cwiseAbs().maxCoeff();
  if (err <= tol * scale) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "max |diff| " << err << " (scale " << scale << ")\n"
                                       << x << "\nvs\n"
                                       << y;
}

TEST(CovariancePairs, ALeverArmTurnsAnAngularVarianceIntoALinearOneByHand) {
  // The edge's head g sits 2 along x from e; the edge rotates about z with variance 0.01 (and
  // nothing else). e moves with it: dp = dth x (e - g), so dp_y = -2 dth_z: var 0.04, and
  // cov(dp_y, dth_z) = -0.02.
  coord::Covariance6 S = coord::Covariance6::Zero();
  S(5, 5) = 0.01;
  const Vec lever(2, 0, 0);  // g - e
  PoseCovariancePairs pairs;
  pairs.Add(RotationPairs(Eigen::Matrix3d::Identity()), lever, 1.0, 1.0, S);
  coord::Covariance6 S_Z = coord::Covariance6::Zero();
  pairs.AddTo(S_Z);
  coord::Covariance6 expected = coord::Covariance6::Zero();
  expected(1, 1) = 0.04;
  expected(1, 5) = expected(5, 1) = -0.02;
  expected(5, 5) = 0.01;
  EXPECT_TRUE(Same(S_Z, expected));
}

TEST(CovariancePairs, EveryEdgeEqualsTheDenseForm) {
  std::mt19937_64 rng(20261206);
  int compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const jac::PoseInZ q = RandomQuery(rng);
    for (unsigned bits = 0; bits < 32; ++bits) {
      const jac::PoseMoves m = MovesOf(bits);
      const jac::EdgeInZ edge{RandomUnitQuaternion(rng).toRotationMatrix(), RandomVector(rng, 2.0)};
      const jac::PoseEdgeFactors k = jac::EdgeOnPoseFactors(q, edge, m);
      if (k.d != 0.0) continue;
      const coord::Covariance6 S = RandomCovariance(rng);
      PoseCovariancePairs pairs;
      pairs.Add(RotationPairs(edge.R_ZP), k.lever, k.s, k.c, S);
      coord::Covariance6 paired = coord::Covariance6::Zero(), dense = paired;
      pairs.AddTo(paired);
      jac::AddPropagated(jac::EdgeOnPoseInZ(q, edge, m), S, dense);
      ASSERT_TRUE(Same(paired, dense)) << "trial " << trial << " moves " << bits;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 200 * 16);  // the half of the flags with m.r == m.b
}

TEST(CovariancePairs, DirectSinkSumsManyEdgesAsTheDenseForm) {
  std::mt19937_64 rng(20261207);
  for (int trial = 0; trial < 200; ++trial) {
    const jac::PoseInZ q = RandomQuery(rng);
    DirectSink sink;
    coord::Covariance6 dense = coord::Covariance6::Zero();
    for (int n = 0; n < 1 + trial % 12; ++n) {
      const jac::PoseMoves m = MovesOf(static_cast<unsigned>(rng() % 32));
      const jac::EdgeInZ edge{RandomUnitQuaternion(rng).toRotationMatrix(), RandomVector(rng, 2.0)};
      const coord::Covariance6 S = RandomCovariance(rng);
      sink.AddPoseEdge({PerturbedEdge::Kind::kPose, 0}, q, edge, m, S);
      jac::AddPropagated(jac::EdgeOnPoseInZ(q, edge, m), S, dense);
    }
    coord::Covariance6 S_out;
    sink.Finish(S_out);
    ASSERT_TRUE(Same(S_out, dense, 1e-12)) << "trial " << trial;
  }
}

TEST(CovariancePairs, APlantedLeverSignErrorFails) {
  std::mt19937_64 rng(20261208);
  const jac::PoseInZ q = RandomQuery(rng);
  const jac::PoseMoves m = MovesOf(1U);  // e below the edge: s = 1, c = 0, a lever arm
  const jac::EdgeInZ edge{RandomUnitQuaternion(rng).toRotationMatrix(), RandomVector(rng, 2.0)};
  const jac::PoseEdgeFactors k = jac::EdgeOnPoseFactors(q, edge, m);
  const coord::Covariance6 S = RandomCovariance(rng);
  PoseCovariancePairs pairs;
  pairs.Add(RotationPairs(edge.R_ZP), -k.lever, k.s, k.c, S);
  coord::Covariance6 paired = coord::Covariance6::Zero(), dense = paired;
  pairs.AddTo(paired);
  jac::AddPropagated(jac::EdgeOnPoseInZ(q, edge, m), S, dense);
  EXPECT_FALSE(Same(paired, dense, 1e-3));
}

}  // namespace
}  // namespace semgraph::core::internal
