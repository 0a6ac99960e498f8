// The pose edges' J S J^T with the edges in SIMD lanes (covariance_lanes.h) against the dense
// form (coord/jacobians.h EdgeOnPoseInZ and AddPropagated): by hand, a lever arm turning an
// angular variance into a linear one; on random edges, every combination of the moves flags
// (the answer's frames e, f, a, b, r below the edge or not: d != 0 brings in the orientation
// operator O) and random covariances, one edge and sums of many through DirectSink (across the
// batches, whose unused lanes must not count); both kernels (SSE2 pairs, and AVX2 quads where
// the CPU has them) on every count of lanes, with the lever arm in the compiled queries' form.
// A planted error (the lever arm reversed in the cross terms) fails.
#include "semgraph/core/covariance_lanes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
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

TEST(CovarianceLanes, ALeverArmTurnsAnAngularVarianceIntoALinearOneByHand) {
  // The edge's head g sits 2 along x from e; the edge rotates about z with variance 0.01 (and
  // nothing else). e moves with it: dp = dth x (e - g), so dp_y = -2 dth_z: var 0.04, and
  // cov(dp_y, dth_z) = -0.02.
  coord::Covariance6 S = coord::Covariance6::Zero();
  S(5, 5) = 0.01;
  const Vec lever(2, 0, 0);  // g - e
  PoseCovarianceLanes lanes;
  lanes.Add(Eigen::Matrix3d::Identity(), lever, 1.0, 1.0, 0.0, Eigen::Matrix3d::Identity(), S);
  coord::Covariance6 S_Z = coord::Covariance6::Zero();
  lanes.AddTo(S_Z);
  coord::Covariance6 expected = coord::Covariance6::Zero();
  expected(1, 1) = 0.04;
  expected(1, 5) = expected(5, 1) = -0.02;
  expected(5, 5) = 0.01;
  EXPECT_TRUE(Same(S_Z, expected));
}

TEST(CovarianceLanes, EveryEdgeEqualsTheDenseForm) {
  std::mt19937_64 rng(20261206);
  int compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const jac::PoseInZ q = RandomQuery(rng);
    for (unsigned bits = 0; bits < 32; ++bits) {
      const jac::PoseMoves m = MovesOf(bits);
      const jac::EdgeInZ edge{RandomUnitQuaternion(rng).toRotationMatrix(), RandomVector(rng, 2.0)};
      const jac::PoseEdgeFactors k = jac::EdgeOnPoseFactors(q, edge, m);
      const coord::Covariance6 S = RandomCovariance(rng);
      PoseCovarianceLanes lanes;
      lanes.Add(edge.R_ZP, k.lever, k.s, k.c, k.d, q.O_Z, S);
      coord::Covariance6 laned = coord::Covariance6::Zero(), dense = laned;
      lanes.AddTo(laned);
      jac::AddPropagated(jac::EdgeOnPoseInZ(q, edge, m), S, dense);
      ASSERT_TRUE(Same(laned, dense)) << "trial " << trial << " moves " << bits;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 200 * 32);
}

// The compiled queries' form of the inputs: the lever arm as s g + alpha e + beta f, with e and f
// given to the kernel; every flag combination (d != 0 too), every count of lanes, both kernels.
TEST(CovarianceLanes, BothKernelsSumEveryCountOfLanesAsTheDenseForm) {
  std::mt19937_64 rng(20261209);
  std::printf("AVX2 kernel on this CPU: %s\n", PoseEdgeLanesUseAvx2() ? "yes" : "no");
  constexpr int kLanes = 12;
  for (int trial = 0; trial < 100; ++trial) {
    const jac::PoseInZ q = RandomQuery(rng);
    double x[LaneDoubles(kLanes)];
    const auto at = [&](int row, int j) -> double& { return x[LaneIndex(row, j)]; };
    coord::Covariance6 dense[kLanes + 1];
    dense[0].setZero();
    for (int j = 0; j < kLanes; ++j) {
      const jac::PoseMoves m = MovesOf(static_cast<unsigned>(rng() % 32));
      const jac::EdgeInZ edge{RandomUnitQuaternion(rng).toRotationMatrix(), RandomVector(rng, 2.0)};
      const jac::PoseEdgeFactors k = jac::EdgeOnPoseFactors(q, edge, m);
      const coord::Covariance6 S = RandomCovariance(rng);
      dense[j + 1] = dense[j];
      jac::AddPropagated(jac::EdgeOnPoseInZ(q, edge, m), S, dense[j + 1]);
      const int u[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
          at(LaneRow::kR + 3 * r + c, j) = edge.R_ZP(r, c);
          at(LaneRow::kS12 + 3 * r + c, j) = S(r, c + 3);
        }
        at(LaneRow::kLeverBase + r, j) = k.s * edge.p_ZoGo_Z[r];
      }
      // lever = m.e (g - e) - m.f (g - f) + m.r (e - f) = s g + (r - e) e + (f - r) f
      at(LaneRow::kAlpha, j) = static_cast<double>(m.r) - static_cast<double>(m.e);
      at(LaneRow::kBeta, j) = static_cast<double>(m.f) - static_cast<double>(m.r);
      at(LaneRow::kS, j) = k.s;
      at(LaneRow::kC, j) = k.c;
      at(LaneRow::kD, j) = k.d;
      for (int t = 0; t < 6; ++t) {
        at(LaneRow::kS11 + t, j) = S(u[t][0], u[t][1]);
        at(LaneRow::kS22 + t, j) = S(u[t][0] + 3, u[t][1] + 3);
      }
    }
    for (int n = 1; n <= kLanes; ++n) {
      double padded[LaneDoubles(kLanes)];
      std::copy(std::begin(x), std::end(x), std::begin(padded));
      PadLanes(padded, n);
      for (const bool sse2 : {true, false}) {
        PoseCovarianceSums sums;
        (sse2 ? SumPoseEdgeLanesSse2 : SumPoseEdgeLanes)(padded, n, q.p_ZoEo_Z, q.p_ZoFo_Z, &q.O_Z,
                                                         sums);
        coord::Covariance6 laned = coord::Covariance6::Zero();
        sums.AddTo(laned);
        ASSERT_TRUE(Same(laned, dense[n], 1e-12)) << (sse2 ? "SSE2" : "dispatched") << ", n " << n;
      }
    }
  }
}

