// Tests for coord/covariance.h: the meaning of a covariance (docs/uncertainty.md) on cases
// worked by hand, the body -> coordinates conversion against a Jacobian measured by finite
// differences of the exact perturbation (X Exp(xi) by the 4x4 matrix exponential, delta by
// AngleAxis: neither is semgraph code), likewise the docs' formula for Barfoot's left
// perturbation, the orders (a GTSAM-order matrix round trip), every check at its boundary
// (1e12, the symmetry and eigenvalue tolerances scaled by max(1, max |S|)), NaN / Inf in every
// entry, the checks' order, the texts, and no allocation.
#include "semgraph/coord/covariance.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>

#include "support/alloc_counter.h"

namespace semgraph::coord {
namespace {

using base::ErrorCode;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix3d Rz(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).matrix(); }

Eigen::Matrix3d Hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d W;
  W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return W;
}

// X Exp(xi) with xi = (rho, phi), by the exponential of the 4x4 matrix [phi^ rho; 0 0].
Eigen::Matrix4d RightPerturbed(const Eigen::Matrix4d& X, const Eigen::Matrix<double, 6, 1>& xi) {
  Eigen::Matrix4d h = Eigen::Matrix4d::Zero();
  h.topLeftCorner<3, 3>() = Hat(xi.tail<3>());
  h.topRightCorner<3, 1>() = xi.head<3>();
  return X * h.exp();
}

// semgraph's coordinates delta of X_true relative to X: (p_true - p, Log(R_true R^T)).
Eigen::Matrix<double, 6, 1> CoordinatesDelta(const Eigen::Matrix4d& X, const Eigen::Matrix4d& Xt) {
  Eigen::Matrix<double, 6, 1> d;
  d.head<3>() = Xt.topRightCorner<3, 1>() - X.topRightCorner<3, 1>();
  const Eigen::AngleAxisd aa(
      Eigen::Matrix3d(Xt.topLeftCorner<3, 3>() * X.topLeftCorner<3, 3>().transpose()));
  d.tail<3>() = aa.angle() * aa.axis();
  return d;
}

Eigen::Matrix4d RandomPose(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix4d X = Eigen::Matrix4d::Identity();
  X.topLeftCorner<3, 3>() =
      Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
  X.topRightCorner<3, 1>() = Eigen::Vector3d(n(rng), n(rng), n(rng)) * 3.0;
  return X;
}

Covariance6 RandomCovariance(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Covariance6 A;
  for (int i = 0; i < 36; ++i) A.data()[i] = n(rng);
  return A * A.transpose() * 1e-3;
}

void ExpectMatrixNear(const Covariance6& a, const Covariance6& b, double tol) {
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) EXPECT_NEAR(a(r, c), b(r, c), tol) << "(" << r << ", " << c << ")";
  }
}

// -------------------------------------------------------------- meaning, by hand

TEST(Covariance, BodyTranslationNoiseTurnsWithTheRotation) {
  // Head turned 90 deg about z: a body x noise (sigma 0.1) is the tail's y noise.
  Covariance6 body = Covariance6::Zero();
  body(0, 0) = 0.01;
  const Covariance6 c = BodyToCoordinates(Rz(kPi / 2), body);
  Covariance6 expected = Covariance6::Zero();
  expected(1, 1) = 0.01;
  ExpectMatrixNear(c, expected, 1e-18);
}

TEST(Covariance, BodyRotationNoiseTurnsWithTheRotationAndMovesNoPoint) {
  // Body roll noise (about the head's x) with the head yawed 90 deg: rotation about the tail's y;
  // dp stays zero (the perturbation is at the head's origin: the pose's own point).
  Covariance6 body = Covariance6::Zero();
  body(3, 3) = 0.04;
  body(0, 3) = body(3, 0) = 0.001;  // x-noise correlated with roll -> y-noise with pitch
  const Covariance6 c = BodyToCoordinates(Rz(kPi / 2), body);
  Covariance6 expected = Covariance6::Zero();
  expected(4, 4) = 0.04;
  expected(1, 4) = expected(4, 1) = 0.001;
  ExpectMatrixNear(c, expected, 1e-17);  // cos(pi/2) is 6e-17, not 0
}

