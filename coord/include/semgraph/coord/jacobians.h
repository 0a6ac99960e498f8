// File: semgraph/coord/jacobians.h
//
// The Jacobians of every evaluation step, in one place (docs/uncertainty.md, "Propagation").
// Every perturbation is in the `coordinates` convention: a pose X = (R, p) perturbed by
// d = (dp, dth) is (Exp(dth) R, p + dp), dth a rotation vector in X's [r]; a twist (v, w) by
// (dv, dw) is (v + dv, w + dw). Rows and columns are linear first.
//
//   Compose      X_AC = X_AB X_BC:  J_AB = [[I, -[R_AB p_BC]x], [0, I]],
//                                   J_BC = diag(R_AB, R_AB)
//   Inverse      X_BA = X_AB^-1:    J = [[-R^T, -R^T [p]x], [0, -R^T]]
//   Extrapolate  Y = X Exp(dt xi):  J_X = [[I, -[R u]x], [0, I]]  (u: translation of Exp)
//                                   J_xi = diag(R, R) [[Jl dt, (Q - [u]x Jl) dt], [0, Jl dt]]
//                (Jl: the left Jacobian of SO(3) at phi = dt w, Q: Barfoot's Q(dt v, phi))
//   Derive       a pose edge's screw twist from its two bracketing samples (twist source
//                `poses`), per sample: LinearSegmentTwistJacobians, ScrewSegmentTwistJacobians
//   Edge on a query answer: an edge {p} -> {g}'s perturbation moves every frame below g
//     rigidly: in a common frame Z, a rotation x = R_ZP dth about g's origin and a translation
//     t = R_ZP dp. EdgeOnPose / EdgeOnTwist give the answer's change for the frames that move
//     (PoseMoves / the steps' flags): the one formula behind every pose, position, orientation
//     and twist query, whatever the path (docs/uncertainty.md derives them).
// All functions are noexcept, allocation-free, O(1) (fixed-size Eigen).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "semgraph/coord/covariance.h"
#include "semgraph/coord/se3.h"