TEST(CovarianceLanes, DirectSinkSumsManyEdgesAsTheDenseForm) {
  std::mt19937_64 rng(20261207);
  for (int trial = 0; trial < 200; ++trial) {
    const jac::PoseInZ q = RandomQuery(rng);
    DirectSink sink;
    coord::Covariance6 dense = coord::Covariance6::Zero();
    for (int n = 0; n < 1 + trial % 20; ++n) {  // up to two full batches and some
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

// An edge that moves both [a] and [b] of an orientation (not [r]) turns both alike: the answer's
// rotation does not change, K = I - O is near zero (O = R_a R_b^T, a product of rounded
// rotations), and so must the contribution be, not a difference of large terms (summing c^2 T3,
// c d T3 and d^2 T3 apart and applying O at the end left about 1e-16 of T3 here).
TEST(CovarianceLanes, AnEdgeTurningBothSidesOfAnOrientationAddsNearlyNothingToIt) {
  std::mt19937_64 rng(20261210);
  for (int trial = 0; trial < 50; ++trial) {
    jac::PoseInZ q = RandomQuery(rng);
    const Eigen::Matrix3d R_a = RandomUnitQuaternion(rng).toRotationMatrix();
    q.O_Z = R_a * R_a.transpose();                            // [a] and [b] at the same orientation
    const jac::PoseMoves m{false, false, true, true, false};  // e, f, a, b, r
    const jac::EdgeInZ edge{RandomUnitQuaternion(rng).toRotationMatrix(), RandomVector(rng, 2.0)};
    const jac::PoseEdgeFactors k = jac::EdgeOnPoseFactors(q, edge, m);
    ASSERT_EQ(k.c, 1.0);
    ASSERT_EQ(k.d, -1.0);
    const coord::Covariance6 S = RandomCovariance(rng);
    PoseCovarianceLanes lanes;
    lanes.Add(edge.R_ZP, k.lever, k.s, k.c, k.d, q.O_Z, S);
    coord::Covariance6 laned = coord::Covariance6::Zero();
    lanes.AddTo(laned);
    const double largest = laned.bottomRightCorner<3, 3>().cwiseAbs().maxCoeff();
    EXPECT_LE(largest, 1e-24 * S.norm()) << "trial " << trial;
  }
}

TEST(CovarianceLanes, APlantedLeverSignErrorFails) {
  std::mt19937_64 rng(20261208);
  const jac::PoseInZ q = RandomQuery(rng);
  const jac::PoseMoves m = MovesOf(1U);  // e below the edge: s = 1, c = 0, a lever arm
  const jac::EdgeInZ edge{RandomUnitQuaternion(rng).toRotationMatrix(), RandomVector(rng, 2.0)};
  const jac::PoseEdgeFactors k = jac::EdgeOnPoseFactors(q, edge, m);
  const coord::Covariance6 S = RandomCovariance(rng);
  PoseCovarianceLanes lanes;
  lanes.Add(edge.R_ZP, -k.lever, k.s, k.c, k.d, q.O_Z, S);
  coord::Covariance6 laned = coord::Covariance6::Zero(), dense = laned;
  lanes.AddTo(laned);
  jac::AddPropagated(jac::EdgeOnPoseInZ(q, edge, m), S, dense);
  EXPECT_FALSE(Same(laned, dense, 1e-3));
}

}  // namespace
}  // namespace semgraph::core::internal