TEST(Covariance, CoordinatesConventionIsTheEdgeFormUnchanged) {
  // ROS's PoseWithCovariance and semgraph's default: no conversion, only symmetrization.
  std::mt19937 rng(1);
  const Covariance6 S = RandomCovariance(rng);
  const auto out = PoseCovarianceToEdgeForm(S, CovarianceOrder::kLinearAngular,
                                            PoseCovarianceConvention::kCoordinates, Rz(1.0));
  ASSERT_TRUE(out.has_value());
  ExpectMatrixNear(*out, S, 1e-18);
}

TEST(Covariance, BodyToCoordinatesIsTheFirstOrderMapOfTheExactPerturbation) {
  // J = d(delta)/d(xi) at xi = 0 by central differences of the exact X Exp(xi); then
  // J S J^T must be BodyToCoordinates(R, S), and J must be diag(R, R).
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Matrix4d X = RandomPose(rng);
    const Eigen::Matrix3d R = X.topLeftCorner<3, 3>();
    Covariance6 J;
    const double h = 1e-6;
    for (int k = 0; k < 6; ++k) {
      Eigen::Matrix<double, 6, 1> e = Eigen::Matrix<double, 6, 1>::Zero();
      e[k] = h;
      J.col(k) =
          (CoordinatesDelta(X, RightPerturbed(X, e)) - CoordinatesDelta(X, RightPerturbed(X, -e))) /
          (2 * h);
    }
    const Covariance6 S = RandomCovariance(rng);
    ExpectMatrixNear(BodyToCoordinates(R, S), J * S * J.transpose(), 1e-8);
    ExpectMatrixNear(CoordinatesToBody(R, BodyToCoordinates(R, S)), S, 1e-14);
  }
}

TEST(Covariance, LeftPerturbationFormulaOfTheDocs) {
  // docs/uncertainty.md: Barfoot's Exp(xi^) X, xi = (rho, phi), is delta = B xi with
  // B = [[I, -[p]x], [0, I]] (the rotation about t's origin moves h's origin by p). Measured by
  // central differences of the exact left perturbation, as above.
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Matrix4d X = RandomPose(rng);
    Covariance6 B = Covariance6::Identity();
    B.topRightCorner<3, 3>() = -Hat(X.topRightCorner<3, 1>());
    Covariance6 J;
    const double h = 1e-6;
    for (int k = 0; k < 6; ++k) {
      Eigen::Matrix<double, 6, 1> e = Eigen::Matrix<double, 6, 1>::Zero();
      e[k] = h;
      const auto left = [&](const Eigen::Matrix<double, 6, 1>& xi) {
        return Eigen::Matrix4d(RightPerturbed(Eigen::Matrix4d::Identity(), xi) * X);
      };
      J.col(k) = (CoordinatesDelta(X, left(e)) - CoordinatesDelta(X, left(-e))) / (2 * h);
    }
    EXPECT_LT((J - B).cwiseAbs().maxCoeff(), 1e-8);
  }
}

// -------------------------------------------------------------- orders