namespace semgraph::coord::jacobians {

using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Eigen::Matrix3d;
using Eigen::Vector3d;

/// [v]x: the cross-product matrix, [v]x y = v x y.
[[nodiscard]] inline Matrix3d Hat(const Vector3d& v) noexcept {
  Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// S_out += J S J^T for a J whose bottom-left block is zero, J = [[A, B], [0, C]] (every
/// Jacobian here: rotations do not depend on translations): nine 3x3 products instead of the
/// dense form's 432 multiply-adds.
inline void AddPropagated(const Matrix6& J, const Covariance6& S, Covariance6& S_out) noexcept {
  const auto A = J.topLeftCorner<3, 3>(), B = J.topRightCorner<3, 3>();
  const auto C = J.bottomRightCorner<3, 3>();
  const auto S11 = S.topLeftCorner<3, 3>(), S12 = S.topRightCorner<3, 3>();
  const auto S21 = S.bottomLeftCorner<3, 3>(), S22 = S.bottomRightCorner<3, 3>();
  Matrix3d U, V;
  U.noalias() = A * S11;
  U.noalias() += B * S21;
  V.noalias() = A * S12;
  V.noalias() += B * S22;
  Matrix3d TL, TR, BR, CS;
  TL.noalias() = U * A.transpose();
  TL.noalias() += V * B.transpose();
  TR.noalias() = V * C.transpose();
  CS.noalias() = C * S22;
  BR.noalias() = CS * C.transpose();
  S_out.topLeftCorner<3, 3>() += TL;
  S_out.topRightCorner<3, 3>() += TR;
  S_out.bottomLeftCorner<3, 3>() += TR.transpose();
  S_out.bottomRightCorner<3, 3>() += BR;
}

// ============================================================ pose steps

/// X_AC = X_AB X_BC: the answer's perturbation from each factor's.
inline void Compose(const Matrix3d& R_AB, const Vector3d& p_AB, const Matrix3d& R_BC,
                    const Vector3d& p_BC, Matrix6& J_AB, Matrix6& J_BC) noexcept {
  (void)p_AB;  // the translation of the left factor does not enter (d p_AC / d p_AB = I)
  (void)R_BC;
  J_AB.setIdentity();
  J_AB.topRightCorner<3, 3>() = -Hat(R_AB * p_BC);
  J_BC.setZero();
  J_BC.topLeftCorner<3, 3>() = R_AB;
  J_BC.bottomRightCorner<3, 3>() = R_AB;
}

/// X_BA = X_AB^-1.
[[nodiscard]] inline Matrix6 Inverse(const Matrix3d& R_AB, const Vector3d& p_AB) noexcept {
  Matrix6 J = Matrix6::Zero();
  const Matrix3d Rt = R_AB.transpose();
  J.topLeftCorner<3, 3>() = -Rt;
  J.topRightCorner<3, 3>() = -Rt * Hat(p_AB);
  J.bottomRightCorner<3, 3>() = -Rt;
  return J;
}

/// The covariance of X_AC = X_AB X_BC from independent factors (coordinates convention).
[[nodiscard]] inline Covariance6 ComposeCovariance(const Eigen::Isometry3d& X_AB,
                                                   const Covariance6& S_AB,
                                                   const Eigen::Isometry3d& X_BC,
                                                   const Covariance6& S_BC) noexcept {
  Matrix6 J_AB, J_BC;
  Compose(X_AB.linear(), X_AB.translation(), X_BC.linear(), X_BC.translation(), J_AB, J_BC);
  Covariance6 S = Covariance6::Zero();
  AddPropagated(J_AB, S_AB, S);
  AddPropagated(J_BC, S_BC, S);
  return S;
}

/// The covariance of X_BA = X_AB^-1 (coordinates convention).
[[nodiscard]] inline Covariance6 InverseCovariance(const Eigen::Isometry3d& X_AB,
                                                   const Covariance6& S_AB) noexcept {
  Covariance6 S = Covariance6::Zero();
  AddPropagated(Inverse(X_AB.linear(), X_AB.translation()), S_AB, S);
  return S;
}

// ============================================================ SO(3) / SE(3) pieces

/// The left Jacobian of SO(3) at phi: Exp(phi + d) = Exp(Jl d) Exp(phi) to first order. It is
/// also the matrix V of SE(3)'s Exp (se3.h): Exp(v, w) = (exp([w]x), Jl(w) v).
[[nodiscard]] inline Matrix3d LeftJacobianSO3(const Vector3d& phi) noexcept {
  const double th = phi.norm();
  double a, b;  // (1 - cos th) / th^2, (th - sin th) / th^3
  if (th < 0.1) {
    const double t2 = th * th;
    a = 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0));
    b = 1.0 / 6.0 - t2 / 120.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0));
  } else {
    const double s = std::sin(0.5 * th);
    a = 2.0 * s * s / (th * th);
    b = (th - std::sin(th)) / (th * th * th);
  }
  const Matrix3d W = Hat(phi);
  return Matrix3d::Identity() + a * W + b * W * W;
}

/// Barfoot's Q(rho, phi): d(Jl(phi) rho)/d phi = Q - [Jl rho]x Jl (see ExtrapolateJacobians).
[[nodiscard]] inline Matrix3d BarfootQ(const Vector3d& rho, const Vector3d& phi) noexcept {
  const double th = phi.norm();
  double c1, c2, c3;
  if (th < 0.1) {  // series: no cancellation at small angles
    const double t2 = th * th;
    c1 = 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0;
    c2 = 1.0 / 24.0 - t2 / 720.0 + t2 * t2 / 40320.0;
    c3 = 1.0 / 120.0 - t2 / 2520.0 + t2 * t2 / 120960.0;
  } else {
    const double s = std::sin(th), c = std::cos(th);
    const double t2 = th * th;
    c1 = (th - s) / (t2 * th);
    c2 = (t2 + 2.0 * c - 2.0) / (2.0 * t2 * t2);
    c3 = (2.0 * th - 3.0 * s + th * c) / (2.0 * t2 * t2 * th);
  }
  const Matrix3d P = Hat(phi), Rh = Hat(rho);
  const Matrix3d PR = P * Rh, RP = Rh * P, PRP = PR * P;
  return 0.5 * Rh + c1 * (PR + RP + PRP) + c2 * (P * PR + RP * P - 3.0 * PRP) +
         c3 * (PRP * P + P * PRP);
}

