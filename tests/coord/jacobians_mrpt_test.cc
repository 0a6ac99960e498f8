// Cross-check of coord/jacobians.h's pose covariance propagation (ComposeCovariance,
// InverseCovariance) against a peer no one here wrote: MRPT's CPose3DPDFGaussian (Debian's
// libmrpt-poses-dev), its composition (operator+) and inversion (operator-, inverse()), on
// 1,000 random pose pairs.
//
// The two libraries' covariances mean different things, so the test converts:
//   MRPT: a Gaussian over the parameters (x, y, z, yaw, pitch, roll), perturbed additively,
//         R = Rz(yaw) Ry(pitch) Rx(roll), the pose's matrix the same as semgraph's X_AB;
//   semgraph (coordinates convention): p_true = p + dp, R_true = Exp(dtheta) R.
// To first order dp = (dx, dy, dz) and dtheta = E (dyaw, dpitch, droll) with
//   E = [ z | Rz(yaw) y | Rz(yaw) Ry(pitch) x ]   (x, y, z the unit axes)
// (each Euler angle turns about its axis as moved by the rotations applied before it), so
//   Sigma_semgraph = J Sigma_MRPT J^T,  J = diag(I, E).
// E is checked first against finite differences of MRPT's own rotation matrices, then used to
// carry random semgraph covariances into MRPT (E^-1, pitch away from +-90 deg) and MRPT's
// answers back. Two comparisons per pair:
//  - with the first-order propagation through MRPT's own pose composition and inversion
//    (CPose3D, finite differences in its Euler parameters): semgraph must agree to the
//    differences' accuracy, always;
//  - with CPose3DPDFGaussian's analytic covariances (operator+, operator-): MRPT 2.5.8 (Debian
//    12) gets the angular rows of its Jacobians negated for about a third of random pairs (its
//    6D -> quaternion -> 6D path; the finite differences of its own composition disagree with
//    it there), which leaves its answer equal to semgraph's with the position-angle cross
//    blocks negated (D S D, D = diag(I, -I)). So each pair must equal semgraph's answer or
//    exactly that flip, to rounding; the flipped pairs are counted. A fixed MRPT gives none.
// Near gimbal lock of an answer (|cos pitch| < 0.05) MRPT's Euler Jacobians lose digits: those
// pairs are counted, not compared.
#include <gtest/gtest.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "semgraph/coord/covariance.h"
#include "semgraph/coord/jacobians.h"

namespace semgraph::coord {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Matrix6 = Eigen::Matrix<double, 6, 6>;
using mrpt::poses::CPose3D;
using mrpt::poses::CPose3DPDFGaussian;

Matrix3d Rot(const Vector3d& axis, double angle) { return Eigen::AngleAxisd(angle, axis).matrix(); }

// R = Rz(yaw) Ry(pitch) Rx(roll), written here (then checked against MRPT's).
Matrix3d YawPitchRoll(double yaw, double pitch, double roll) {
  return Rot(Vector3d::UnitZ(), yaw) * Rot(Vector3d::UnitY(), pitch) * Rot(Vector3d::UnitX(), roll);
}

// J = diag(I, E): MRPT's (dx, dy, dz, dyaw, dpitch, droll) -> semgraph's (dp, dtheta).
Matrix6 MrptToCoordinates(double yaw, double pitch) {
  Matrix6 J = Matrix6::Zero();
  J.topLeftCorner<3, 3>().setIdentity();
  const Matrix3d Rz = Rot(Vector3d::UnitZ(), yaw);
  J.block<3, 1>(3, 3) = Vector3d::UnitZ();
  J.block<3, 1>(3, 4) = Rz * Vector3d::UnitY();
  J.block<3, 1>(3, 5) = Rz * Rot(Vector3d::UnitY(), pitch) * Vector3d::UnitX();
  return J;
}
Matrix6 MrptToCoordinates(const CPose3D& X) { return MrptToCoordinates(X.yaw(), X.pitch()); }

Eigen::Isometry3d IsometryOf(const CPose3D& X) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = X.getRotationMatrix().asEigen();
  out.translation() = Vector3d(X.x(), X.y(), X.z());
  return out;
}

