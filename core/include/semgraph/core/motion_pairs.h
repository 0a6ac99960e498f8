// The compiled acceleration query's per-edge arithmetic in lane pairs: a motion (evaluate.h's
// Motion: v, w, a, alpha of one relation at one point in one frame) held as the three pairs
// (v_i, a_i) and the three pairs (w_i, alpha_i), i = x, y, z, so that every rotation, cross
// product and sum works on two vectors at once (one SSE2 instruction per pair on x86-64; GCC's and
// Clang's vector extension, plain pairs of doubles elsewhere).
//
// Why a second form of the same math: EdgeMotion, RotateMotion, ShiftMotion and
// AccelerationComposer (evaluate.h) in Eigen's 3-vectors cost the compiled query about 490
// instructions per edge against the hand-written chain's 361: the scalar 3x3 products and the
// four vectors spilled between the stages. Fused and paired, an edge costs about 375 (callgrind,
// docs/performance.md "Accelerations"). The one-shot query keeps the staged kernels (its steps
// move and rotate through their own chains); motion_pairs_test checks the functions here against
// them (LoadEdgeMotion: compiled_acceleration_test, against the one-shot query).
//
// Invariants: the formulas are evaluate.h's (docs/dynamics.md section 7); lane 0 holds the
// twist, lane 1 the acceleration. Costs: every function is O(1), noexcept, allocation-free.
#pragma once

#include <Eigen/Core>
#include <utility>

#include "semgraph/core/edge_values.h"
#include "semgraph/core/evaluate.h"
#include "semgraph/core/lane_pairs.h"