/// Y = X Exp(dt xi), xi = (v, w) the edge's screw twist in [h] (se3.h): the answer's
/// perturbation from X's (J_X) and from xi's (J_xi, with (dv, dw) in [h]).
inline void ExtrapolateJacobians(const Matrix3d& R, const Vector3d& v, const Vector3d& w, double dt,
                                 Matrix6& J_X, Matrix6& J_xi) noexcept {
  const Vector3d phi = dt * w, rho = dt * v;
  const Matrix3d Jl = LeftJacobianSO3(phi);
  const Vector3d u = Jl * rho;  // translation of Exp(dt xi)
  J_X.setIdentity();
  J_X.topRightCorner<3, 3>() = -Hat(R * u);
  Matrix6 J_exp = Matrix6::Zero();  // Exp(dt xi) in the coordinates convention, per d xi
  J_exp.topLeftCorner<3, 3>() = dt * Jl;
  J_exp.topRightCorner<3, 3>() = dt * (BarfootQ(rho, phi) - Hat(u) * Jl);
  J_exp.bottomRightCorner<3, 3>() = dt * Jl;
  J_xi.topRows<3>() = R * J_exp.topRows<3>();
  J_xi.bottomRows<3>() = R * J_exp.bottomRows<3>();
}

/// The inverse of the left Jacobian of SO(3): I - [phi]x / 2 + c [phi]x^2,
/// c = (1 - (th/2) cot(th/2)) / th^2 (series below th = 0.1), |phi| = th < 2 pi.
[[nodiscard]] inline Matrix3d LeftJacobianInverseSO3(const Vector3d& phi) noexcept {
  const double c = kernels::LeftJacobianInverseC(phi.norm());
  const Matrix3d W = Hat(phi);
  return Matrix3d::Identity() - 0.5 * W + c * W * W;
}

/// The derivative of a pose edge's linear interpolation (se3.h SegmentTwist, linear):
///   w = Log(R0^T R1) / dt,  v = R_l^T (p1 - p0) / dt,  R_l = R0 Exp(l phi),  phi = Log(R0^T R1),
/// by each sample's perturbation (coordinates convention, (dp, dth) in [t]): with
/// D = Jl(phi)^-1 R0^T (d phi = D (dth1 - dth0)), u = R_l^T (p1 - p0) and K = l [u]x Jr(l phi) D
/// (Jr(x) = Jl(-x)):
///   J1 = [[R_l^T, K], [0, D]] / dt,   J0 = [[-R_l^T, R_l^T [p1 - p0]x - K], [0, -D]] / dt.
inline void LinearSegmentTwistJacobians(const Matrix3d& R0, const Matrix3d& R_l,
                                        const Vector3d& phi, const Vector3d& p1_minus_p0, double dt,
                                        double lambda, Matrix6& J0, Matrix6& J1) noexcept {
  const Matrix3d D = LeftJacobianInverseSO3(phi) * R0.transpose();
  const Vector3d u = R_l.transpose() * p1_minus_p0;
  const Matrix3d K = lambda * Hat(u) * LeftJacobianSO3(-lambda * phi) * D;
  const double k = 1.0 / dt;
  J1.setZero();
  J1.topLeftCorner<3, 3>() = k * R_l.transpose();
  J1.topRightCorner<3, 3>() = k * K;
  J1.bottomRightCorner<3, 3>() = k * D;
  J0.setZero();
  J0.topLeftCorner<3, 3>() = -k * R_l.transpose();
  J0.topRightCorner<3, 3>() = k * (R_l.transpose() * Hat(p1_minus_p0) - K);
  J0.bottomRightCorner<3, 3>() = -k * D;
}

