// A pose edge's J S J^T (coord/jacobians.h EdgeOnPoseInZ, AddPropagated), summed over the
// edges of a pose query with covariance, with the edges in SIMD lanes: each lane does one
// edge's whole arithmetic, so every vector operation is full and no shuffle is needed; four
// lanes (AVX2 with FMA, chosen at run time when the CPU has them) or two (SSE2).
//
// The math (docs/uncertainty.md "Propagation"): an edge's Jacobian with rows in Z is
// J = [[s R, L R], [0, K R]] (EdgeOnPoseFactors; L = [lever]x, R = R_ZP, K = c I + d O with O
// the answer's O_Z, the same for every edge). With the edge's covariance
// S = [[S11, S12], [S12^T, S22]] rotated into Z, T1 = R S11 R^T, T2 = R S12 R^T,
// T3 = R S22 R^T, and Y = L T2^T, N = L T3:
//   J S J^T = [[s^2 T1 + s (Y + Y^T) + L N^T,  (s T2 + N) K^T],
//              [K (s T2 + N)^T,                 K T3 K^T      ]]
// (T2 L^T = Y^T; L T3 L^T = L N^T as T3 is symmetric). When every edge has d = 0 (the answer's
// [r] is [b], or the edge moves both), K = c I and the last two blocks are c (s T2 + N) and
// c^2 T3; otherwise each lane forms K (O given to the kernel: the same for every edge) and the
// two products with it, as the dense form does, so that a K near zero (an edge that moves both
// sides of an orientation) gives a contribution near zero, not a difference of large terms.
// About 230 multiplies and 170 adds per edge (with K: about 70 more), against the dense form's
// nine 3x3 products on zero blocks and full skew matrices.
//
// Inputs, one row per quantity and one column (lane) per edge: R_ZP; the lever arm as
// lever = base + alpha e + beta f (e, f: the answer's points in Z, given to the kernel; a caller
// with the lever at hand puts it in `base` with alpha = beta = 0, a compiled query puts s g
// there, g the edge's head in Z, so that the lanes are filled before e and f are known); s, c,
// d; and S's upper triangle.
//
// Invariants: S symmetric (every stored covariance is, coord/covariance.h; only its upper
// triangle is read); the sum equals the dense form's up to rounding (covariance_lanes_test);
// both kernels give the same sum up to rounding (FMA). Costs: the kernel about 190 instructions
// per edge with AVX2 and FMA, 440 with SSE2 (docs/performance.md "Covariances");
// PoseCovarianceLanes::Add O(1) (38 stores; every kBatch edges one kernel call), AddTo
// O(kBatch); noexcept, allocation-free, lock-free (the CPU check reads a word the C runtime set
// at startup).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <utility>

#include "semgraph/coord/covariance.h"
#include "semgraph/core/export.h"

namespace semgraph::core::internal {

/// The rows of the kernel's inputs (a row holds one quantity of every edge, lane by lane).
struct LaneRow {
  enum : int {
    kR = 0,          ///< R_ZP, row-major (9 rows)
    kLeverBase = 9,  ///< the lever arm's base (3)
    kAlpha = 12,     ///< the coefficient of e in the lever arm
    kBeta = 13,      ///< the coefficient of f
    kS = 14,         ///< s
    kC = 15,         ///< c
    kD = 16,         ///< d
    kS11 = 17,       ///< S11's upper triangle (00, 01, 02, 11, 12, 22)
    kS22 = 23,       ///< S22's upper triangle
    kS12 = 29,       ///< S12 = S(0:3, 3:6), row-major (9)
    kRows = 38
  };
};

/// The kernel's running sums, per lane (summed over the lanes at the end): the upper triangles
/// of the top-left and bottom-right blocks, then the top-right block row-major.
struct PoseCovarianceSums {
  enum : int { kTL = 0, kBR = 6, kTR = 12, kEntries = 21 };
  alignas(64) double lane[kEntries][4] = {};