TEST(Covariance, GtsamOrderRoundTrip) {
  // A GTSAM Pose3 covariance: (rotation, translation) order, body convention. Rotation block
  // diag(1, 2, 3)e-4, translation block diag(4, 5, 6)e-2, one rotation-translation term.
  Covariance6 g = Covariance6::Zero();
  g.diagonal() << 1e-4, 2e-4, 3e-4, 4e-2, 5e-2, 6e-2;
  g(0, 5) = g(5, 0) = 1e-3;  // rot x with trans z
  const Covariance6 la = Reorder(g, CovarianceOrder::kAngularLinear);
  Covariance6 expected = Covariance6::Zero();
  expected.diagonal() << 4e-2, 5e-2, 6e-2, 1e-4, 2e-4, 3e-4;
  expected(3, 2) = expected(2, 3) = 1e-3;  // now row dtheta_x, column dp_z
  EXPECT_EQ(la, expected);
  EXPECT_EQ(Reorder(la, CovarianceOrder::kAngularLinear), g);  // and back: the same swap
  EXPECT_EQ(SwapHalves(la), g);
  EXPECT_EQ(Reorder(g, CovarianceOrder::kLinearAngular), g);

  // Through the whole input and output path, with a rotation.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  const auto edge = PoseCovarianceToEdgeForm(g, CovarianceOrder::kAngularLinear,
                                             PoseCovarianceConvention::kBody, R);
  ASSERT_TRUE(edge.has_value());
  // Translation variance of the edge form: R diag(4, 5, 6)e-2 R^T.
  const Eigen::Matrix3d trans = R * Eigen::Vector3d(4e-2, 5e-2, 6e-2).asDiagonal() * R.transpose();
  EXPECT_LT((edge->topLeftCorner<3, 3>() - trans).cwiseAbs().maxCoeff(), 1e-17);
  const Covariance6 back = PoseCovarianceFromEdgeForm(*edge, CovarianceOrder::kAngularLinear,
                                                      PoseCovarianceConvention::kBody, R);
  ExpectMatrixNear(back, g, 1e-16);
  EXPECT_EQ(back, back.transpose());
}

TEST(Covariance, TwistOrderOnly) {
  Covariance6 s = Covariance6::Zero();
  s.diagonal() << 1, 2, 3, 4, 5, 6;  // (dw, dv) as given
  const auto out = TwistCovarianceToEdgeForm(s, CovarianceOrder::kAngularLinear);
  ASSERT_TRUE(out.has_value());
  const Eigen::Matrix<double, 6, 1> expected{4, 5, 6, 1, 2, 3};
  EXPECT_EQ((Eigen::Matrix<double, 6, 1>(out->diagonal())), expected);
}

// -------------------------------------------------------------- checks

TEST(CovarianceCheck, AcceptsZeroAndPositiveSemiDefinite) {
  EXPECT_TRUE(CheckCovariance(Covariance6::Zero()).ok());
  std::mt19937 rng(3);
  for (int i = 0; i < 100; ++i) EXPECT_TRUE(CheckCovariance(RandomCovariance(rng)).ok());
  // Rank one (a line of noise): eigenvalues 0 (five) and 6.
  EXPECT_TRUE(CheckCovariance(Covariance6::Ones()).ok());
}

TEST(CovarianceCheck, NotFiniteInEveryEntry) {
  for (double bad : {kNaN, kInf, -kInf}) {
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 6; ++c) {
        Covariance6 s = Covariance6::Identity();
        s(r, c) = bad;
        const CovarianceCheck k = CheckCovariance(s);
        EXPECT_EQ(k.code(), ErrorCode::kInvalidNumber);
        EXPECT_EQ(k.problem, CovarianceProblem::kNotFinite);
        EXPECT_EQ(k.row, r);
        EXPECT_EQ(k.col, c);
        EXPECT_EQ(std::isnan(k.value), std::isnan(bad));
      }
    }
  }
}

TEST(CovarianceCheck, MagnitudeBoundIs1e12Inclusive) {
  Covariance6 s = Covariance6::Identity();
  s(3, 3) = 1e12;
  EXPECT_TRUE(CheckCovariance(s).ok());
  s(3, 3) = std::nextafter(1e12, 2e12);
  CovarianceCheck k = CheckCovariance(s);
  EXPECT_EQ(k.code(), ErrorCode::kInvalidNumber);
  EXPECT_EQ(k.problem, CovarianceProblem::kTooLarge);
  EXPECT_EQ(k.row, 3);
  EXPECT_EQ(k.col, 3);
  EXPECT_EQ(k.value, s(3, 3));
  EXPECT_EQ(k.limit, kMaxMagnitude);
  // Negative entries count by magnitude; the first offending entry in row-major order.
  s(3, 3) = 1.0;
  s(1, 4) = -2e12;
  s(4, 1) = -2e12;
  k = CheckCovariance(s);
  EXPECT_EQ(k.problem, CovarianceProblem::kTooLarge);
  EXPECT_EQ(k.row, 1);
  EXPECT_EQ(k.col, 4);
}