/// The derivative of a pose edge's screw interpolation (se3.h SegmentTwist, screw):
/// xi = Log(X0^-1 X1) / dt, xi_hat = Log(X0^-1 X1) = (rho, phi), by each sample's perturbation.
/// A perturbation (dp, dth) of X = (R, p) is the left one Exp(eta) X with eta = L(p) d,
/// L(p) = [[I, [p]x], [0, I]]; X0^-1 X1 then turns into Exp(Ad(X0^-1) (eta1 - eta0)) X0^-1 X1 and
/// Log(Exp(b) Exp(xi_hat)) = xi_hat + JL^-1 b, JL = [[Jl, Q], [0, Jl]] SE(3)'s left Jacobian at
/// xi_hat (Barfoot's), JL^-1 = [[Jl^-1, -Jl^-1 Q Jl^-1], [0, Jl^-1]]. With
/// Ad(X0^-1) L(p1) = [[R0^T, R0^T [p1 - p0]x], [0, R0^T]] and Ad(X0^-1) L(p0) = diag(R0^T, R0^T):
///   J1 = JL^-1 [[R0^T, R0^T [p1 - p0]x], [0, R0^T]] / dt,   J0 = -JL^-1 diag(R0^T, R0^T) / dt.
inline void ScrewSegmentTwistJacobians(const Matrix3d& R0, const Vector3d& p1_minus_p0,
                                       const Vector3d& rho, const Vector3d& phi, double dt,
                                       Matrix6& J0, Matrix6& J1) noexcept {
  const Matrix3d Ji = LeftJacobianInverseSO3(phi);
  const Matrix3d B = -Ji * BarfootQ(rho, phi) * Ji;  // top right of JL^-1
  const Matrix3d Rt = R0.transpose();
  const double k = 1.0 / dt;
  J0.setZero();
  J0.topLeftCorner<3, 3>() = -k * Ji * Rt;
  J0.topRightCorner<3, 3>() = -k * B * Rt;
  J0.bottomRightCorner<3, 3>() = -k * Ji * Rt;
  J1.setZero();
  J1.topLeftCorner<3, 3>() = k * Ji * Rt;
  J1.topRightCorner<3, 3>() = k * (Ji * Rt * Hat(p1_minus_p0) + B * Rt);
  J1.bottomRightCorner<3, 3>() = k * Ji * Rt;
}

// ============================================================ edges on a query's answer

/// An edge {p} -> {g} seen from a common frame Z: R_ZP (the tail's axes) and g's origin.
struct EdgeInZ {
  Matrix3d R_ZP;
  Vector3d p_ZoGo_Z;
};

/// A pose answer (e,[a]) wrt (f,[b]) in [r], seen from Z: R_RZ, the points e and f, and the
/// orientation operator O = R_ZA R_ZB^T (carrying [b] onto [a], in Z).
struct PoseInZ {
  Matrix3d R_RZ;
  Vector3d p_ZoEo_Z, p_ZoFo_Z;
  Matrix3d O_Z;
};
/// Which of the answer's frames an edge moves (lie below the edge's head, or are it).
struct PoseMoves {
  bool e = false, f = false, a = false, b = false, r = false;
};

/// The parts of d(answer) / d(edge) for a pose answer, rows in Z (dp_Z, dth_Z), columns the
/// edge's (dp, dth) in [p], R = R_ZP:
///   J = [[s R, [lever]x R], [0, (c I + d O) R]],  s, c, d in {-1, 0, 1}.
/// Per (t, x) of the edge: dp_Z = (m_e - m_f) t + (m_e [g - e]x - m_f [g - f]x + m_r [e - f]x) x,
/// dth_Z = ((m_a - m_r) I + (m_r - m_b) O) x; then columns R_ZP.
struct PoseEdgeFactors {
  double s = 0.0, c = 0.0, d = 0.0;
  Vector3d lever = Vector3d::Zero();  // linear in the points
};
[[nodiscard]] inline PoseEdgeFactors EdgeOnPoseFactors(const PoseInZ& q, const EdgeInZ& edge,
                                                       const PoseMoves& m) noexcept {
  const Vector3d& e = q.p_ZoEo_Z;
  const Vector3d& f = q.p_ZoFo_Z;
  const Vector3d& g = edge.p_ZoGo_Z;
  PoseEdgeFactors k;
  if (m.e) k.lever += g - e;
  if (m.f) k.lever -= g - f;
  if (m.r) k.lever += e - f;
  k.s = static_cast<double>(m.e) - static_cast<double>(m.f);
  k.c = static_cast<double>(m.a) - static_cast<double>(m.r);
  k.d = static_cast<double>(m.r) - static_cast<double>(m.b);
  return k;
}