Covariance6 ToEigen(const mrpt::math::CMatrixDouble66& m) {
  Covariance6 out;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) out(r, c) = m(r, c);
  }
  return out;
}
mrpt::math::CMatrixDouble66 ToMrpt(const Covariance6& m) {
  mrpt::math::CMatrixDouble66 out;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) out(r, c) = m(r, c);
  }
  return out;
}

struct Random {
  std::mt19937 rng{20261204};
  std::uniform_real_distribution<double> angle{-M_PI, M_PI};
  std::uniform_real_distribution<double> pitch{-1.3, 1.3};  // |pitch| < 75 deg: E invertible
  std::normal_distribution<double> normal{0.0, 1.0};

  CPose3D Pose() {
    return CPose3D(3 * normal(rng), 3 * normal(rng), 3 * normal(rng), angle(rng), pitch(rng),
                   angle(rng));
  }
  // A full-rank covariance with standard deviations of about 1e-2 (1 cm, 0.6 deg).
  Covariance6 Sigma() {
    Matrix6 L;
    for (int i = 0; i < 36; ++i) L.data()[i] = 1e-2 * normal(rng);
    return L * L.transpose() + 1e-6 * Matrix6::Identity();
  }
};

double RelativeError(const Covariance6& got, const Covariance6& want) {
  return (got - want).cwiseAbs().maxCoeff() / want.cwiseAbs().maxCoeff();
}

using Vector6 = Eigen::Matrix<double, 6, 1>;
Vector6 ParametersOf(const CPose3D& X) {
  Vector6 v;
  v << X.x(), X.y(), X.z(), X.yaw(), X.pitch(), X.roll();
  return v;
}
CPose3D FromParameters(const Vector6& v) { return CPose3D(v[0], v[1], v[2], v[3], v[4], v[5]); }

// d f(x) / d x in MRPT's parameters, central differences (angles' differences wrapped).
template <class F>
Matrix6 ParameterJacobian(const CPose3D& x, F&& f) {
  const double h = 1e-6;
  Matrix6 J;
  for (int k = 0; k < 6; ++k) {
    Vector6 e = Vector6::Zero();
    e[k] = h;
    Vector6 d = ParametersOf(f(FromParameters(ParametersOf(x) + e))) -
                ParametersOf(f(FromParameters(ParametersOf(x) - e)));
    for (int a = 3; a < 6; ++a) d[a] = std::remainder(d[a], 2 * M_PI);
    J.col(k) = d / (2 * h);
  }
  return J;
}

TEST(JacobiansMrpt, MrptRotationIsYawPitchRoll) {
  Random r;
  for (int i = 0; i < 100; ++i) {
    const CPose3D X = r.Pose();
    const Matrix3d R = X.getRotationMatrix().asEigen();
    EXPECT_LT((R - YawPitchRoll(X.yaw(), X.pitch(), X.roll())).cwiseAbs().maxCoeff(), 1e-14);
  }
}

TEST(JacobiansMrpt, EulerToRotationVectorMatchesFiniteDifferences) {
  // dtheta = Log(R(angles + h e_k) R^T) / h, central differences, on MRPT's own matrices.
  Random r;
  const double h = 1e-6;
  for (int i = 0; i < 100; ++i) {
    const CPose3D X = r.Pose();
    const Matrix3d R = X.getRotationMatrix().asEigen();
    const double a[3] = {X.yaw(), X.pitch(), X.roll()};
    const Matrix6 J = MrptToCoordinates(X);
    for (int k = 0; k < 3; ++k) {
      double plus[3] = {a[0], a[1], a[2]}, minus[3] = {a[0], a[1], a[2]};
      plus[k] += h;
      minus[k] -= h;
      const auto log = [&](const double* b) {
        const CPose3D Y(0, 0, 0, b[0], b[1], b[2]);
        const Eigen::AngleAxisd aa(Matrix3d(Y.getRotationMatrix().asEigen() * R.transpose()));
        return Vector3d(aa.angle() * aa.axis());
      };
      const Vector3d column = (log(plus) - log(minus)) / (2 * h);
      EXPECT_LT((column - J.block<3, 1>(3, 3 + k)).norm(), 1e-8) << "angle " << k;
    }
  }
}

