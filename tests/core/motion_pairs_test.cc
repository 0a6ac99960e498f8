// The compiled acceleration query's paired kernels (motion_pairs.h): by hand, a spinning
// relation moved to a point off its axis (the centripetal acceleration) and a quarter turn; on
// 2,000 random records, MovedEdgeMotion equals the staged EdgeMotion, RotateMotion and
// ShiftMotion of evaluate.h, both directions; RotationPairs from a quaternion is Eigen's matrix,
// bit for bit; on random sequences of motions on both sides, one running ThenPairs product (D's
// side in order, C's reversed) equals AccelerationComposer; the compiled query's last moves
// (ShiftPairs, RotatePairs on a composed motion) equal ShiftMotion and RotateMotion. A planted
// error fails each comparison.
#include "semgraph/core/motion_pairs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "support/tolerance.h"
#include "support/world_scene.h"

namespace semgraph::core::internal {
namespace {

using semgraph::testing::Near;
using semgraph::testing::RandomUnitQuaternion;
using semgraph::testing::RandomVector;
using Vec = Eigen::Vector3d;
using QuatB = coord::QuaternionBackend;

TwistAndAcceleration Record(const Vec& v, const Vec& w, const Vec& a, const Vec& alpha) {
  return TwistAndAcceleration{{v, w}, {a, alpha}, 1.0};
}

TwistAndAcceleration RandomRecord(std::mt19937_64& rng) {
  return Record(RandomVector(rng, 1.0), RandomVector(rng, 1.0), RandomVector(rng, 1.0),
                RandomVector(rng, 1.0));
}

::testing::AssertionResult SameMotion(const Motion& x, const Motion& y, double tol = 1e-12) {
  for (const auto& [u, v] :
       {std::pair{&x.v, &y.v}, {&x.w, &y.w}, {&x.a, &y.a}, {&x.alpha, &y.alpha}}) {
    auto r = Near(*u, *v, tol);
    if (!r) return r;
  }
  return ::testing::AssertionSuccess();
}

// The staged kernels the compiled query used before (and the one-shot query still uses).
Motion Staged(const TwistAndAcceleration& r, bool invert, const Eigen::Quaterniond& R_ZH,
              const Vec& p) {
  Motion m = EdgeMotion(r, invert);
  RotateMotion<QuatB>(R_ZH, m);
  ShiftMotion(m, p);
  return m;
}

TEST(MotionPairs, ASpinningRelationMovedOffItsAxisByHand) {
  // The relation spins at omega about z through h; Z's origin lies at -r x from h (p = h - Zo =
  // r x). There it moves at omega r along -y with the centripetal acceleration omega^2 r
  // towards the axis (+x); inverted, it spins at -omega: the velocity flips, the centripetal
  // acceleration does not.
  const double omega = 3.0, r = 0.5;
  const Vec w(0, 0, omega), p(r, 0, 0), z = Vec::Zero();
  for (const bool invert : {false, true}) {
    const double s = invert ? -1.0 : 1.0;
    const Motion m =
        MovedEdgeMotion(Record(z, w, z, z), invert, Eigen::Matrix3d::Identity(), p).ToMotion();
    EXPECT_TRUE(Near(m.v, Vec(0, -s * omega * r, 0), 1e-15));
    EXPECT_TRUE(Near(m.w, s * w, 1e-15));
    EXPECT_TRUE(Near(m.a, Vec(omega * omega * r, 0, 0), 1e-15));
    EXPECT_TRUE(Near(m.alpha, z, 1e-15));
  }
}

TEST(MotionPairs, AQuarterTurnByHand) {
  // R_ZH a quarter turn about z: x of [h] is y of [Z]; no shift.
  const Eigen::Matrix3d R_ZH = Eigen::AngleAxisd(M_PI / 2, Vec::UnitZ()).toRotationMatrix();
  const Motion m = MovedEdgeMotion(Record(Vec(1, 0, 0), Vec(0, 0, 2), Vec(0, 3, 0), Vec(4, 0, 5)),
                                   false, R_ZH, Vec::Zero())
                       .ToMotion();
  EXPECT_TRUE(Near(m.v, Vec(0, 1, 0), 1e-15));
  EXPECT_TRUE(Near(m.w, Vec(0, 0, 2), 1e-15));
  EXPECT_TRUE(Near(m.a, Vec(-3, 0, 0), 1e-15));
  EXPECT_TRUE(Near(m.alpha, Vec(0, 4, 5), 1e-15));
}

TEST(MotionPairs, MovedEdgeMotionIsTheStagedKernels) {
  std::mt19937_64 rng(20261206);
  for (int i = 0; i < 2000; ++i) {
    const TwistAndAcceleration r = RandomRecord(rng);
    const Eigen::Quaterniond R_ZH = RandomUnitQuaternion(rng);
    const Vec p = RandomVector(rng, 2.0);
    const bool invert = i % 2 == 1;
    EXPECT_TRUE(SameMotion(MovedEdgeMotion(r, invert, R_ZH.toRotationMatrix(), p).ToMotion(),
                           Staged(r, invert, R_ZH, p)))
        << "record " << i << (invert ? " inverted" : "");
  }
  // A planted error (the shift's lever arm reversed) is far outside the tolerance.
  const TwistAndAcceleration r = RandomRecord(rng);
  const Vec p = RandomVector(rng, 2.0);
  EXPECT_FALSE(SameMotion(MovedEdgeMotion(r, false, Eigen::Matrix3d::Identity(), -p).ToMotion(),
                          Staged(r, false, Eigen::Quaterniond::Identity(), p), 1e-3));
}

TEST(MotionPairs, RotationPairsFromAQuaternionIsEigensMatrix) {
  std::mt19937_64 rng(20261206);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Quaterniond q = RandomUnitQuaternion(rng);
    const RotationPairs paired(q);
    const Eigen::Matrix3d R = q.toRotationMatrix();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(paired.r[r][c][0], R(r, c)) << "quaternion " << i << " entry " << r << c;
        ASSERT_EQ(paired.r[r][c][1], R(r, c)) << "quaternion " << i << " entry " << r << c;
      }
    }
  }
}

