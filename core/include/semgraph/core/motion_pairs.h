// The compiled acceleration query's per-edge arithmetic in lane pairs: a motion (evaluate.h's
// Motion: v, w, a, alpha of one relation at one point in one frame) held as the three pairs
// (v_i, a_i) and the three pairs (w_i, alpha_i), i = x, y, z, so that every rotation, cross
// product and sum works on two vectors at once (one SSE2 instruction per pair on x86-64; GCC's and
// Clang's vector extension, plain pairs of doubles elsewhere).
//
// Why a second form of the same math: EdgeMotion, RotateMotion, ShiftMotion and
// AccelerationComposer (evaluate.h) in Eigen's 3-vectors cost the compiled query about 490
// instructions per edge against the hand-written chain's 361: the scalar 3x3 products and the
// four vectors spilled between the stages. Fused and paired, an edge costs about 410 (callgrind,
// docs/performance.md "Accelerations"). The one-shot query keeps the staged kernels (its steps
// move and rotate through their own chains); motion_pairs_test checks each function here against
// them.
//
// Invariants: the formulas are evaluate.h's (docs/dynamics.md section 7); lane 0 holds the
// twist, lane 1 the acceleration. Costs: every function is O(1), noexcept, allocation-free.
#pragma once

#include <Eigen/Core>

#include "semgraph/core/edge_values.h"
#include "semgraph/core/evaluate.h"

namespace semgraph::core::internal {

using Pair = double __attribute__((vector_size(16)));

/// A Motion as pairs: va[i] = (v_i, a_i), wl[i] = (w_i, alpha_i).
struct MotionPairs {
  Pair va[3];
  Pair wl[3];
  static MotionPairs Zero() noexcept {
    const Pair z{0.0, 0.0};
    return MotionPairs{{z, z, z}, {z, z, z}};
  }
  [[nodiscard]] Motion ToMotion() const noexcept {
    return Motion{{va[0][0], va[1][0], va[2][0]},
                  {wl[0][0], wl[1][0], wl[2][0]},
                  {va[0][1], va[1][1], va[2][1]},
                  {wl[0][1], wl[1][1], wl[2][1]}};
  }
};

/// s x (x_i pairs): the cross product of the 3-vector s with both lanes' vectors.
[[gnu::always_inline]] inline void CrossPairs(const double s[3], const Pair x[3],
                                              Pair out[3]) noexcept {
  out[0] = s[1] * x[2] - s[2] * x[1];
  out[1] = s[2] * x[0] - s[0] * x[2];
  out[2] = s[0] * x[1] - s[1] * x[0];
}

/// EdgeMotion(r, invert), then RotateMotion with R (R_ZH), then ShiftMotion with p (h - Zo, in
/// [Z]), fused: the motion of a twist edge's relation at Z's origin in [Z].
/// The rotation goes first (it commutes with the inversion's cross product: R (w x v) =
/// Rw x Rv); the shift is v += p x w, a += p x alpha + w x (p x w) (= ShiftMotion's
/// a + p x alpha - w x (w x p)).
[[gnu::always_inline]] inline MotionPairs MovedEdgeMotion(const TwistAndAcceleration& r,
                                                          bool invert, const Eigen::Matrix3d& R,
                                                          const Eigen::Vector3d& p) noexcept {
  const Eigen::Vector3d &v = r.V.v_DHo_H, &w = r.V.w_DH_H, &a = r.A.a_DHo_H,
                        &alpha = r.A.alpha_DH_H;
  const Pair va[3] = {{v.x(), a.x()}, {v.y(), a.y()}, {v.z(), a.z()}};
  const Pair wl[3] = {{w.x(), alpha.x()}, {w.y(), alpha.y()}, {w.z(), alpha.z()}};
  MotionPairs m;
  for (int i = 0; i < 3; ++i) {
    m.va[i] = R(i, 0) * va[0] + R(i, 1) * va[1] + R(i, 2) * va[2];
    m.wl[i] = R(i, 0) * wl[0] + R(i, 1) * wl[1] + R(i, 2) * wl[2];
  }
  if (invert) {  // a' = -a + 2 w x v, the rest negated
    const double w0[3] = {m.wl[0][0], m.wl[1][0], m.wl[2][0]};
    const Pair v0[3] = {Pair{m.va[0][0], 0.0}, Pair{m.va[1][0], 0.0}, Pair{m.va[2][0], 0.0}};
    Pair wv[3];
    CrossPairs(w0, v0, wv);
    for (int i = 0; i < 3; ++i) {
      m.va[i] = Pair{-m.va[i][0], 2.0 * wv[i][0] - m.va[i][1]};
      m.wl[i] = -m.wl[i];
    }
  }
  const double p_[3] = {p.x(), p.y(), p.z()};
  Pair pxwl[3];  // (p x w, p x alpha)
  CrossPairs(p_, m.wl, pxwl);
  const double w0[3] = {m.wl[0][0], m.wl[1][0], m.wl[2][0]};
  Pair wxpw[3];  // lane 0: w x (p x w)
  CrossPairs(w0, pxwl, wxpw);
  for (int i = 0; i < 3; ++i) m.va[i] += pxwl[i] + Pair{0.0, wxpw[i][0]};
  return m;
}

/// AccelerationComposer (evaluate.h) on MotionPairs: C's side prepended (c = m then c), D's
/// side appended (d = d then m); Result() = d then c, as a Motion.
struct MotionPairsComposer {
  MotionPairs c_side = MotionPairs::Zero(), d_side = MotionPairs::Zero();

  /// X then Y at one point, into `into` (X or Y): alpha += alpha_other + w_X x w_Y,
  /// a += a_other + 2 w_X x v_Y, twists summed. The cross products in one paired pass:
  /// w_X x (w_Y_i, v_Y_i).
  [[gnu::always_inline]] static void Compose(const MotionPairs& X, const MotionPairs& Y,
                                             MotionPairs& into, const MotionPairs& other) noexcept {
    const double w_X[3] = {X.wl[0][0], X.wl[1][0], X.wl[2][0]};
    const Pair wv_Y[3] = {Pair{Y.wl[0][0], Y.va[0][0]}, Pair{Y.wl[1][0], Y.va[1][0]},
                          Pair{Y.wl[2][0], Y.va[2][0]}};
    Pair x[3];  // (w_X x w_Y, w_X x v_Y)
    CrossPairs(w_X, wv_Y, x);
    for (int i = 0; i < 3; ++i) {
      into.wl[i] += other.wl[i] + Pair{0.0, x[i][0]};
      into.va[i] += other.va[i] + Pair{0.0, 2.0 * x[i][1]};
    }
  }
  [[gnu::always_inline]] void Add(bool ref_side, const MotionPairs& m) noexcept {
    if (ref_side) {
      Compose(d_side, m, d_side, m);
    } else {
      Compose(m, c_side, c_side, m);
    }
  }
  [[nodiscard]] Motion Result() const noexcept {
    return ComposeMotion(d_side.ToMotion(), c_side.ToMotion());
  }
};

}  // namespace semgraph::core::internal