// Which of the two forms MRPT's analytic answer has (see the top of the file).
enum class Agreement { kSame, kAngularRowsNegated, kNeither };
Agreement Compare(const Covariance6& mrpt_converted, const Covariance6& ours, double& error) {
  Matrix6 D = Matrix6::Identity();
  D.bottomRightCorner<3, 3>() *= -1.0;
  const double same = RelativeError(mrpt_converted, ours);
  const double flipped = RelativeError(mrpt_converted, D * ours * D);
  error = std::min(same, flipped);
  if (same < 1e-9) return Agreement::kSame;
  return flipped < 1e-9 ? Agreement::kAngularRowsNegated : Agreement::kNeither;
}

TEST(JacobiansMrpt, CompositionAndInversionAgreeOnAThousandPairs) {
  Random r;
  int compared = 0, near_gimbal_lock = 0;
  int same[2] = {0, 0}, negated[2] = {0, 0};  // [composition, inversion]
  double worst_numeric = 0, worst_analytic = 0;
  for (int i = 0; i < 1000; ++i) {
    const CPose3D X_AB = r.Pose(), X_BC = r.Pose();
    const Covariance6 S_AB = r.Sigma(), S_BC = r.Sigma();  // semgraph's convention
    // Into MRPT's parameters: Sigma_MRPT = J^-1 Sigma J^-T.
    const Matrix6 Ji_AB = MrptToCoordinates(X_AB).inverse();
    const Matrix6 Ji_BC = MrptToCoordinates(X_BC).inverse();
    const Covariance6 M_AB = Ji_AB * S_AB * Ji_AB.transpose();
    const Covariance6 M_BC = Ji_BC * S_BC * Ji_BC.transpose();
    const CPose3DPDFGaussian pdf_AB(X_AB, ToMrpt(M_AB)), pdf_BC(X_BC, ToMrpt(M_BC));
    const CPose3DPDFGaussian pdf_AC = pdf_AB + pdf_BC;
    const CPose3DPDFGaussian pdf_BA = -pdf_AB;
    // The means agree with plain composition and inversion (same poses on both sides).
    const Eigen::Isometry3d X_AC = IsometryOf(X_AB) * IsometryOf(X_BC);
    ASSERT_LT((IsometryOf(pdf_AC.mean).matrix() - X_AC.matrix()).cwiseAbs().maxCoeff(), 1e-12);
    ASSERT_LT((IsometryOf(pdf_BA.mean).matrix() - IsometryOf(X_AB).inverse().matrix())
                  .cwiseAbs()
                  .maxCoeff(),
              1e-12);
    // The answers' pitch: MRPT's Euler Jacobians divide by cos(pitch).
    if (std::abs(std::cos(pdf_AC.mean.pitch())) < 0.05 ||
        std::abs(std::cos(pdf_BA.mean.pitch())) < 0.05) {
      ++near_gimbal_lock;
      continue;
    }
    const Covariance6 ours_AC =
        jacobians::ComposeCovariance(IsometryOf(X_AB), S_AB, IsometryOf(X_BC), S_BC);
    const Covariance6 ours_BA = jacobians::InverseCovariance(IsometryOf(X_AB), S_AB);
    const Matrix6 J_AC = MrptToCoordinates(pdf_AC.mean);
    const Matrix6 J_BA = MrptToCoordinates(pdf_BA.mean);

    // 1. Through MRPT's pose composition and inversion, by finite differences.
    const Matrix6 F_AB = ParameterJacobian(X_AB, [&](const CPose3D& x) { return x + X_BC; });
    const Matrix6 F_BC = ParameterJacobian(X_BC, [&](const CPose3D& u) { return X_AB + u; });
    const Matrix6 F_inv = ParameterJacobian(X_AB, [](const CPose3D& x) {
      CPose3D inverse = x;
      inverse.inverse();
      return inverse;
    });
    const Covariance6 numeric_AC =
        J_AC * (F_AB * M_AB * F_AB.transpose() + F_BC * M_BC * F_BC.transpose()) * J_AC.transpose();
    const Covariance6 numeric_BA = J_BA * F_inv * M_AB * F_inv.transpose() * J_BA.transpose();
    const double e_numeric =
        std::max(RelativeError(ours_AC, numeric_AC), RelativeError(ours_BA, numeric_BA));
    EXPECT_LT(e_numeric, 1e-6) << "pair " << i;
    worst_numeric = std::max(worst_numeric, e_numeric);

    // 2. CPose3DPDFGaussian's analytic answers.
    double e_compose = 0, e_inverse = 0;
    const Agreement compose =
        Compare(J_AC * ToEigen(pdf_AC.cov) * J_AC.transpose(), ours_AC, e_compose);
    const Agreement inverse =
        Compare(J_BA * ToEigen(pdf_BA.cov) * J_BA.transpose(), ours_BA, e_inverse);
    EXPECT_NE(compose, Agreement::kNeither) << "pair " << i << ": " << e_compose;
    EXPECT_NE(inverse, Agreement::kNeither) << "pair " << i << ": " << e_inverse;
    same[0] += compose == Agreement::kSame;
    same[1] += inverse == Agreement::kSame;
    negated[0] += compose == Agreement::kAngularRowsNegated;
    negated[1] += inverse == Agreement::kAngularRowsNegated;
    worst_analytic = std::max({worst_analytic, e_compose, e_inverse});
    ++compared;
  }
  EXPECT_EQ(compared + near_gimbal_lock, 1000);
  EXPECT_GE(compared, 950);
  // Most pairs agree outright: the flip is MRPT's exception, not a convention mismatch.
  EXPECT_GT(same[0], compared / 2);
  EXPECT_GT(same[1], compared / 2);
  std::printf(
      "compared %d pairs (%d near gimbal lock skipped). Against finite differences of "
      "MRPT's composition and inversion: worst relative difference %.3g. Against "
      "CPose3DPDFGaussian: composition %d same, %d with MRPT's angular rows negated; "
      "inversion %d same, %d negated; worst relative difference %.3g\n",
      compared, near_gimbal_lock, worst_numeric, same[0], negated[0], same[1], negated[1],
      worst_analytic);
}