/// d(answer) / d(edge) for a pose answer, with the answer's rows still in Z (dp_Z, dth_Z; the
/// answer in [r] is diag(R_RZ, R_RZ) times this): what a sum over many edges accumulates, so
/// that the rotation into [r] is done once. Columns: the edge's (dp, dth) in [p]. The parts:
/// EdgeOnPoseFactors.
[[nodiscard]] inline Matrix6 EdgeOnPoseInZ(const PoseInZ& q, const EdgeInZ& edge,
                                           const PoseEdgeFactors& k) noexcept {
  Matrix6 J = Matrix6::Zero();
  if (k.s != 0.0) J.topLeftCorner<3, 3>() = k.s * edge.R_ZP;
  J.topRightCorner<3, 3>().noalias() = Hat(k.lever) * edge.R_ZP;
  if (k.d != 0.0) J.bottomRightCorner<3, 3>().noalias() = k.d * q.O_Z * edge.R_ZP;
  if (k.c != 0.0) J.bottomRightCorner<3, 3>() += k.c * edge.R_ZP;
  return J;
}
/// The same from the moves flags.
[[nodiscard]] inline Matrix6 EdgeOnPoseInZ(const PoseInZ& q, const EdgeInZ& edge,
                                           const PoseMoves& m) noexcept {
  return EdgeOnPoseInZ(q, edge, EdgeOnPoseFactors(q, edge, m));
}

/// d(answer) / d(edge) for a pose answer: rows (dp, dth) of the answer in [r], columns the
/// edge's (dp, dth) in [p]. (A position answer is the top rows, an orientation the bottom.)
[[nodiscard]] inline Matrix6 EdgeOnPose(const PoseInZ& q, const EdgeInZ& edge,
                                        const PoseMoves& m) noexcept {
  Matrix6 J = EdgeOnPoseInZ(q, edge, m);
  J.topRows<3>() = q.R_RZ * J.topRows<3>();
  J.bottomRows<3>() = q.R_RZ * J.bottomRows<3>();
  return J;
}

/// S_Z (rows and columns in Z) as rows and columns in [r]: diag(R_RZ, R_RZ) S_Z diag^T.
[[nodiscard]] inline Covariance6 RotateRows(const Matrix3d& R_RZ, const Covariance6& S_Z) noexcept {
  // Block by block (three 3x3 congruences; the lower-left block is the upper-right's transpose):
  // the same numbers as AddPropagated with diag(R_RZ, R_RZ), without its products by zero blocks.
  Matrix3d U, TL, TR, BR;
  U.noalias() = R_RZ * S_Z.topLeftCorner<3, 3>();
  TL.noalias() = U * R_RZ.transpose();
  U.noalias() = R_RZ * S_Z.topRightCorner<3, 3>();
  TR.noalias() = U * R_RZ.transpose();
  U.noalias() = R_RZ * S_Z.bottomRightCorner<3, 3>();
  BR.noalias() = U * R_RZ.transpose();
  Covariance6 S;
  S.topLeftCorner<3, 3>() = TL;
  S.topRightCorner<3, 3>() = TR;
  S.bottomLeftCorner<3, 3>() = TR.transpose();
  S.bottomRightCorner<3, 3>() = BR;
  return S;
}

/// One twist edge's contribution to a twist answer at e, seen from Z: its twist (the signed
/// stored one, rotated into Z: a_Z = s R_ZH v at h, w_Z = s R_ZH w) and the point h; moved to
/// e it is (a_Z + w_Z x (e - h), w_Z).
struct TwistStepInZ {
  Vector3d a_Z, w_Z;
  Vector3d p_ZoHo_Z;
  bool moves = false;  ///< h lies below the edge being differentiated (filled per edge)
};

/// d(answer) / d(twist edge): rows (dv, dw) of the answer (at e, in [r]), columns the edge's
/// (dv, dw) in [h]; s = -1 when traversed against its direction (or subtracted).
[[nodiscard]] inline Matrix6 TwistEdgeOnTwist(const Matrix3d& R_RZ, const Matrix3d& R_ZH,
                                              const Vector3d& p_ZoHo_Z, const Vector3d& p_ZoEo_Z,
                                              double s) noexcept {
  // v_Z = R_ZH v + (R_ZH w) x (e - h), w_Z = R_ZH w.
  const Matrix3d RRH = s * R_RZ * R_ZH;
  Matrix6 J = Matrix6::Zero();
  J.topLeftCorner<3, 3>() = RRH;
  J.topRightCorner<3, 3>() = -R_RZ * Hat(p_ZoEo_Z - p_ZoHo_Z) * (s * R_ZH);
  J.bottomRightCorner<3, 3>() = RRH;
  return J;
}

