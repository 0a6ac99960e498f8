// Input validation of coord/validate.h (docs/rules.md §5): non-finite numbers anywhere,
// rotation tolerances and normalization, reflections, 4x4 shape, the order of the checks
// (invalid_number -> invalid_rotation -> representation_constraint) and the error texts.
//
// Component indices (error.value.component): vectors 0..2 (x y z); quaternions 0..3 in the
// order w x y z; 3x3 and 4x4 matrices row-major (3*row + col, 4*row + col).
#include "semgraph/coord/validate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <ostream>
#include <random>
#include <string>

#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/quaternion_backend.h"
#include "support/rotation_matrix_backend.h"
#include "support/tolerance.h"
#include "support/world_scene.h"

namespace semgraph::semantics {
void PrintTo(ErrorCode code, std::ostream* os) { *os << ToString(code); }
}  // namespace semgraph::semantics

namespace semgraph::coord {
namespace {

using base::ErrorCode;
using semantics::Body;
using semantics::Frame;
using semantics::NameTable;
using semgraph::testing::ExpectNear;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kBadNumbers[] = {kNaN, kInf, -kInf};

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// Names for the semantics of the values under test: frames {a}, {b} on bodies A, B.
struct Names {
  NameTable table;
  Frame a{*table.Intern("a")}, b{*table.Intern("b")}, c{*table.Intern("c")};
  Body A{*table.Intern("A")}, B{*table.Intern("B")};

