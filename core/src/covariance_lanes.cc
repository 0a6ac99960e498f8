// The pose edges' J S J^T with the edges in SIMD lanes: one kernel written once over a vector
// type, built for SSE2 pairs and for AVX2 + FMA quads. Contract: covariance_lanes.h.
#include "semgraph/core/covariance_lanes.h"

#include <cstring>

namespace semgraph::core::internal {

namespace {

using Lanes2 = double __attribute__((vector_size(16)));
using Lanes4 = double __attribute__((vector_size(32)));
using Sums = PoseCovarianceSums;

// Upper-triangle index of a symmetric 3x3's entry (i, j), and the entries in that order.
constexpr int kSym[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
constexpr int kUpperRow[6] = {0, 0, 0, 1, 1, 2};
constexpr int kUpperCol[6] = {0, 1, 2, 1, 2, 2};

// Helpers take and give vectors by reference only: a 32-byte vector by value would change the
// ABI between the SSE2 and AVX2 functions (GCC's -Wpsabi).
template <class V>
[[gnu::always_inline]] inline void Load(const double* x, int row, int j0, V& v) noexcept {
  std::memcpy(&v, x + LaneIndex(row, j0), sizeof v);
}

// out = (l x t)_i.
template <class V>
[[gnu::always_inline]] inline void CrossRow(const V (&l)[3], const V& t0, const V& t1, const V& t2,
                                            int i, V& out) noexcept {
  if (i == 0) out = l[1] * t2 - l[2] * t1;
  if (i == 1) out = l[2] * t0 - l[0] * t2;
  if (i == 2) out = l[0] * t1 - l[1] * t0;
}

// RX = R X with X symmetric (upper triangle), then T = RX R^T's upper triangle.
template <class V>
[[gnu::always_inline]] inline void SymmetricCongruence(const V (&R)[3][3], const V (&X)[6],
                                                       V (&T)[6]) noexcept {
  V RX[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      RX[i][j] = R[i][0] * X[kSym[0][j]] + R[i][1] * X[kSym[1][j]] + R[i][2] * X[kSym[2][j]];
    }
  }
  for (int u = 0; u < 6; ++u) {
    const int i = kUpperRow[u], j = kUpperCol[u];
    T[u] = RX[i][0] * R[j][0] + RX[i][1] * R[j][1] + RX[i][2] * R[j][2];
  }
}

// T = R X R^T, X general.
template <class V>
[[gnu::always_inline]] inline void Congruence(const V (&R)[3][3], const V (&X)[3][3],
                                              V (&T)[3][3]) noexcept {
  V RX[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      RX[i][j] = R[i][0] * X[0][j] + R[i][1] * X[1][j] + R[i][2] * X[2][j];
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      T[i][j] = RX[i][0] * R[j][0] + RX[i][1] * R[j][1] + RX[i][2] * R[j][2];
    }
  }
}

// Adds `v` to the running sum `entry` of the lanes j0 .. j0 + W - 1.
template <class V>
[[gnu::always_inline]] inline void Accumulate(Sums& sums, int entry, int j0, const V& v) noexcept {
  V acc;
  double* at = &sums.lane[entry][j0 % 4];
  std::memcpy(&acc, at, sizeof acc);
  acc += v;
  std::memcpy(at, &acc, sizeof acc);
}

// The kernel, W = sizeof(V) / 8 edges at a time (the formula of covariance_lanes.h).
template <class V, bool kWithO>
[[gnu::always_inline]] inline void SumLanes(const double* in, int n, const Eigen::Vector3d& e_Z,
                                            const Eigen::Vector3d& f_Z, Sums& sums) noexcept {
  constexpr int W = static_cast<int>(sizeof(V) / sizeof(double));
  if (kWithO && !sums.with_o) {  // the sums with O start now
    for (int k = Sums::kTRd; k < Sums::kEntries; ++k) {
      for (double& x : sums.lane[k]) x = 0.0;
    }
    sums.with_o = true;
  }
  V e[3], f[3];
  for (int i = 0; i < 3; ++i) {
    for (int w = 0; w < W; ++w) {
      e[i][w] = e_Z[i];
      f[i][w] = f_Z[i];
    }
  }
  for (int j0 = 0; j0 < n; j0 += W) {
    V R[3][3], l[3], S11[6], S22[6], S12[3][3], alpha, beta, s, c, d;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        Load(in, LaneRow::kR + 3 * i + j, j0, R[i][j]);
        Load(in, LaneRow::kS12 + 3 * i + j, j0, S12[i][j]);
      }
      Load(in, LaneRow::kLeverBase + i, j0, l[i]);
    }
    for (int u = 0; u < 6; ++u) {
      Load(in, LaneRow::kS11 + u, j0, S11[u]);
      Load(in, LaneRow::kS22 + u, j0, S22[u]);
    }
    Load(in, LaneRow::kAlpha, j0, alpha);
    Load(in, LaneRow::kBeta, j0, beta);
    Load(in, LaneRow::kS, j0, s);
    Load(in, LaneRow::kC, j0, c);
    for (int i = 0; i < 3; ++i) l[i] += alpha * e[i] + beta * f[i];
    V T1[6], T3[6], T2[3][3];
    SymmetricCongruence(R, S11, T1);
    SymmetricCongruence(R, S22, T3);
    Congruence(R, S12, T2);
    V Y[3][3], N[3][3];  // Y(:, j) = l x T2(j, :); N(:, j) = l x T3(:, j)
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        CrossRow(l, T2[j][0], T2[j][1], T2[j][2], i, Y[i][j]);
        CrossRow(l, T3[kSym[0][j]], T3[kSym[1][j]], T3[kSym[2][j]], i, N[i][j]);
      }
    }
    const V s2 = s * s, c2 = c * c;
    for (int u = 0; u < 6; ++u) {
      const int i = kUpperRow[u], j = kUpperCol[u];
      V LNt;  // (L N^T)(i, j) = (l x N(j, :))_i
      CrossRow(l, N[j][0], N[j][1], N[j][2], i, LNt);
      const V tl = s2 * T1[u] + s * (Y[i][j] + Y[j][i]) + LNt;
      const V br = c2 * T3[u];
      Accumulate(sums, Sums::kTL + u, j0, tl);
      Accumulate(sums, Sums::kBR + u, j0, br);
    }
    V M[3][3];  // s T2 + N
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        M[i][j] = s * T2[i][j] + N[i][j];
        const V tr = c * M[i][j];
        Accumulate(sums, Sums::kTR + 3 * i + j, j0, tr);
      }
    }
    if constexpr (kWithO) {
      Load(in, LaneRow::kD, j0, d);
      const V cd = c * d, d2 = d * d;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          const V trd = d * M[i][j];
          Accumulate(sums, Sums::kTRd + 3 * i + j, j0, trd);
        }
      }
      for (int u = 0; u < 6; ++u) {
        const V brcd = cd * T3[u], brdd = d2 * T3[u];
        Accumulate(sums, Sums::kBRcd + u, j0, brcd);
        Accumulate(sums, Sums::kBRdd + u, j0, brdd);
      }
    }
  }
}

