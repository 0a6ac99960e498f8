// Lane pairs: two doubles in one SSE2 register (GCC's and Clang's vector extension; plain
// pairs of doubles on other targets), for the compiled queries' kernels that do the same
// arithmetic on two quantities at once: motion_pairs.h (a twist and an acceleration),
// covariance_pairs.h (two 3x3 blocks of a covariance).
//
// Invariants: none beyond the types'. Costs: every function is O(1), noexcept,
// allocation-free; a scalar times a Pair broadcasts the scalar (one shuffle on SSE2).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace semgraph::core::internal {

using Pair = double __attribute__((vector_size(16)));

/// s x (x_i pairs): the cross product of the 3-vector s with both lanes' vectors.
[[gnu::always_inline]] inline void CrossPairs(const double s[3], const Pair x[3],
                                              Pair out[3]) noexcept {
  out[0] = s[1] * x[2] - s[2] * x[1];
  out[1] = s[2] * x[0] - s[0] * x[2];
  out[2] = s[0] * x[1] - s[1] * x[0];
}

/// A rotation matrix with every entry in both lanes (r[i][j] = (R(i,j), R(i,j))): the factors
/// of RotatePairs and CongruencePairs. From a quaternion it is formed straight in pairs
/// (Eigen's toRotationMatrix formula, the same roundings): through toRotationMatrix's scalar
/// matrix GCC moved the entries through general registers, 13 moves per twist edge of the
/// compiled acceleration query, on the vector ports it is bound by (docs/performance.md).
struct RotationPairs {
  Pair r[3][3];

  RotationPairs(const Eigen::Matrix3d& R) noexcept {  // NOLINT: implicit, as the matrix it holds
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) r[i][j] = Pair{R(i, j), R(i, j)};
    }
  }
  [[gnu::always_inline]] explicit RotationPairs(const Eigen::Quaterniond& q) noexcept {
    const Pair x{q.x(), q.x()}, y{q.y(), q.y()}, z{q.z(), q.z()}, w{q.w(), q.w()};
    const Pair tx = 2.0 * x, ty = 2.0 * y, tz = 2.0 * z;
    const Pair twx = tx * w, twy = ty * w, twz = tz * w;
    const Pair txx = tx * x, txy = ty * x, txz = tz * x;
    const Pair tyy = ty * y, tyz = tz * y, tzz = tz * z;
    const Pair one{1.0, 1.0};
    r[0][0] = one - (tyy + tzz);
    r[0][1] = txy - twz;
    r[0][2] = txz + twy;
    r[1][0] = txy + twz;
    r[1][1] = one - (txx + tzz);
    r[1][2] = tyz - twx;
    r[2][0] = txz - twy;
    r[2][1] = tyz + twx;
    r[2][2] = one - (txx + tyy);
  }
};

}  // namespace semgraph::core::internal