  /// S_Z += the sums.
  void AddTo(coord::Covariance6& S_Z) const noexcept;
};

/// Where lane j of row r lies in the kernel's inputs: blocks of 4 lanes, each holding every
/// row's 4 lanes (so the rows of one lane are 4 doubles apart, a constant a reader can store to
/// at fixed offsets: EdgeValues::LoadPoseIntoLanes).
constexpr std::size_t LaneIndex(int r, int j) noexcept {
  return static_cast<std::size_t>((j / 4 * LaneRow::kRows + r) * 4 + j % 4);
}
/// Doubles of inputs for n lanes (whole blocks).
constexpr std::size_t LaneDoubles(int n) noexcept {
  return static_cast<std::size_t>((n + 3) / 4 * LaneRow::kRows * 4);
}

/// The words of a covariance's upper triangle, relative to its first (a column-major 6x6), in
/// the order of the rows kS11 .. kS12 above: S11's upper triangle (00, 01, 02, 11, 12, 22),
/// S22's, then S12 = S(0:3, 3:6) row-major.
inline constexpr std::size_t kCovarianceLaneWords[21] = {0,  6,  12, 7,  13, 14, 21, 27, 33, 28, 34,
                                                         35, 18, 24, 30, 19, 25, 31, 20, 26, 32};
/// Those words of a record whose covariance starts at word kS, as template arguments.
template <std::size_t kS, std::size_t... K>
constexpr auto CovarianceLaneWords(std::index_sequence<K...>) noexcept {
  return std::index_sequence<(kS + kCovarianceLaneWords[K])...>{};
}

/// Adds lanes 0 .. n-1 of `x` (LaneIndex) to `sums`, e and f the answer's points in Z, O its O_Z
/// (nullptr: every lane has d = 0). Lanes from n to the next multiple of 4 are read and must
/// hold zeros (or any finite numbers with S = 0). AVX2 + FMA when the CPU has them, else SSE2.
SEMGRAPH_CORE_EXPORT void SumPoseEdgeLanes(const double* x, int n, const Eigen::Vector3d& e,
                                           const Eigen::Vector3d& f, const Eigen::Matrix3d* O,
                                           PoseCovarianceSums& sums) noexcept;
/// The same on SSE2 lanes, whatever the CPU (for tests: both kernels agree).
SEMGRAPH_CORE_EXPORT void SumPoseEdgeLanesSse2(const double* x, int n, const Eigen::Vector3d& e,
                                               const Eigen::Vector3d& f, const Eigen::Matrix3d* O,
                                               PoseCovarianceSums& sums) noexcept;
/// Whether SumPoseEdgeLanes takes the AVX2 kernel on this CPU.
SEMGRAPH_CORE_EXPORT bool PoseEdgeLanesUseAvx2() noexcept;

/// Zeroes lanes n .. (the next multiple of 4) - 1 of every row (what the kernel reads past n).
inline void PadLanes(double* x, int n) noexcept {
  for (int r = 0; r < LaneRow::kRows; ++r) {
    for (int j = n; j % 4 != 0; ++j) x[LaneIndex(r, j)] = 0.0;
  }
}

/// Writes one lane's rows other than S's: R = R_ZP, the lever arm as base + alpha e + beta f, and
/// s, c, d. `lane`: the lane's first row (x + LaneIndex(0, j)); its rows are 4 doubles apart.
inline void SetLaneFactors(double* lane, const Eigen::Matrix3d& R, const Eigen::Vector3d& base,
                           double alpha, double beta, double s, double c, double d) noexcept {
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) lane[4 * (LaneRow::kR + 3 * i + k)] = R(i, k);
    lane[4 * (LaneRow::kLeverBase + i)] = base[i];
  }
  lane[4 * LaneRow::kAlpha] = alpha;
  lane[4 * LaneRow::kBeta] = beta;
  lane[4 * LaneRow::kS] = s;
  lane[4 * LaneRow::kC] = c;
  lane[4 * LaneRow::kD] = d;
}

/// The sum of J S J^T over pose edges with their levers at hand (one-shot queries:
/// propagate.h DirectSink), rows and columns (dp_Z, dth_Z) in Z, kBatch edges per kernel call.
class PoseCovarianceLanes {
 public:
  static constexpr int kBatch = 8;

  /// One edge: R = R_ZP, the lever arm and s, c, d of EdgeOnPoseFactors, S its covariance in
  /// [p] (dp, dth), O the answer's O_Z (the same for every edge; kept when d != 0).
  void Add(const Eigen::Matrix3d& R, const Eigen::Vector3d& lever, double s, double c, double d,
           const Eigen::Matrix3d& O, const coord::Covariance6& S) noexcept {
    if (n_ == kBatch) Flush();
    if (d != 0.0 && !with_o_) {
      with_o_ = true;
      O_ = O;
    }
    double* const lane = x_ + LaneIndex(0, n_++);
    SetLaneFactors(lane, R, lever, 0.0, 0.0, s, c, d);
    int u = 0;
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) lane[4 * (LaneRow::kS12 + 3 * i + k)] = S(i, k + 3);
      for (int k = i; k < 3; ++k, ++u) {
        lane[4 * (LaneRow::kS11 + u)] = S(i, k);
        lane[4 * (LaneRow::kS22 + u)] = S(i + 3, k + 3);
      }
    }
  }

  /// S_Z += the sum (the edges still in the batch summed first).
  void AddTo(coord::Covariance6& S_Z) noexcept;

 private:
  void Flush() noexcept;  // the batch's edges into sums_
  alignas(64) double x_[LaneDoubles(kBatch)];
  PoseCovarianceSums sums_;
  Eigen::Matrix3d O_ = Eigen::Matrix3d::Zero();
  bool with_o_ = false;
  int n_ = 0;
};

}  // namespace semgraph::core::internal