TEST(CovarianceCheck, SymmetryToleranceAtItsBoundary) {
  // max |S| = 1: tol = 1e-9 (max(1, .) keeps it there for a smaller matrix too).
  for (double scale : {1.0, 1e-6}) {
    Covariance6 s = Covariance6::Identity() * scale;
    s(0, 1) = 1e-9;  // s(1, 0) = 0: asymmetry exactly 1e-9
    EXPECT_TRUE(CheckCovariance(s).ok()) << scale;
    s(0, 1) = std::nextafter(1e-9, 1.0);
    const CovarianceCheck k = CheckCovariance(s);
    EXPECT_EQ(k.code(), ErrorCode::kInvalidCovariance) << scale;
    EXPECT_EQ(k.problem, CovarianceProblem::kNotSymmetric);
    EXPECT_EQ(k.row, 0);
    EXPECT_EQ(k.col, 1);
    EXPECT_EQ(k.value, s(0, 1));
    EXPECT_EQ(k.other, 0.0);
    EXPECT_EQ(k.limit, 1e-9);
  }
  // max |S| = 1e4: tol = 1e-5.
  Covariance6 s = Covariance6::Identity() * 1e4;
  const double tol = kCovarianceTolerance * 1e4;
  s(5, 2) = tol;
  EXPECT_TRUE(CheckCovariance(s).ok());
  s(5, 2) = std::nextafter(tol, 1.0);
  const CovarianceCheck k = CheckCovariance(s);
  EXPECT_EQ(k.problem, CovarianceProblem::kNotSymmetric);
  EXPECT_EQ(k.row, 2);  // reported as the upper entry (2, 5)
  EXPECT_EQ(k.col, 5);
  EXPECT_EQ(k.value, 0.0);
  EXPECT_EQ(k.other, s(5, 2));
  EXPECT_EQ(k.limit, tol);
}

TEST(CovarianceCheck, EigenvalueToleranceAtItsBoundary) {
  Covariance6 s = Covariance6::Identity();
  s(2, 2) = -1e-9;
  EXPECT_TRUE(CheckCovariance(s).ok());
  s(2, 2) = -2e-9;
  CovarianceCheck k = CheckCovariance(s);
  EXPECT_EQ(k.code(), ErrorCode::kInvalidCovariance);
  EXPECT_EQ(k.problem, CovarianceProblem::kNotPositive);
  EXPECT_EQ(k.value, -2e-9);
  EXPECT_EQ(k.limit, -1e-9);
  // Scaled: max |S| = 1e6 allows -1e-3.
  s = Covariance6::Identity() * 1e6;
  s(4, 4) = -1e-3;
  EXPECT_TRUE(CheckCovariance(s).ok());
  s(4, 4) = -1.1e-3;
  EXPECT_EQ(CheckCovariance(s).problem, CovarianceProblem::kNotPositive);
  // Not diagonal: [[1, 2], [2, 1]] has eigenvalues 3 and -1, though every entry is positive.
  s = Covariance6::Identity();
  s(0, 3) = s(3, 0) = 2.0;
  k = CheckCovariance(s);
  EXPECT_EQ(k.problem, CovarianceProblem::kNotPositive);
  EXPECT_NEAR(k.value, -1.0, 1e-14);
  EXPECT_EQ(k.limit, -2e-9);  // max |S| = 2
}

TEST(CovarianceCheck, OrderOfTheChecksAndMatrixAsGiven) {
  // Asymmetric, indefinite and with a NaN: invalid_number first.
  Covariance6 s = Covariance6::Identity();
  s(0, 1) = 5.0;
  s(2, 2) = -1.0;
  s(5, 4) = kNaN;
  EXPECT_EQ(CheckCovariance(s).code(), ErrorCode::kInvalidNumber);
  // Asymmetric and indefinite: the symmetry is named.
  s(5, 4) = 0.0;
  EXPECT_EQ(CheckCovariance(s).problem, CovarianceProblem::kNotSymmetric);
  // The entry is named as given, before reordering: (4, 0) of a GTSAM-order matrix.
  s = Covariance6::Identity();
  s(4, 0) = kInf;
  const auto out = PoseCovarianceToEdgeForm(s, CovarianceOrder::kAngularLinear,
                                            PoseCovarianceConvention::kBody, Rz(0.3));
  ASSERT_FALSE(out.has_value());
  EXPECT_EQ(out.error().row, 4);
  EXPECT_EQ(out.error().col, 0);
  EXPECT_FALSE(TwistCovarianceToEdgeForm(s, CovarianceOrder::kLinearAngular).has_value());
}