  /// Frame-form edge pose {a}|A wrt {b}|B in [b]: every backend holds it.
  PoseSemantics Edge() const { return PoseSemantics::OfFrame(a, A, b, B, b.axes()); }
  OrientationSemantics EdgeOrientation() const { return {a.axes(), A, b.axes(), B, b.axes()}; }
  PositionSemantics Pos() const { return {a.origin(), A, b.origin(), B, b.axes()}; }
  LinearVelocitySemantics Lin() const { return {a.origin(), A, B, a.axes()}; }
  AngularVelocitySemantics Ang() const { return {A, B, a.axes()}; }
  TwistSemantics Tw() const { return {a.origin(), A, B, a.axes()}; }
  AccelerationSemantics Acc() const { return {a.origin(), A, B, a.axes()}; }
  WrenchSemantics Wr() const { return {a.origin(), A, B, a.axes()}; }
};

Eigen::Matrix3d SomeRotation(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  return semgraph::testing::RandomUnitQuaternion(rng).toRotationMatrix();
}

Eigen::Quaterniond SomeQuaternion(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  return semgraph::testing::RandomUnitQuaternion(rng);
}

/// The error is kInvalidNumber about `role`, component `component`, holding `bad`.
template <class T>
void ExpectInvalidNumber(const Expected<T, Error>& r, ValueRole role, int component, double bad,
                         const NameTable& names) {
  ASSERT_FALSE(r.has_value()) << "a non-finite number was accepted";
  const Error& e = r.error();
  const std::string text = Describe(e, names);
  EXPECT_EQ(e.code, ErrorCode::kInvalidNumber) << text;
  EXPECT_EQ(e.value.problem, ValueProblem::kNotFinite) << text;
  EXPECT_EQ(e.value.role, role) << text;
  EXPECT_EQ(int(e.value.component), component) << text;
  if (std::isnan(bad)) {
    EXPECT_TRUE(std::isnan(e.value.magnitude)) << text;
  } else {
    EXPECT_EQ(e.value.magnitude, bad) << text;
  }
  EXPECT_TRUE(Contains(text, "component " + std::to_string(component))) << text;
  EXPECT_TRUE(Contains(text, "must be finite")) << text;
  EXPECT_TRUE(Contains(text, std::isnan(bad) ? "nan" : (bad > 0 ? "inf" : "-inf"))) << text;
}

template <class T>
void ExpectInvalidRotation(const Expected<T, Error>& r, ValueProblem problem) {
  ASSERT_FALSE(r.has_value()) << "an invalid rotation was accepted";
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidRotation);
  EXPECT_EQ(r.error().value.problem, problem);
}

// ================================================================== vectors

TEST(Validate, NonFinitePositionComponentIsInvalidNumber) {
  Names n;
  for (double bad : kBadNumbers) {
    for (int i = 0; i < 3; ++i) {
      Eigen::Vector3d p(0.5, -1.0, 2.0);
      p[i] = bad;
      ExpectInvalidNumber(MakePosition(n.Pos(), p), ValueRole::kPosition, i, bad, n.table);
      ExpectInvalidNumber(ValidateVector(p, ValueRole::kPosition), ValueRole::kPosition, i, bad,
                          n.table);
      EXPECT_TRUE(Contains(Describe(MakePosition(n.Pos(), p).error(), n.table), "position"));
    }
  }
}

TEST(Validate, NonFiniteVelocityComponentIsInvalidNumber) {
  Names n;
  for (double bad : kBadNumbers) {
    for (int i = 0; i < 3; ++i) {
      Eigen::Vector3d v(0.1, 0.2, 0.3), w(-0.3, 0.2, -0.1);
      Eigen::Vector3d v_bad = v, w_bad = w;
      v_bad[i] = bad;
      w_bad[i] = bad;
      ExpectInvalidNumber(MakeTwist(n.Tw(), v_bad, w), ValueRole::kLinearVelocity, i, bad, n.table);
      ExpectInvalidNumber(MakeTwist(n.Tw(), v, w_bad), ValueRole::kAngularVelocity, i, bad,
                          n.table);
      ExpectInvalidNumber(MakeLinearVelocity(n.Lin(), v_bad), ValueRole::kLinearVelocity, i, bad,
                          n.table);
      ExpectInvalidNumber(MakeAngularVelocity(n.Ang(), w_bad), ValueRole::kAngularVelocity, i, bad,
                          n.table);
      EXPECT_TRUE(Contains(Describe(MakeTwist(n.Tw(), v_bad, w).error(), n.table),
                           "linear velocity component"));
      EXPECT_TRUE(Contains(Describe(MakeTwist(n.Tw(), v, w_bad).error(), n.table),
                           "angular velocity component"));
    }
  }
  // Both bad: the linear part is reported first.
  ExpectInvalidNumber(MakeTwist(n.Tw(), Eigen::Vector3d(0, kNaN, 0), Eigen::Vector3d(kInf, 0, 0)),
                      ValueRole::kLinearVelocity, 1, kNaN, n.table);
}

TEST(Validate, NonFiniteAccelerationOrWrenchComponentIsInvalidNumber) {
  Names n;
  for (double bad : kBadNumbers) {
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d u(0.1, 0.2, 0.3), w(-0.3, 0.2, -0.1);
      Eigen::Vector3d u_bad = u, w_bad = w;
      u_bad[i] = bad;
      w_bad[i] = bad;
      ExpectInvalidNumber(MakeAcceleration(n.Acc(), u_bad, w), ValueRole::kLinearAcceleration, i,
                          bad, n.table);
      ExpectInvalidNumber(MakeAcceleration(n.Acc(), u, w_bad), ValueRole::kAngularAcceleration, i,
                          bad, n.table);
      ExpectInvalidNumber(MakeWrench(n.Wr(), u_bad, w), ValueRole::kForce, i, bad, n.table);
      ExpectInvalidNumber(MakeWrench(n.Wr(), u, w_bad), ValueRole::kMoment, i, bad, n.table);
      EXPECT_TRUE(Contains(Describe(MakeAcceleration(n.Acc(), u_bad, w).error(), n.table),
                           "linear acceleration component"));
      EXPECT_TRUE(Contains(Describe(MakeAcceleration(n.Acc(), u, w_bad).error(), n.table),
                           "angular acceleration component"));
      EXPECT_TRUE(
          Contains(Describe(MakeWrench(n.Wr(), u_bad, w).error(), n.table), "force component"));
      EXPECT_TRUE(
          Contains(Describe(MakeWrench(n.Wr(), u, w_bad).error(), n.table), "moment component"));
    }
  }
  // Both bad: the linear part (the force) is reported first.
  const Eigen::Vector3d nan_y(0, kNaN, 0), inf_x(kInf, 0, 0);
  ExpectInvalidNumber(MakeAcceleration(n.Acc(), nan_y, inf_x), ValueRole::kLinearAcceleration, 1,
                      kNaN, n.table);
  ExpectInvalidNumber(MakeWrench(n.Wr(), nan_y, inf_x), ValueRole::kForce, 1, kNaN, n.table);
}