namespace semgraph::core::internal {

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

/// A twist edge's record (v, w, a, alpha of D to H at Ho in [H]) as pairs.
[[gnu::always_inline]] inline MotionPairs Pairs(const TwistAndAcceleration& r) noexcept {
  const Eigen::Vector3d &v = r.V.v_DHo_H, &w = r.V.w_DH_H, &a = r.A.a_DHo_H,
                        &alpha = r.A.alpha_DH_H;
  return MotionPairs{{{v.x(), a.x()}, {v.y(), a.y()}, {v.z(), a.z()}},
                     {{w.x(), alpha.x()}, {w.y(), alpha.y()}, {w.z(), alpha.z()}}};
}

/// FlatSource::LoadAcceleration(value, s, r) into pairs: a twist edge's record and its
/// `present` word (0: no acceleration). At the current values the record's words go from its
/// sequence lock straight into the lanes (SeqLockValue::LoadWordPairs: no shuffle, no copy
/// through memory); at a time, through the timed read. False when the edge was removed.
template <class Source>
[[gnu::always_inline]] inline bool LoadEdgeMotion(const Source& src, const AccelerationValue& value,
                                                  const TwistStep<FlatChain>& s, MotionPairs& m,
                                                  double& present) noexcept {
  if (!src.timed()) {
    // TwistAndAcceleration's words: v 0-2, w 3-5, a 6-8, alpha 9-11, present 12.
    static_assert(sizeof(TwistAndAcceleration) == 13 * sizeof(double) &&
                  AccelerationValue::kWords == 13);
    AccelerationValue::WordPair p[7];
    if (!value.LoadWordPairs(p, std::index_sequence<0, 1, 2, 3, 4, 5, 12>{},
                             std::index_sequence<6, 7, 8, 9, 10, 11, 12>{},
                             AccelerationValue::ExpectedHeader(s.epoch))) {
      return false;
    }
    m = MotionPairs{{p[0], p[1], p[2]}, {p[3], p[4], p[5]}};
    present = p[6][0];
    return true;
  }
  // Zeroed: a timed read leaves an absent acceleration unwritten.
  TwistAndAcceleration r{{}, {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}, 0.0};
  if (!src.LoadAcceleration(value, s, r)) return false;
  m = Pairs(r);
  present = r.present;
  return true;
}

/// RotateMotion on pairs: x re-expressed with R (R_new_old), one 3x3 matrix for both lanes.
[[gnu::always_inline]] inline MotionPairs RotatePairs(const RotationPairs& R,
                                                      const MotionPairs& x) noexcept {
  MotionPairs m;
  for (int i = 0; i < 3; ++i) {
    m.va[i] = R.r[i][0] * x.va[0] + R.r[i][1] * x.va[1] + R.r[i][2] * x.va[2];
    m.wl[i] = R.r[i][0] * x.wl[0] + R.r[i][1] * x.wl[1] + R.r[i][2] * x.wl[2];
  }
  return m;
}

/// EdgeMotion's inversion on pairs, in place: a' = -a + 2 w x v, the rest negated.
[[gnu::always_inline]] inline void InvertPairs(MotionPairs& m) noexcept {
  const double w0[3] = {m.wl[0][0], m.wl[1][0], m.wl[2][0]};
  const Pair v0[3] = {Pair{m.va[0][0], 0.0}, Pair{m.va[1][0], 0.0}, Pair{m.va[2][0], 0.0}};
  Pair wv[3];
  CrossPairs(w0, v0, wv);
  for (int i = 0; i < 3; ++i) {
    m.va[i] = Pair{-m.va[i][0], 2.0 * wv[i][0] - m.va[i][1]};
    m.wl[i] = -m.wl[i];
  }
}

/// ShiftMotion(m, p) on pairs, in place: v += p x w, a += p x alpha + w x (p x w) (=
/// ShiftMotion's a + p x alpha - w x (w x p)).
[[gnu::always_inline]] inline void ShiftPairs(const Eigen::Vector3d& p, MotionPairs& m) noexcept {
  const double p_[3] = {p.x(), p.y(), p.z()};
  Pair pxwl[3];  // (p x w, p x alpha)
  CrossPairs(p_, m.wl, pxwl);
  const double w0[3] = {m.wl[0][0], m.wl[1][0], m.wl[2][0]};
  Pair wxpw[3];  // lane 0: w x (p x w)
  CrossPairs(w0, pxwl, wxpw);
  for (int i = 0; i < 3; ++i) m.va[i] += pxwl[i] + Pair{0.0, wxpw[i][0]};
}

/// EdgeMotion(r, invert), then RotateMotion with R (R_ZH), then ShiftMotion with p (h - Zo, in
/// [Z]), fused: the motion of a twist edge's relation at Z's origin in [Z] (r: Pairs(record)).
/// The rotation goes first (it commutes with the inversion's cross product: R (w x v) =
/// Rw x Rv).
[[gnu::always_inline]] inline MotionPairs MovedEdgeMotion(const MotionPairs& r, bool invert,
                                                          const RotationPairs& R,
                                                          const Eigen::Vector3d& p) noexcept {
  MotionPairs m = RotatePairs(R, r);
  if (invert) InvertPairs(m);
  ShiftPairs(p, m);
  return m;
}
/// The same from a record.
[[gnu::always_inline]] inline MotionPairs MovedEdgeMotion(const TwistAndAcceleration& r,
                                                          bool invert, const Eigen::Matrix3d& R,
                                                          const Eigen::Vector3d& p) noexcept {
  return MovedEdgeMotion(Pairs(r), invert, R, p);
}

/// X then Y at one point in one frame, in place (X = X then Y): AccelerationComposer's
/// composition (evaluate.h) on pairs: alpha += alpha_Y + w_X x w_Y, a += a_Y + 2 w_X x v_Y,
/// twists summed; the cross products in one paired pass, w_X x (w_Y_i, v_Y_i).
///
/// The composition is associative, so AccelerationComposer's two sides (D's appended in the
/// plan's order, C's prepended) are one running product: D's steps in order, then C's in
/// reverse, each appended. The compiled query orders its steps so: one loop, no branch on the
/// side, no final composition of the sides.
[[gnu::always_inline]] inline void ThenPairs(MotionPairs& X, const MotionPairs& Y) noexcept {
  const double w_X[3] = {X.wl[0][0], X.wl[1][0], X.wl[2][0]};
  const Pair wv_Y[3] = {Pair{Y.wl[0][0], Y.va[0][0]}, Pair{Y.wl[1][0], Y.va[1][0]},
                        Pair{Y.wl[2][0], Y.va[2][0]}};
  Pair x[3];  // (w_X x w_Y, w_X x v_Y)
  CrossPairs(w_X, wv_Y, x);
  for (int i = 0; i < 3; ++i) {
    X.wl[i] += Y.wl[i] + Pair{0.0, x[i][0]};
    X.va[i] += Y.va[i] + Pair{0.0, 2.0 * x[i][1]};
  }
}

}  // namespace semgraph::core::internal