TEST(JacobiansMrpt, DifferentConventionsDifferWithoutTheConversion) {
  // The conversion matters: MRPT's matrix read as semgraph's (no J) is wrong for a composed
  // pose whose rotation is not about z only (the test above would fail without it).
  Random r;
  const CPose3D X_AB(1, 2, 3, 0.3, 0.6, -0.9), X_BC(0.5, -1, 2, -1.2, 0.4, 0.7);
  const Covariance6 S = r.Sigma();
  const CPose3DPDFGaussian ab(X_AB, ToMrpt(S)), bc(X_BC, ToMrpt(S));
  const Covariance6 raw = ToEigen((ab + bc).cov);
  const Matrix6 Ji = MrptToCoordinates(X_AB).inverse();
  const Matrix6 Jj = MrptToCoordinates(X_BC).inverse();
  // Ours, from the same physical covariances (MRPT's S carried into semgraph's convention).
  const Matrix6 J_AB = Ji.inverse(), J_BC = Jj.inverse();
  const Covariance6 ours = jacobians::ComposeCovariance(
      IsometryOf(X_AB), J_AB * S * J_AB.transpose(), IsometryOf(X_BC), J_BC * S * J_BC.transpose());
  EXPECT_GT(RelativeError(raw, ours), 1e-2);
  const Matrix6 J_AC = MrptToCoordinates((ab + bc).mean);
  EXPECT_LT(RelativeError(J_AC * raw * J_AC.transpose(), ours), 1e-9);
}

}  // namespace
}  // namespace semgraph::coord