TEST(Validate, AccelerationsAndWrenchesAreBoundedLikeTwistsAndFlushSubnormals) {
  Names n;
  const Eigen::Vector3d ok(1e12, -1e12, 0.5), big(0, 0, -1.5e12), sub(1e-310, 2.0, 0);
  auto acc = MakeAcceleration(n.Acc(), ok, sub);
  ASSERT_TRUE(acc);
  EXPECT_EQ(acc->semantics, n.Acc());
  EXPECT_EQ(acc->linear, ok);
  EXPECT_EQ(acc->angular, Eigen::Vector3d(0, 2.0, 0));
  auto wr = MakeWrench(n.Wr(), sub, ok);
  ASSERT_TRUE(wr);
  EXPECT_EQ(wr->semantics, n.Wr());
  EXPECT_EQ(wr->force, Eigen::Vector3d(0, 2.0, 0));
  EXPECT_EQ(wr->moment, ok);
  const std::pair<Expected<Acceleration, Error>, ValueRole> accs[] = {
      {MakeAcceleration(n.Acc(), big, ok), ValueRole::kLinearAcceleration},
      {MakeAcceleration(n.Acc(), ok, big), ValueRole::kAngularAcceleration}};
  for (const auto& [r, role] : accs) {
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, ErrorCode::kInvalidNumber);
    EXPECT_EQ(r.error().value.problem, ValueProblem::kTooLarge);
    EXPECT_EQ(r.error().value.role, role);
    EXPECT_EQ(int(r.error().value.component), 2);
    EXPECT_EQ(r.error().value.magnitude, -1.5e12);
  }
  const std::pair<Expected<Wrench, Error>, ValueRole> wrs[] = {
      {MakeWrench(n.Wr(), big, ok), ValueRole::kForce},
      {MakeWrench(n.Wr(), ok, big), ValueRole::kMoment}};
  for (const auto& [r, role] : wrs) {
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().value.problem, ValueProblem::kTooLarge);
    EXPECT_EQ(r.error().value.role, role);
    EXPECT_EQ(Describe(r.error(), n.table),
              std::string(role == ValueRole::kForce ? "force" : "moment") +
                  " component 2 is -1.5e+12 (magnitude above 1e+12)");
  }
}

TEST(Validate, FiniteVectorsWithinRangeAreKeptExactly) {
  Names n;
  const Eigen::Vector3d p(1e12, -1e-300, 0.0), v(1, 2, 3), w(-4, 5, -6);
  auto pos = MakePosition(n.Pos(), p);
  ASSERT_TRUE(pos);
  EXPECT_EQ(pos->value, p);
  EXPECT_TRUE(pos->semantics == n.Pos());
  auto tw = MakeTwist(n.Tw(), v, w);
  ASSERT_TRUE(tw);
  EXPECT_EQ(tw->linear, v);
  EXPECT_EQ(tw->angular, w);
}

TEST(Validate, HugeComponentsAreInvalidNumbers) {
  Names n;
  auto pos = MakePosition(n.Pos(), Eigen::Vector3d(0, -1e13, 0));
  ASSERT_FALSE(pos);
  EXPECT_EQ(pos.error().code, ErrorCode::kInvalidNumber);
  EXPECT_EQ(pos.error().value.problem, ValueProblem::kTooLarge);
  EXPECT_EQ(pos.error().value.component, 1);
  EXPECT_NE(Describe(pos.error(), n.table).find("magnitude above"), std::string::npos);
  auto tw = MakeTwist(n.Tw(), Eigen::Vector3d::Zero(), Eigen::Vector3d(1e300, 0, 0));
  ASSERT_FALSE(tw);
  EXPECT_EQ(tw.error().value.role, ValueRole::kAngularVelocity);
}

TEST(Validate, MessagesShowTheOffendingNumberWithRoundTripDigits) {
  // Before: 6 significant digits, so 1000000000000.5 read "1e+12 (magnitude above 1e+12)".
  Names n;
  auto pos = MakePosition(n.Pos(), Eigen::Vector3d(0, 0, 1000000000000.5));
  ASSERT_FALSE(pos);
  EXPECT_EQ(Describe(pos.error(), n.table),
            "position component 2 is 1000000000000.5 (magnitude above 1e+12)");
  auto tw = MakeTwist(n.Tw(), Eigen::Vector3d(-1.0000000000001e12, 0, 0), Eigen::Vector3d::Zero());
  ASSERT_FALSE(tw);
  EXPECT_EQ(Describe(tw.error(), n.table),
            "linear velocity component 0 is -1000000000000.1 (magnitude above 1e+12)");
  // A quaternion 2e-6 off unit: the norm error printed is the computed one, exactly.
  auto q = ValidateQuaternion(Eigen::Quaterniond(1.000002, 0, 0, 0));
  ASSERT_FALSE(q);
  const std::string text = Describe(q.error(), n.table);
  const std::string prefix = "quaternion norm differs from 1 by ";
  ASSERT_EQ(text.rfind(prefix, 0), 0u) << text;
  EXPECT_EQ(std::strtod(text.c_str() + prefix.size(), nullptr), q.error().value.magnitude) << text;
  EXPECT_TRUE(Contains(text, "(more than 1e-06)")) << text;
}