template <class V>
[[gnu::always_inline]] inline void SumLanesOf(const double* in, int n, const Eigen::Vector3d& e,
                                              const Eigen::Vector3d& f, bool with_o,
                                              Sums& sums) noexcept {
  if (with_o) return SumLanes<V, true>(in, n, e, f, sums);
  SumLanes<V, false>(in, n, e, f, sums);
}

#if defined(__x86_64__) && !(defined(__AVX2__) && defined(__FMA__))
#define SEMGRAPH_LANES_DISPATCH 1
// The same kernel built for AVX2 + FMA (the build targets less; the CPU is checked first).
__attribute__((target("avx2,fma"))) void SumLanesAvx2(const double* in, int n,
                                                      const Eigen::Vector3d& e,
                                                      const Eigen::Vector3d& f, bool with_o,
                                                      Sums& sums) noexcept {
  SumLanesOf<Lanes4>(in, n, e, f, with_o, sums);
}
#endif

// The symmetric 3x3 with this upper triangle.
Eigen::Matrix3d Symmetric(const double* lanes_total) noexcept {
  Eigen::Matrix3d X;
  for (int u = 0; u < 6; ++u) {
    X(kUpperRow[u], kUpperCol[u]) = X(kUpperCol[u], kUpperRow[u]) = lanes_total[u];
  }
  return X;
}

}  // namespace