/// A pose edge's Jacobian on a twist answer, accumulated step by step (in Z, per (t, x)):
/// the moved points and rotated twists of the steps (v_Z = a_Z + w_Z x (e - h)), e's motion,
/// then [r]'s rotation and the edge's axes (Finish).
struct PoseEdgeOnTwistSum {
  Matrix3d Vx = Matrix3d::Zero(), Vt = Matrix3d::Zero(), Wx = Matrix3d::Zero();

  /// One step; m_e whether e moves with the edge.
  void Add(const TwistStepInZ& st, const Vector3d& p_ZoEo_Z, const EdgeInZ& edge,
           bool m_e) noexcept {
    const Matrix3d Wh = Hat(st.w_Z);
    if (st.moves) {  // h and [h] move: the step's twist rotates by x, h moves with (t, x)
      const Vector3d& h = st.p_ZoHo_Z;
      Vx += -Hat(st.a_Z) + Hat(p_ZoEo_Z - h) * Wh + Wh * Hat(h - edge.p_ZoGo_Z);
      Vt -= Wh;
      Wx -= Wh;
    }
    if (m_e) {  // e moves: v_Z changes by w_Z x (t + x x (e - g))
      Vt += Wh;
      Vx -= Wh * Hat(p_ZoEo_Z - edge.p_ZoGo_Z);
    }
  }
  /// Rows (dv, dw) of the answer in [r], columns the edge's (dp, dth) in [p]. `answer_Z`: the
  /// whole answer in Z; m_r whether [r] moves (d(R_RZ y) = R_RZ [y]x x).
  [[nodiscard]] Matrix6 Finish(const Matrix3d& R_RZ, const Vector3d& v_answer_Z,
                               const Vector3d& w_answer_Z, const EdgeInZ& edge,
                               bool m_r) const noexcept {
    Matrix3d vx = Vx, wx = Wx;
    if (m_r) {
      vx += Hat(v_answer_Z);
      wx += Hat(w_answer_Z);
    }
    Matrix6 J = Matrix6::Zero();
    J.topLeftCorner<3, 3>() = R_RZ * Vt * edge.R_ZP;
    J.topRightCorner<3, 3>() = R_RZ * vx * edge.R_ZP;
    J.bottomRightCorner<3, 3>() = R_RZ * wx * edge.R_ZP;
    return J;
  }
};

/// The same over a container of steps.
template <class Steps>
[[nodiscard]] Matrix6 PoseEdgeOnTwist(const Matrix3d& R_RZ, const Vector3d& p_ZoEo_Z,
                                      const Vector3d& v_answer_Z, const Vector3d& w_answer_Z,
                                      const Steps& steps, const EdgeInZ& edge, bool m_e,
                                      bool m_r) noexcept {
  PoseEdgeOnTwistSum sum;
  for (const TwistStepInZ& st : steps) sum.Add(st, p_ZoEo_Z, edge, m_e);
  return sum.Finish(R_RZ, v_answer_Z, w_answer_Z, edge, m_r);
}

// ============================================================ conversions of a given value

/// d(answer) for a re-expression X -> (R M R^T, R p) (poses) or (R v, R w) (twists).
[[nodiscard]] inline Matrix6 Reexpress(const Matrix3d& R) noexcept {
  Matrix6 J = Matrix6::Zero();
  J.topLeftCorner<3, 3>() = R;
  J.bottomRightCorner<3, 3>() = R;
  return J;
}
/// d(answer) for a point moved with the pose's rotation: p -> p + R u (u fixed in the pose's
/// own axes, d = R u): dp' = dp - [d]x dth.
[[nodiscard]] inline Matrix6 MovePoint(const Vector3d& d) noexcept {
  Matrix6 J = Matrix6::Identity();
  J.topRightCorner<3, 3>() = -Hat(d);
  return J;
}
}  // namespace semgraph::coord::jacobians