TEST(CovarianceCheck, AcceptedIsStoredSymmetrized) {
  Covariance6 s = Covariance6::Identity();
  s(1, 2) = 0.25 + 1e-10;
  s(2, 1) = 0.25;
  const auto out = PoseCovarianceToEdgeForm(s, CovarianceOrder::kLinearAngular,
                                            PoseCovarianceConvention::kCoordinates, Rz(0));
  ASSERT_TRUE(out.has_value());
  EXPECT_EQ((*out)(1, 2), (*out)(2, 1));
  EXPECT_EQ((*out)(1, 2), 0.5 * (s(1, 2) + s(2, 1)));
}

TEST(CovarianceCheck, Texts) {
  Covariance6 s = Covariance6::Identity();
  s(2, 3) = kNaN;
  EXPECT_EQ(Describe(CheckCovariance(s)), "covariance entry (2, 3) is nan (must be finite)");
  EXPECT_EQ(Describe(CheckCovariance(s).error(), semantics::NameTable{}),
            "covariance entry (2, 3) is nan (must be finite)");
  s(2, 3) = 2e12;
  EXPECT_EQ(Describe(CheckCovariance(s)),
            "covariance entry (2, 3) is 2e+12 (magnitude above 1e+12)");
  s = Covariance6::Identity();
  s(0, 1) = 0.5;
  s(1, 0) = 0.25;
  EXPECT_EQ(Describe(CheckCovariance(s)),
            "covariance entry (0, 1) = 0.5 differs from entry (1, 0) = 0.25 by 0.25 (more than "
            "1e-09: not symmetric)");
  EXPECT_EQ(Describe(CheckCovariance(s).error(), semantics::NameTable{}),
            "covariance entry (0, 1) differs from its transpose by 0.25 (more than 1e-09 * "
            "max(1, max |entry|): not symmetric)");
  s = Covariance6::Identity();
  s(5, 5) = -0.5;
  EXPECT_EQ(Describe(CheckCovariance(s)),
            "covariance has eigenvalue -0.5 (below -1e-09: not positive semi-definite)");
  EXPECT_EQ(ToString(CheckCovariance(s).code()), "invalid_covariance");
  EXPECT_EQ(Describe(CovarianceCheck{}), "ok");
}

TEST(CovarianceCheck, NoAllocation) {
  std::mt19937 rng(5);
  Covariance6 good = RandomCovariance(rng), bad = good;
  bad(0, 0) = -1.0;
  const Eigen::Matrix3d R = Rz(0.4);
  int accepted = 0;
  std::size_t count = 0;
  {
    semgraph::testing::CountAllocations counting;
    for (int i = 0; i < 1000; ++i) {
      accepted += CheckCovariance(good).ok() + CheckCovariance(bad).ok();
      const auto e = PoseCovarianceToEdgeForm(good, CovarianceOrder::kAngularLinear,
                                              PoseCovarianceConvention::kBody, R);
      accepted += e.has_value();
      accepted += TwistCovarianceToEdgeForm(bad, CovarianceOrder::kLinearAngular).has_value();
      const Covariance6 out = PoseCovarianceFromEdgeForm(*e, CovarianceOrder::kAngularLinear,
                                                         PoseCovarianceConvention::kBody, R);
      accepted += out(0, 0) > 0.0;
    }
    count = counting.count();
  }
  EXPECT_EQ(count, 0u);
  EXPECT_EQ(accepted, 3000);
}

}  // namespace
}  // namespace semgraph::coord