bool PoseEdgeLanesUseAvx2() noexcept {
#if defined(SEMGRAPH_LANES_DISPATCH)
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#elif defined(__AVX2__) && defined(__FMA__)
  return true;
#else
  return false;
#endif
}

void SumPoseEdgeLanes(const double* in, int n, const Eigen::Vector3d& e, const Eigen::Vector3d& f,
                      bool with_o, PoseCovarianceSums& sums) noexcept {
#if defined(SEMGRAPH_LANES_DISPATCH)
  if (PoseEdgeLanesUseAvx2()) return SumLanesAvx2(in, n, e, f, with_o, sums);
  SumLanesOf<Lanes2>(in, n, e, f, with_o, sums);
#elif defined(__AVX2__) && defined(__FMA__)
  SumLanesOf<Lanes4>(in, n, e, f, with_o, sums);
#else
  SumLanesOf<Lanes2>(in, n, e, f, with_o, sums);
#endif
}

void SumPoseEdgeLanesSse2(const double* in, int n, const Eigen::Vector3d& e,
                          const Eigen::Vector3d& f, bool with_o,
                          PoseCovarianceSums& sums) noexcept {
  SumLanesOf<Lanes2>(in, n, e, f, with_o, sums);
}

void PoseCovarianceSums::AddTo(coord::Covariance6& S_Z, const Eigen::Matrix3d& O) const noexcept {
  double t[kEntries];
  for (int k = 0; k < (with_o ? kEntries : kTRd); ++k) {
    t[k] = (lane[k][0] + lane[k][1]) + (lane[k][2] + lane[k][3]);
  }
  for (int u = 0; u < 6; ++u) {
    const int i = kUpperRow[u], j = kUpperCol[u];
    S_Z(i, j) += t[kTL + u];
    S_Z(i + 3, j + 3) += t[kBR + u];
    if (i != j) {
      S_Z(j, i) += t[kTL + u];
      S_Z(j + 3, i + 3) += t[kBR + u];
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      S_Z(i, j + 3) += t[kTR + 3 * i + j];
      S_Z(j + 3, i) += t[kTR + 3 * i + j];
    }
  }
  if (!with_o) return;
  Eigen::Matrix3d TRd;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) TRd(i, j) = t[kTRd + 3 * i + j];
  }
  const Eigen::Matrix3d TR = TRd * O.transpose();
  const Eigen::Matrix3d BRcd = Symmetric(t + kBRcd), BRdd = Symmetric(t + kBRdd);
  const Eigen::Matrix3d cross = BRcd * O.transpose();
  const Eigen::Matrix3d BR = cross + cross.transpose() + O * BRdd * O.transpose();
  S_Z.topRightCorner<3, 3>() += TR;
  S_Z.bottomLeftCorner<3, 3>() += TR.transpose();
  S_Z.bottomRightCorner<3, 3>() += BR;
}

void PoseCovarianceLanes::Flush() noexcept {
  PadLanes(x_, n_);
  SumPoseEdgeLanes(x_, n_, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), with_o_, sums_);
  n_ = 0;
}

void PoseCovarianceLanes::AddTo(coord::Covariance6& S_Z) noexcept {
  if (n_ > 0) Flush();
  sums_.AddTo(S_Z, O_);
}

}  // namespace semgraph::core::internal