// AccelerationComposer's steps (side, motion) as one running product: D's side in order, then
// C's reversed. `swap_c` plants an order error: C's first two kept in the plan's order.
MotionPairs RunningProduct(const std::vector<std::pair<bool, MotionPairs>>& steps,
                           bool swap_c = false) {
  std::vector<MotionPairs> d_side, c_side;
  for (const auto& [ref_side, m] : steps) (ref_side ? d_side : c_side).push_back(m);
  std::reverse(c_side.begin(), c_side.end());
  if (swap_c && c_side.size() >= 2) std::swap(c_side[c_side.size() - 1], c_side[c_side.size() - 2]);
  MotionPairs product = MotionPairs::Zero();
  for (const MotionPairs& m : d_side) ThenPairs(product, m);
  for (const MotionPairs& m : c_side) ThenPairs(product, m);
  return product;
}

TEST(MotionPairs, TheRunningProductIsAccelerationComposer) {
  std::mt19937_64 rng(20261207);
  for (int sequence = 0; sequence < 200; ++sequence) {
    AccelerationComposer staged;
    std::vector<std::pair<bool, MotionPairs>> steps;
    for (int k = 0; k < 1 + sequence % 9; ++k) {
      const TwistAndAcceleration r = RandomRecord(rng);
      const Eigen::Quaterniond R_ZH = RandomUnitQuaternion(rng);
      const Vec p = RandomVector(rng, 2.0);
      const bool ref_side = (rng() & 1U) != 0, invert = (rng() & 1U) != 0;
      staged.Add(ref_side, Staged(r, invert, R_ZH, p));
      steps.emplace_back(ref_side, MovedEdgeMotion(r, invert, R_ZH.toRotationMatrix(), p));
    }
    EXPECT_TRUE(SameMotion(RunningProduct(steps).ToMotion(), staged.Result(), 1e-11))
        << "sequence " << sequence;
  }
  // Planted: two of C's steps in the plan's order (the Coriolis terms' order is wrong).
  AccelerationComposer staged;
  std::vector<std::pair<bool, MotionPairs>> steps;
  for (int k = 0; k < 3; ++k) {
    const TwistAndAcceleration r = RandomRecord(rng);
    staged.Add(false, Staged(r, false, Eigen::Quaterniond::Identity(), Vec::Zero()));
    steps.emplace_back(false, MovedEdgeMotion(r, false, Eigen::Matrix3d::Identity(), Vec::Zero()));
  }
  EXPECT_FALSE(SameMotion(RunningProduct(steps, true).ToMotion(), staged.Result(), 1e-3));
}

// The tail of the compiled query: a composed motion (twist and acceleration in both lanes, not
// an edge record) moved to another point, then rotated, as ShiftMotion and RotateMotion do.
TEST(MotionPairs, TheLastMovesAreShiftMotionAndRotateMotion) {
  std::mt19937_64 rng(20261208);
  for (int i = 0; i < 1000; ++i) {
    MotionPairs composed = MovedEdgeMotion(RandomRecord(rng), false, Eigen::Matrix3d::Identity(),
                                           RandomVector(rng, 2.0));
    ThenPairs(composed, MovedEdgeMotion(RandomRecord(rng), true, Eigen::Matrix3d::Identity(),
                                        RandomVector(rng, 2.0)));
    const Vec p = RandomVector(rng, 2.0);
    const Eigen::Quaterniond R = RandomUnitQuaternion(rng);
    MotionPairs m = composed;
    ShiftPairs(p, m);
    m = RotatePairs(RotationPairs(R), m);
    Motion staged = composed.ToMotion();
    ShiftMotion(staged, p);
    RotateMotion<QuatB>(R, staged);
    EXPECT_TRUE(SameMotion(m.ToMotion(), staged)) << "motion " << i;
  }
  // Planted: the rotation before the shift (the lever arm in the wrong axes).
  const MotionPairs composed = MovedEdgeMotion(RandomRecord(rng), false,
                                               Eigen::Matrix3d::Identity(), RandomVector(rng, 2.0));
  const Vec p = RandomVector(rng, 2.0);
  const Eigen::Quaterniond R = RandomUnitQuaternion(rng);
  MotionPairs m = RotatePairs(RotationPairs(R), composed);
  ShiftPairs(p, m);
  Motion staged = composed.ToMotion();
  ShiftMotion(staged, p);
  RotateMotion<QuatB>(R, staged);
  EXPECT_FALSE(SameMotion(m.ToMotion(), staged, 1e-3));
}

}  // namespace
}  // namespace semgraph::core::internal