TEST(Validate, FormatNumberIsTheShortestExactForm) {
  EXPECT_EQ(FormatNumber(0.1), "0.1");
  EXPECT_EQ(FormatNumber(1e12), "1e+12");
  EXPECT_EQ(FormatNumber(1000000000000.5), "1000000000000.5");
  EXPECT_EQ(FormatNumber(-0.0), "-0");
  EXPECT_EQ(FormatNumber(kNaN), "nan");
  EXPECT_EQ(FormatNumber(-kInf), "-inf");
  EXPECT_EQ(FormatNumber(0.1 + 0.2), "0.30000000000000004");
  std::mt19937_64 rng(13);
  for (int i = 0; i < 10000; ++i) {
    const std::uint64_t bits = rng();
    double x;
    std::memcpy(&x, &bits, sizeof(x));
    if (!std::isfinite(x)) continue;
    const std::string text = FormatNumber(x);
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), x) << text;
    EXPECT_LE(text.size(), 24u) << text;
  }
}

TEST(Validate, SubnormalComponentsAreFlushedToZero) {
  Names n;
  const double subnormal = 1e-310;
  ASSERT_EQ(std::fpclassify(subnormal), FP_SUBNORMAL);
  auto pos = MakePosition(n.Pos(), Eigen::Vector3d(subnormal, 1.0, -subnormal));
  ASSERT_TRUE(pos);
  EXPECT_EQ(pos->value, Eigen::Vector3d(0.0, 1.0, 0.0));
  auto q = ValidateQuaternion(Eigen::Quaterniond(1.0, subnormal, 0.0, 0.0));
  ASSERT_TRUE(q);
  EXPECT_EQ(q->x(), 0.0);
}

// ================================================================== quaternions

