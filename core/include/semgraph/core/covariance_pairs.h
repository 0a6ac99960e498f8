// A pose edge's J S J^T (coord/jacobians.h EdgeOnPoseInZ, AddPropagated) in lane pairs, summed
// over the edges of a pose query with covariance: the same sum in about three quarters of the
// dense form's instructions and 70% of its time (docs/performance.md "Covariances").
//
// The math (docs/uncertainty.md "Propagation"): an edge's Jacobian with rows in Z is
// J = [[s R, L R], [0, c R]] (EdgeOnPoseFactors with d = 0: the answer's [r] is [b], or the edge
// moves both; L = [lever]x, R = R_ZP). With the edge's covariance S = [[S11, S12], [S12^T, S22]]
// rotated into Z, T1 = R S11 R^T, T2 = R S12 R^T, T3 = R S22 R^T, and Y = L T2^T, N = L T3:
//   J S J^T = [[s^2 T1 + s (Y + Y^T) + L N^T,  c (s T2 + N)],
//              [c (s T2 + N)^T,                 c^2 T3      ]]
// (T2 L^T = Y^T; L T3 L^T = L N^T as T3 is symmetric). The dense form takes nine 3x3 products
// on zero blocks and full skew matrices; here the rotations take four 3x3 products on pairs of
// blocks (lanes (T1, T3) and (T2^T, T2)), the lever arms two cross-product passes on pairs, and
// the sums stay in pairs across edges: (TL, BR) in one symmetric pair matrix, TR in another.
// Edges with d != 0 (the orientation operator O enters) go through the dense form.
//
// Invariants: S symmetric (every stored covariance is, coord/covariance.h); the sum equals the
// dense form's up to rounding (covariance_pairs_test). Costs: Add O(1), about 700 instructions
// with GCC 12 (about 300 multiplies and adds on pairs, the rest register copies and spills);
// AddTo O(1); noexcept, allocation-free.
#pragma once

#include <algorithm>

#include "semgraph/coord/covariance.h"
#include "semgraph/coord/jacobians.h"
#include "semgraph/core/lane_pairs.h"

namespace semgraph::core::internal {

/// Two 3x3 matrices, one per lane: m[i][j] = (X_A(i, j), X_B(i, j)).
struct MatrixPairs {
  Pair m[3][3];
};

/// R X R^T in both lanes.
[[gnu::always_inline]] inline MatrixPairs CongruencePairs(const RotationPairs& R,
                                                          const MatrixPairs& X) noexcept {
  MatrixPairs RX, out;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      RX.m[i][j] = R.r[i][0] * X.m[0][j] + R.r[i][1] * X.m[1][j] + R.r[i][2] * X.m[2][j];
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      out.m[i][j] = RX.m[i][0] * R.r[j][0] + RX.m[i][1] * R.r[j][1] + RX.m[i][2] * R.r[j][2];
    }
  }
  return out;
}

/// [l]x X in both lanes: column j is l x X(:, j). `transposed`: [l]x X^T.
template <bool kTransposed>
[[gnu::always_inline]] inline MatrixPairs SkewTimesPairs(const double l[3],
                                                         const MatrixPairs& X) noexcept {
  const auto x = [&](int i, int j) { return kTransposed ? X.m[j][i] : X.m[i][j]; };
  MatrixPairs out;
  for (int j = 0; j < 3; ++j) {
    out.m[0][j] = l[1] * x(2, j) - l[2] * x(1, j);
    out.m[1][j] = l[2] * x(0, j) - l[0] * x(2, j);
    out.m[2][j] = l[0] * x(1, j) - l[1] * x(0, j);
  }
  return out;
}

/// The sum of J S J^T over pose edges with d = 0, rows and columns (dp_Z, dth_Z) in Z.
struct PoseCovariancePairs {
  MatrixPairs sym{};  ///< (TL, BR): the upper triangle (i <= j) is kept
  MatrixPairs tr{};   ///< (unused, TR)

  /// One edge: R = R_ZP, the lever arm and s, c of EdgeOnPoseFactors (d must be 0), S its
  /// covariance in [p] (dp, dth).
  [[gnu::always_inline]] void Add(const RotationPairs& R, const Eigen::Vector3d& lever, double s,
                                  double c, const coord::Covariance6& S) noexcept {
    MatrixPairs X1, X2;  // (S11, S22), (S12^T, S12)
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        X1.m[i][j] = Pair{S(i, j), S(i + 3, j + 3)};
        X2.m[i][j] = Pair{S(i + 3, j), S(i, j + 3)};
      }
    }
    const MatrixPairs P1 = CongruencePairs(R, X1);  // (T1, T3)
    const MatrixPairs P2 = CongruencePairs(R, X2);  // (T2^T, T2)
    MatrixPairs Q_in;                               // (T2^T, T3)
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {  // T3 from its upper triangle: P1's lower one is never formed
        Q_in.m[i][j] = Pair{P2.m[i][j][0], P1.m[std::min(i, j)][std::max(i, j)][1]};
      }
    }
    const double l[3] = {lever.x(), lever.y(), lever.z()};
    const MatrixPairs Q = SkewTimesPairs<false>(l, Q_in);  // (Y, N)
    const MatrixPairs Z = SkewTimesPairs<true>(l, Q);      // (L Y^T, L N^T)
    const Pair k1{s * s, c * c}, k2{s, 0.0};
    for (int i = 0; i < 3; ++i) {
      for (int j = i; j < 3; ++j) {
        sym.m[i][j] += k1 * P1.m[i][j] + k2 * (Q.m[i][j] + Q.m[j][i]) + Pair{Z.m[i][j][1], 0.0};
      }
    }
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) tr.m[i][j] += c * (s * P2.m[i][j] + Q.m[i][j]);
    }
  }

  /// S_Z += the sum.
  void AddTo(coord::Covariance6& S_Z) const noexcept {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const Pair& u = i <= j ? sym.m[i][j] : sym.m[j][i];
        S_Z(i, j) += u[0];
        S_Z(i + 3, j + 3) += u[1];
        S_Z(i, j + 3) += tr.m[i][j][1];
        S_Z(j + 3, i) += tr.m[i][j][1];
      }
    }
  }
};

}  // namespace semgraph::core::internal