TEST(Validate, NonFiniteQuaternionComponentIsInvalidNumberInWxyzOrder) {
  Names n;
  for (double bad : kBadNumbers) {
    for (int i = 0; i < 4; ++i) {
      double wxyz[4] = {0.5, 0.5, 0.5, 0.5};
      wxyz[i] = bad;
      const Eigen::Quaterniond q(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
      ExpectInvalidNumber(ValidateQuaternion(q), ValueRole::kQuaternion, i, bad, n.table);
      ExpectInvalidNumber(MakeOrientation<QuaternionBackend>(n.EdgeOrientation(), q),
                          ValueRole::kQuaternion, i, bad, n.table);
      ExpectInvalidNumber(MakePose<HomogeneousBackend>(n.Edge(), q, Eigen::Vector3d(1, 2, 3)),
                          ValueRole::kQuaternion, i, bad, n.table);
      EXPECT_TRUE(Contains(Describe(ValidateQuaternion(q).error(), n.table), "quaternion"));
    }
  }
}

TEST(Validate, QuaternionNormOffByMoreThanToleranceIsInvalidRotation) {
  Names n;
  for (double scale : {1.0 + 2e-6, 1.0 - 2e-6, 2.0, 0.5}) {
    SCOPED_TRACE(scale);
    const Eigen::Quaterniond q(SomeQuaternion(7).coeffs() * scale);
    const auto r = ValidateQuaternion(q);
    ExpectInvalidRotation(r, ValueProblem::kQuaternionNorm);
    EXPECT_EQ(r.error().value.role, ValueRole::kQuaternion);
    EXPECT_NEAR(r.error().value.magnitude, std::abs(scale - 1.0), 1e-12);
    const std::string text = Describe(r.error(), n.table);
    EXPECT_TRUE(Contains(text, "quaternion norm differs from 1 by")) << text;
    EXPECT_TRUE(Contains(text, "1e-06")) << text;  // states the tolerance
    ExpectInvalidRotation(MakeOrientation<QuaternionBackend>(n.EdgeOrientation(), q),
                          ValueProblem::kQuaternionNorm);
    ExpectInvalidRotation(
        MakePose<testing::RotationMatrixBackend>(n.Edge(), q, Eigen::Vector3d::Zero()),
        ValueProblem::kQuaternionNorm);
  }
  ExpectInvalidRotation(ValidateQuaternion(Eigen::Quaterniond(0, 0, 0, 0)),
                        ValueProblem::kQuaternionNorm);
}

TEST(Validate, QuaternionNormWithinToleranceIsNormalized) {
  for (double scale : {1.0 + 5e-7, 1.0 - 5e-7}) {
    SCOPED_TRACE(scale);
    const Eigen::Quaterniond unit = SomeQuaternion(11);
    const Eigen::Quaterniond q(unit.coeffs() * scale);
    const auto r = ValidateQuaternion(q);
    ASSERT_TRUE(r);
    EXPECT_NEAR(r->norm(), 1.0, 1e-15);
    ExpectNear(*r, unit, 1e-15);
  }
}

// Normalizing is idempotent: a rotation that came out of validation (or is unit to rounding)
// goes through again bit for bit, so a value read back from a graph and added again is stored
// as it was (scene export relies on it). Random inputs off by up to the tolerance, and values
// off by a few ulps (products of rotations).
TEST(Validate, NormalizingIsIdempotent) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> off(-9e-7, 9e-7);
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Quaterniond unit = SomeQuaternion(static_cast<unsigned>(i));
    const Eigen::Quaterniond q(unit.coeffs() * (1.0 + off(rng)));
    const auto once = ValidateQuaternion(q);
    ASSERT_TRUE(once);
    const auto twice = ValidateQuaternion(*once);
    ASSERT_TRUE(twice);
    ASSERT_EQ(once->coeffs(), twice->coeffs()) << i;

    Eigen::Matrix3d R = unit.toRotationMatrix();
    R(i % 3, (i / 3) % 3) += off(rng) / 4;
    const auto R_once = ValidateRotationMatrix(R);
    ASSERT_TRUE(R_once);
    const auto R_twice = ValidateRotationMatrix(*R_once);
    ASSERT_TRUE(R_twice);
    ASSERT_EQ(*R_once, *R_twice) << i;
  }
  // A quaternion off unit by 2 ulp is kept; by 1e-14 (a long product) it is normalized.
  Eigen::Quaterniond near = SomeQuaternion(3);
  near.coeffs() *= 1.0 + 4.440892098500626e-16;
  if (std::abs(near.norm() - 1.0) <= kUnitRounding) {
    EXPECT_EQ(ValidateQuaternion(near)->coeffs(), near.coeffs());
  }
  const Eigen::Quaterniond drifted(SomeQuaternion(3).coeffs() * (1.0 + 1e-14));
  EXPECT_NE(ValidateQuaternion(drifted)->coeffs(), drifted.coeffs());
  EXPECT_NEAR(ValidateQuaternion(drifted)->norm(), 1.0, 1e-15);
  Eigen::Matrix3d M = SomeRotation(4);
  M(0, 1) += 1e-13;
  EXPECT_NE(*ValidateRotationMatrix(M), M);
  EXPECT_LT((ValidateRotationMatrix(M)->transpose() * *ValidateRotationMatrix(M) -
             Eigen::Matrix3d::Identity())
                .cwiseAbs()
                .maxCoeff(),
            1e-14);
}

// ================================================================== rotation matrices

TEST(Validate, NonFiniteRotationMatrixEntryIsInvalidNumberRowMajor) {
  Names n;
  const Eigen::Matrix3d R = SomeRotation(3);
  for (double bad : kBadNumbers) {
    for (int row = 0; row < 3; ++row) {
      for (int col = 0; col < 3; ++col) {
        Eigen::Matrix3d M = R;
        M(row, col) = bad;
        const int index = 3 * row + col;
        ExpectInvalidNumber(ValidateRotationMatrix(M), ValueRole::kRotationMatrix, index, bad,
                            n.table);
        ExpectInvalidNumber(MakeOrientation<HomogeneousBackend>(n.EdgeOrientation(), M),
                            ValueRole::kRotationMatrix, index, bad, n.table);
        ExpectInvalidNumber(MakePose<QuaternionBackend>(n.Edge(), M, Eigen::Vector3d(1, 0, 0)),
                            ValueRole::kRotationMatrix, index, bad, n.table);
        EXPECT_TRUE(Contains(Describe(ValidateRotationMatrix(M).error(), n.table),
                             "rotation matrix component " + std::to_string(index)));
      }
    }
  }
}

TEST(Validate, NonOrthonormalMatrixIsInvalidRotation) {
  Names n;
  const Eigen::Matrix3d R = SomeRotation(5);
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      for (double delta : {1e-5, -1e-5}) {
        Eigen::Matrix3d M = R;
        M(row, col) += delta;
        const auto r = ValidateRotationMatrix(M);
        ExpectInvalidRotation(r, ValueProblem::kNotOrthonormal);
        EXPECT_EQ(r.error().value.role, ValueRole::kRotationMatrix);
        EXPECT_GT(r.error().value.magnitude, kRotationTolerance);
        const std::string text = Describe(r.error(), n.table);
        EXPECT_TRUE(Contains(text, "rotation matrix is not orthonormal")) << text;
        EXPECT_TRUE(Contains(text, "max |M^T M - I|")) << text;
        ExpectInvalidRotation(MakeOrientation<QuaternionBackend>(n.EdgeOrientation(), M),
                              ValueProblem::kNotOrthonormal);
        ExpectInvalidRotation(MakePose<HomogeneousBackend>(n.Edge(), M, Eigen::Vector3d::Zero()),
                              ValueProblem::kNotOrthonormal);
      }
    }
  }
  ExpectInvalidRotation(ValidateRotationMatrix(2.0 * R), ValueProblem::kNotOrthonormal);
  ExpectInvalidRotation(ValidateRotationMatrix(Eigen::Matrix3d::Zero()),
                        ValueProblem::kNotOrthonormal);
}

TEST(Validate, NearlyOrthonormalMatrixIsReturnedOrthonormal) {
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 50; ++trial) {
    SCOPED_TRACE(trial);
    const Eigen::Matrix3d R = semgraph::testing::RandomUnitQuaternion(rng).toRotationMatrix();
    Eigen::Matrix3d M = R;
    for (int i = 0; i < 9; ++i) M.data()[i] += semgraph::testing::UniformDouble(rng, -1e-7, 1e-7);
    const auto r = ValidateRotationMatrix(M);
    ASSERT_TRUE(r) << Describe(r.error(), NameTable());
    ExpectNear(r->transpose() * *r, Eigen::Matrix3d::Identity(), 1e-12);
    EXPECT_NEAR(r->determinant(), 1.0, 1e-12);
    ExpectNear(*r, R, 1e-6);  // the nearest rotation, not some other one
  }
}

TEST(Validate, ReflectionIsInvalidRotation) {
  Names n;
  const Eigen::Matrix3d R = SomeRotation(9);
  for (const Eigen::Matrix3d& M :
       {Eigen::Matrix3d(-R), Eigen::Matrix3d(R * Eigen::Vector3d(1, 1, -1).asDiagonal()),
        Eigen::Matrix3d(Eigen::Vector3d(-1, 1, 1).asDiagonal())}) {
    const auto r = ValidateRotationMatrix(M);
    ExpectInvalidRotation(r, ValueProblem::kReflection);
    EXPECT_NEAR(r.error().value.magnitude, -1.0, 1e-12);
    const std::string text = Describe(r.error(), n.table);
    EXPECT_TRUE(Contains(text, "determinant")) << text;
    EXPECT_TRUE(Contains(text, "reflection")) << text;
    ExpectInvalidRotation(MakePose<QuaternionBackend>(n.Edge(), M, Eigen::Vector3d::Zero()),
                          ValueProblem::kReflection);
  }
}

// ================================================================== 4x4 homogeneous matrices

Eigen::Matrix4d SomeTransform() {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = SomeRotation(21);
  T.topRightCorner<3, 1>() = Eigen::Vector3d(0.25, -1.5, 2.0);
  return T;
}

template <class B>
class ValidateTyped : public ::testing::Test {};
struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};
using Backends =
    ::testing::Types<QuaternionBackend, HomogeneousBackend, testing::RotationMatrixBackend>;
TYPED_TEST_SUITE(ValidateTyped, Backends, BackendName);

TYPED_TEST(ValidateTyped, NonFiniteHomogeneousMatrixEntryIsInvalidNumberRowMajor) {
  Names n;
  for (double bad : kBadNumbers) {
    for (int row = 0; row < 4; ++row) {
      for (int col = 0; col < 4; ++col) {
        Eigen::Matrix4d T = SomeTransform();
        T(row, col) = bad;
        const int index = 4 * row + col;
        const auto r = MakePose<TypeParam>(n.Edge(), T);
        ExpectInvalidNumber(r, ValueRole::kHomogeneousMatrix, index, bad, n.table);
        if (!r) {
          EXPECT_TRUE(Contains(Describe(r.error(), n.table),
                               "homogeneous matrix component " + std::to_string(index)));
        }
      }
    }
  }
}

TYPED_TEST(ValidateTyped, HomogeneousMatrixWithBadBottomRowIsInvalidRotation) {
  Names n;
  for (int col = 0; col < 4; ++col) {
    Eigen::Matrix4d T = SomeTransform();
    T(3, col) += 1e-3;
    const auto r = MakePose<TypeParam>(n.Edge(), T);
    ExpectInvalidRotation(r, ValueProblem::kNotRigidTransform);
    EXPECT_EQ(r.error().value.role, ValueRole::kHomogeneousMatrix);
    EXPECT_NEAR(r.error().value.magnitude, 1e-3, 1e-12);
    const std::string text = Describe(r.error(), n.table);
    EXPECT_TRUE(Contains(text, "homogeneous matrix bottom row is not [0 0 0 1]")) << text;
  }
  // A non-orthonormal rotation block is reported as such.
  Eigen::Matrix4d T = SomeTransform();
  T(0, 1) += 1e-5;
  ExpectInvalidRotation(MakePose<TypeParam>(n.Edge(), T), ValueProblem::kNotOrthonormal);
}

TYPED_TEST(ValidateTyped, ValidInputsAreAcceptedInEveryForm) {
  using B = TypeParam;
  Names n;
  const Eigen::Matrix4d T = SomeTransform();
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const Eigen::Vector3d p = T.topRightCorner<3, 1>();
  const auto from_T = MakePose<B>(n.Edge(), T);
  const auto from_R = MakePose<B>(n.Edge(), R, p);
  const auto from_q = MakePose<B>(n.Edge(), Eigen::Quaterniond(R), p);
  for (const auto* X : {&from_T, &from_R, &from_q}) {
    ASSERT_TRUE(*X) << Describe(X->error(), n.table);
    ExpectNear(B::ToMatrix(B::RotationOf((*X)->value)), R, 1e-12);
    ExpectNear(B::TranslationOf((*X)->value), p, 1e-15);
  }
  // Within tolerance, the stored rotation is normalized whatever the input form.
  const auto slightly_off = MakeOrientation<B>(
      n.EdgeOrientation(), Eigen::Quaterniond(Eigen::Quaterniond(R).coeffs() * (1.0 + 5e-7)));
  ASSERT_TRUE(slightly_off);
  const Eigen::Matrix3d M = B::ToMatrix(slightly_off->value);
  ExpectNear(M.transpose() * M, Eigen::Matrix3d::Identity(), 1e-12);
  ExpectNear(M, R, 1e-12);
}

// ================================================================== order of the checks

TYPED_TEST(ValidateTyped, InvalidNumberIsReportedBeforeInvalidRotation) {
  Names n;
  // NaN inside a quaternion whose norm is also far from 1.
  const Eigen::Quaterniond q_nan(kNaN, 2.0, 0.0, 0.0);
  ExpectInvalidNumber(ValidateQuaternion(q_nan), ValueRole::kQuaternion, 0, kNaN, n.table);
  ExpectInvalidNumber(MakeOrientation<TypeParam>(n.EdgeOrientation(), q_nan),
                      ValueRole::kQuaternion, 0, kNaN, n.table);
  // A bad-norm quaternion with a non-finite position: the number wins.
  ExpectInvalidNumber(
      MakePose<TypeParam>(n.Edge(), Eigen::Quaterniond(2, 0, 0, 0), Eigen::Vector3d(0, kInf, 0)),
      ValueRole::kPosition, 1, kInf, n.table);
  // Inf inside a non-orthonormal (and reflected) matrix.
  Eigen::Matrix3d M = -3.0 * Eigen::Matrix3d::Identity();
  M(2, 1) = -kInf;
  ExpectInvalidNumber(ValidateRotationMatrix(M), ValueRole::kRotationMatrix, 7, -kInf, n.table);
  ExpectInvalidNumber(MakePose<TypeParam>(n.Edge(), M, Eigen::Vector3d::Zero()),
                      ValueRole::kRotationMatrix, 7, -kInf, n.table);
  // A 4x4 with NaN and a bad bottom row.
  Eigen::Matrix4d T = SomeTransform();
  T(3, 0) = 5.0;
  T(1, 3) = kNaN;
  ExpectInvalidNumber(MakePose<TypeParam>(n.Edge(), T), ValueRole::kHomogeneousMatrix, 7, kNaN,
                      n.table);
}

TYPED_TEST(ValidateTyped, RepresentationConstraintIsCheckedAfterTheNumbers) {
  using B = TypeParam;
  Names n;
  // Semantics no backend with [r] = [b] can hold: expressed in [c].
  const PoseSemantics off{n.a.origin(), n.a.axes(), n.A, n.b.origin(), n.b.axes(), n.B, n.c.axes()};
  const OrientationSemantics off_o{n.a.axes(), n.A, n.b.axes(), n.B, n.c.axes()};
  const Eigen::Matrix3d R = SomeRotation(4);
  const Eigen::Quaterniond q(R);
  // Bad numbers first, whatever the semantics.
  ExpectInvalidNumber(MakePose<B>(off, q, Eigen::Vector3d(kNaN, 0, 0)), ValueRole::kPosition, 0,
                      kNaN, n.table);
  ExpectInvalidRotation(
      MakePose<B>(off, Eigen::Quaterniond(q.coeffs() * 1.1), Eigen::Vector3d::Zero()),
      ValueProblem::kQuaternionNorm);
  ExpectInvalidRotation(MakeOrientation<B>(off_o, Eigen::Matrix3d(-R)), ValueProblem::kReflection);
  // Then the representation.
  const auto pose = MakePose<B>(off, q, Eigen::Vector3d::Zero());
  const auto orientation = MakeOrientation<B>(off_o, R);
  if (!B::kConstraints.coordinate_frame_is_ref_orientation) {
    EXPECT_TRUE(pose);
    EXPECT_TRUE(orientation);
    return;
  }
  for (const Error& e : {pose.error(), orientation.error()}) {
    EXPECT_EQ(e.code, ErrorCode::kRepresentationConstraint);
    ASSERT_NE(e.representation, nullptr);
    EXPECT_STREQ(e.representation, B::kName);
    const std::string text = Describe(e, n.table);
    EXPECT_TRUE(Contains(text, std::string("the ") + B::kName + " representation requires"))
        << text;
    EXPECT_TRUE(Contains(text, "coordinate frame [c]")) << text;
    EXPECT_TRUE(Contains(text, "reference orientation frame [b]|B")) << text;
  }
}

TEST(Validate, HomogeneousPointConstraintsAreNamedInTheText) {
  Names n;
  const Eigen::Quaterniond q = SomeQuaternion(2);
  // Point b on A is not the origin of [a].
  const PoseSemantics point_off{n.b.origin(), n.a.axes(), n.A,       n.b.origin(),
                                n.b.axes(),   n.B,        n.b.axes()};
  const auto r1 = MakePose<HomogeneousBackend>(point_off, q, Eigen::Vector3d::Zero());
  ASSERT_FALSE(r1);
  EXPECT_EQ(r1.error().code, ErrorCode::kRepresentationConstraint);
  EXPECT_EQ(Describe(r1.error(), n.table),
            "the homogeneous representation requires point b|A of the pose to be the origin of "
            "orientation frame [a]|A of the pose");
  // Reference point a on B is not the origin of [b].
  const PoseSemantics ref_off{n.a.origin(), n.a.axes(), n.A,       n.a.origin(),
                              n.b.axes(),   n.B,        n.b.axes()};
  const auto r2 = MakePose<HomogeneousBackend>(ref_off, q, Eigen::Vector3d::Zero());
  ASSERT_FALSE(r2);
  const std::string text = Describe(r2.error(), n.table);
  EXPECT_TRUE(Contains(text, "reference point a|B of the pose to be the origin of")) << text;
  // Both of these are fine for the other backends.
  EXPECT_TRUE(MakePose<QuaternionBackend>(point_off, q, Eigen::Vector3d::Zero()));
  EXPECT_TRUE(MakePose<testing::RotationMatrixBackend>(ref_off, q, Eigen::Vector3d::Zero()));
}

}  // namespace
}  // namespace semgraph::coord
