// coord/se3.h: SE(3) Exp/Log, screw and linear interpolation, the segment twist, and the
// checked semantic operations Integrate / Differentiate / Interpolate.
//
// Ground truth is analytic, never another semgraph computation:
//   - a body spinning at rate w about the z axis through the point c of its parent {t}, while
//     sliding along that axis at speed h: X(s) = (Rz(w s), c - Rz(w s) c + (0, 0, h s)), whose
//     screw twist is the constant (v, w) = (c x w_vec + (0, 0, h), (0, 0, w)) (derived by hand:
//     R^T dR/ds = [w_vec]x, R^T dp/ds = R^T (-Rdot c) + h z = -w_vec x c + h z);
//   - linear interpolation: p by hand, the rotation by Eigen's own slerp (an independent
//     implementation), and a rotation about a fixed axis interpolated at a fraction of its angle;
//   - derivatives: central differences of the interpolated motion.
#include "semgraph/coord/se3.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/quaternion_backend.h"
#include "support/tolerance.h"

namespace semgraph::coord {
namespace {

using kernels::QuatPose;
using semgraph::testing::ExpectNear;

Eigen::Quaterniond Rz(double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
}

// The analytic screw motion of the file comment.
struct ScrewMotion {
  Eigen::Vector3d c{0.7, -0.4, 0.2};
  double w = 1.3, h = 0.25;
  QuatPose At(double s) const {
    const Eigen::Quaterniond R = Rz(w * s);
    return {R, c - R * c + Eigen::Vector3d(0, 0, h * s)};
  }
  Eigen::Vector3d v() const { return c.cross(Eigen::Vector3d(0, 0, w)) + Eigen::Vector3d(0, 0, h); }
  Eigen::Vector3d omega() const { return {0, 0, w}; }
};

TEST(Se3Test, ExpOfTheScrewTwistIsTheAnalyticMotion) {
  const ScrewMotion m;
  for (double s : {0.0, 1e-9, 1e-5, 0.01, 0.07, 0.08, 0.5, 1.0, 2.0, 2.4}) {
    const QuatPose X = kernels::Exp(s * m.v(), s * m.omega());
    const QuatPose truth = m.At(s);
    ExpectNear(X.q, truth.q, 1e-13);
    ExpectNear(X.p, truth.p, 1e-13);
  }
}

TEST(Se3Test, LogInvertsExpAcrossAngles) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double angle : {0.0, 1e-12, 1e-7, 1e-3, 0.0999, 0.1, 0.1001, 1.0, 2.5, 3.1, 3.14159}) {
    for (int k = 0; k < 20; ++k) {
      Eigen::Vector3d axis(u(rng), u(rng), u(rng));
      axis.normalize();
      const Eigen::Vector3d w = angle * axis, v(u(rng), u(rng), u(rng));
      const QuatPose X = kernels::Exp(v, w);
      Eigen::Vector3d v2, w2;
      kernels::Log(X, v2, w2);
      ExpectNear(w2, w, 1e-10);
      ExpectNear(v2, v, 1e-9);
      // The rotation part agrees with Eigen's angle-axis.
      ExpectNear(X.q, Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis)), 1e-14);
    }
  }
}

TEST(Se3Test, LogOfTheAnalyticMotionIsItsTwist) {
  const ScrewMotion m;
  for (double s : {1e-6, 0.05, 0.5, 2.0}) {
    Eigen::Vector3d v, w;
    kernels::Log(m.At(s), v, w);
    ExpectNear(v, s * m.v(), 1e-12);
    ExpectNear(w, s * m.omega(), 1e-12);
  }
}

TEST(Se3Test, LogUsesTheShorterRotation) {
  // q and -q are one rotation; the angle reported is in [0, pi].
  const Eigen::Quaterniond q(Eigen::AngleAxisd(2.0, Eigen::Vector3d::UnitX()));
  Eigen::Vector3d v, w;
  kernels::Log(QuatPose{Eigen::Quaterniond(-q.coeffs()), Eigen::Vector3d::Zero()}, v, w);
  ExpectNear(w, Eigen::Vector3d(2.0, 0, 0), 1e-14);
  // A rotation of 4 rad is a rotation of 2*pi - 4 the other way.
  kernels::Log(QuatPose{Eigen::Quaterniond(Eigen::AngleAxisd(4.0, Eigen::Vector3d::UnitX())),
                        Eigen::Vector3d::Zero()},
               v, w);
  ExpectNear(w, Eigen::Vector3d(4.0 - 2 * M_PI, 0, 0), 1e-13);
}

TEST(Se3Test, ScrewInterpolationReproducesAConstantTwistMotionExactly) {
  const ScrewMotion m;
  const double s0 = 0.3, s1 = 1.9;
  const QuatPose X0 = m.At(s0), X1 = m.At(s1);
  for (double lambda : {0.0, 0.1, 0.25, 0.5, 0.77, 1.0}) {
    const QuatPose X = kernels::InterpolateScrew(X0, X1, lambda);
    const QuatPose truth = m.At(s0 + lambda * (s1 - s0));
    ExpectNear(X.q, truth.q, 1e-13);
    ExpectNear(X.p, truth.p, 1e-12);
  }
  // Linear interpolation does not follow a screw with an offset axis (the chord is straight).
  const QuatPose L = kernels::InterpolateLinear(X0, X1, 0.5);
  EXPECT_GT((L.p - m.At(0.5 * (s0 + s1)).p).norm(), 1e-2);
}

TEST(Se3Test, LinearInterpolationIsLerpAndSlerp) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Quaterniond q0 = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
    Eigen::Quaterniond q1 = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
    if (k % 2) q1.coeffs() = -q1.coeffs();  // either sign: the shorter arc either way
    const Eigen::Vector3d p0(u(rng), u(rng), u(rng)), p1(u(rng), u(rng), u(rng));
    const double lambda = 0.5 * (u(rng) + 1.0);
    const QuatPose X = kernels::InterpolateLinear({q0, p0}, {q1, p1}, lambda);
    ExpectNear(X.p, Eigen::Vector3d((1 - lambda) * p0 + lambda * p1), 1e-15);
    ExpectNear(X.q, q0.slerp(lambda, q1), 1e-12);
    EXPECT_NEAR(X.q.norm(), 1.0, 1e-14);
  }
  // About a fixed axis: the angle is interpolated.
  const QuatPose X = kernels::InterpolateLinear({Rz(0.2), Eigen::Vector3d::Zero()},
                                                {Rz(1.4), Eigen::Vector3d::Zero()}, 0.25);
  ExpectNear(X.q, Rz(0.5), 1e-14);
  // Identical rotations.
  ExpectNear(kernels::Slerp(Rz(0.3), Rz(0.3), 0.6), Rz(0.3), 1e-15);
}

// The series slerp weights against sin(t th) / sin th in long double (64-bit mantissa) over
// random angles up to the series' limit (u = 1 - cos th <= kSlerpSeriesMaxU), log-uniform down to
// 1e-9 rad, and random t: within 1e-15 relative (the header's bound is 3e-16).
TEST(Se3Test, SlerpSeriesWeightsMatchTrigonometry) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const long double th_max = std::acos(1.0L - static_cast<long double>(kernels::kSlerpSeriesMaxU));
  double worst = 0.0;
  for (int k = 0; k < 200000; ++k) {
    const double th = k % 2 ? static_cast<double>(th_max) * unit(rng)
                            : static_cast<double>(th_max) * std::pow(1e-9, unit(rng));
    const double x = std::cos(th);  // the series' input is the cosine, as a dot product gives
    const double t = k % 7 == 0 ? (k % 14 == 0 ? 0.0 : 1.0) : unit(rng);
    double w0 = 0.0, w1 = 0.0;
    if (1.0 - x > kernels::kSlerpSeriesMaxU) continue;
    kernels::SlerpSeriesWeights(1.0 - t, t, 1.0 - x, w0, w1);
    const long double th_l = std::acos(static_cast<long double>(x));
    const long double s = std::sin(th_l);
    const long double t0 = static_cast<long double>(1.0 - t);  // 1 - t as the kernel rounds it
    // At th = 0 (x == 1) the weights are the limits 1 - t and t.
    const long double e0 = th_l == 0 ? t0 : std::sin(t0 * th_l) / s;
    const long double e1 = th_l == 0 ? static_cast<long double>(t) : std::sin(t * th_l) / s;
    if (e0 != 0) worst = std::max(worst, static_cast<double>(std::abs((w0 - e0) / e0)));
    if (e1 != 0) worst = std::max(worst, static_cast<double>(std::abs((w1 - e1) / e1)));
    if (e0 == 0) {
      EXPECT_EQ(w0, 0.0);
    }
    if (e1 == 0) {
      EXPECT_EQ(w1, 0.0);
    }
  }
  EXPECT_LE(worst, 1e-15);
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", worst);
  RecordProperty("worst_relative_error", text);
}

// Slerp on either side of the series' limit and at tiny angles: the rotation about a fixed axis
// at the fraction of the angle (analytic), unit norm, and Eigen's slerp.
TEST(Se3Test, SlerpSmallAnglesAndTheSeriesLimit) {
  const double th_max = std::acos(1.0 - kernels::kSlerpSeriesMaxU);  // half angle
  for (double angle : {1e-300, 1e-12, 1e-7, 1e-3, 0.1, 2 * th_max * (1 - 1e-12),
                       2 * th_max * (1 + 1e-12), 0.6, 2.0}) {
    for (double lambda : {0.0, 1e-9, 0.3, 0.5, 0.999, 1.0}) {
      const Eigen::Quaterniond q0 = Rz(0.4) * Eigen::Quaterniond(Eigen::AngleAxisd(
                                                  0.3, Eigen::Vector3d(1, 2, 3).normalized()));
      const Eigen::Vector3d axis = Eigen::Vector3d(-2, 1, 0.5).normalized();
      const Eigen::Quaterniond q1 = q0 * Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis));
      const Eigen::Quaterniond truth =
          q0 * Eigen::Quaterniond(Eigen::AngleAxisd(lambda * angle, axis));
      const Eigen::Quaterniond q = kernels::Slerp(q0, q1, lambda);
      ExpectNear(q, truth, 1e-15);
      EXPECT_NEAR(q.norm(), 1.0, 1e-15);
      Eigen::Quaterniond q1_neg = q1;
      q1_neg.coeffs() = -q1.coeffs();  // the shorter arc: the same rotation
      ExpectNear(kernels::Slerp(q0, q1_neg, lambda), truth, 1e-15);
    }
  }
}

// The body-fixed twist of the interpolated motion by central differences:
// X^-1 dX/ds = ([w], v) -> v = R^T dp/ds, w = vee(R^T dR/ds) (quaternion form: 2 (q^-1 qdot).vec).
void NumericTwist(Interpolation mode, const QuatPose& X0, const QuatPose& X1, double dt,
                  double lambda, Eigen::Vector3d& v, Eigen::Vector3d& w) {
  const double h = 1e-6;
  const QuatPose a = kernels::Interpolate(mode, X0, X1, lambda - h),
                 b = kernels::Interpolate(mode, X0, X1, lambda + h);
  const QuatPose X = kernels::Interpolate(mode, X0, X1, lambda);
  Eigen::Quaterniond qb = b.q;
  if (qb.coeffs().dot(a.q.coeffs()) < 0) qb.coeffs() = -qb.coeffs();
  Eigen::Quaterniond q = X.q;
  if (q.coeffs().dot(a.q.coeffs()) < 0) q.coeffs() = -q.coeffs();
  const Eigen::Vector4d qdot = (qb.coeffs() - a.q.coeffs()) / (2 * h * dt);
  w = 2.0 * (q.conjugate() * Eigen::Quaterniond(qdot(3), qdot(0), qdot(1), qdot(2))).vec();
  v = X.q.conjugate() * ((b.p - a.p) / (2 * h * dt));
}

TEST(Se3Test, SegmentTwistIsTheDerivativeOfTheInterpolatedMotion) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Interpolation mode : {Interpolation::kScrew, Interpolation::kLinear}) {
    for (int k = 0; k < 50; ++k) {
      const QuatPose X0{Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized(),
                        {u(rng), u(rng), u(rng)}};
      const QuatPose X1 =
          kernels::Chain(X0, kernels::Exp({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}));
      const double dt = 0.2 + 0.5 * (u(rng) + 1.0), lambda = 0.1 + 0.4 * (u(rng) + 1.0);
      Eigen::Vector3d v, w, v_num, w_num;
      kernels::SegmentTwist(mode, X0, X1, dt, lambda, v, w);
      NumericTwist(mode, X0, X1, dt, lambda, v_num, w_num);
      ExpectNear(v, v_num, 1e-7);
      ExpectNear(w, w_num, 1e-7);
    }
  }
  // Screw mode on the analytic motion: exactly its twist.
  const ScrewMotion m;
  Eigen::Vector3d v, w;
  kernels::SegmentTwist(Interpolation::kScrew, m.At(0.1), m.At(0.6), 0.5, 0.3, v, w);
  ExpectNear(v, m.v(), 1e-12);
  ExpectNear(w, m.omega(), 1e-12);
}

TEST(Se3Test, IntegrationWithTheTwistExtrapolatesTheMotion) {
  const ScrewMotion m;
  const QuatPose X = kernels::Integrate(m.At(1.0), m.v(), m.omega(), 0.35);
  ExpectNear(X.q, m.At(1.35).q, 1e-13);
  ExpectNear(X.p, m.At(1.35).p, 1e-12);
  const QuatPose Y = kernels::Integrate(m.At(1.0), m.v(), m.omega(), -0.6);  // backwards
  ExpectNear(Y.p, m.At(0.4).p, 1e-12);
}

// ---------------------------------------------------------------- checked operations

class Se3CheckedTest : public ::testing::Test {
 protected:
  semantics::NameTable names;
  semantics::NameId Id(const char* n) { return *names.Intern(n); }
  semantics::Frame F(const char* n) { return semantics::Frame(Id(n)); }
  semantics::Body Bd(const char* n) { return semantics::Body(Id(n)); }
  // The edge {t}|T -> {h}|H.
  semantics::PoseSemantics Edge() {
    return semantics::PoseSemantics::OfFrame(F("h"), Bd("H"), F("t"), Bd("T"), F("t").axes());
  }
  semantics::TwistSemantics ScrewOfEdge() {
    return semantics::TwistSemantics{F("h").origin(), Bd("H"), Bd("T"), F("h").axes()};
  }
};

template <class B>
void CheckedOpsCompute(const semantics::PoseSemantics& edge,
                       const semantics::TwistSemantics& screw) {
  const ScrewMotion m;
  const auto pose = [&](double s) {
    const QuatPose X = m.At(s);
    return Pose<B>{edge, B::MakePose(B::FromQuaternion(X.q), X.p)};
  };
  auto xi = Differentiate<B>(pose(0.2), pose(0.7), 0.5);
  ASSERT_TRUE(xi.has_value());
  EXPECT_EQ(xi->semantics, screw);
  ExpectNear(xi->linear, m.v(), 1e-12);
  ExpectNear(xi->angular, m.omega(), 1e-12);
  auto X = Integrate<B>(pose(0.7), *xi, 0.4);
  ASSERT_TRUE(X.has_value());
  EXPECT_EQ(X->semantics, edge);
  ExpectNear(B::ToQuaternion(B::RotationOf(X->value)), m.At(1.1).q, 1e-12);
  ExpectNear(B::TranslationOf(X->value), m.At(1.1).p, 1e-12);
  auto I = Interpolate<B>(pose(0.2), pose(1.2), 0.3, Interpolation::kScrew);
  ASSERT_TRUE(I.has_value());
  ExpectNear(B::TranslationOf(I->value), m.At(0.5).p, 1e-12);
}

TEST_F(Se3CheckedTest, ComputeOnBothBackends) {
  CheckedOpsCompute<QuaternionBackend>(Edge(), ScrewOfEdge());
  CheckedOpsCompute<HomogeneousBackend>(Edge(), ScrewOfEdge());
}

TEST_F(Se3CheckedTest, IntegrateNeedsTheScrewTwistOfThatVeryEdge) {
  using B = QuaternionBackend;
  const Pose<B> X{Edge(), B::MakePose(Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero())};
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  EXPECT_TRUE(Integrate<B>(X, Twist{ScrewOfEdge(), z, z}, 1.0).has_value());
  auto bad = [&](semantics::TwistSemantics s, semantics::Field field) {
    auto r = Integrate<B>(X, Twist{s, z, z}, 1.0);
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, ErrorCode::kSemanticMismatch);
    EXPECT_EQ(r.error().mismatch.operation, semantics::Operation::kIntegrate);
    EXPECT_EQ(r.error().mismatch.lhs.field, field);
  };
  semantics::TwistSemantics s = ScrewOfEdge();
  s.coordinate_frame = F("t").axes();  // the twist in [t], not [h]
  bad(s, semantics::Field::kCoordinateFrame);
  s = ScrewOfEdge();
  s.ref_body = Bd("W");  // relative to another body
  bad(s, semantics::Field::kRefBody);
  s = ScrewOfEdge();
  s.point = F("t").origin();  // at another point
  bad(s, semantics::Field::kPoint);
  s = ScrewOfEdge();
  s.body = Bd("T");
  bad(s, semantics::Field::kBody);
  // A pose that is not in edge form cannot be integrated.
  semantics::PoseSemantics p = Edge();
  p.coordinate_frame = F("h").axes();
  auto r = Integrate<B>(Pose<B>{p, X.value}, Twist{ScrewOfEdge(), z, z}, 1.0);
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error().mismatch.lhs.field, semantics::Field::kCoordinateFrame);
}

TEST_F(Se3CheckedTest, DifferentiateAndInterpolateNeedTwoSamplesOfOneEdge) {
  using B = QuaternionBackend;
  const auto X0 =
      Pose<B>{Edge(), B::MakePose(Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero())};
  semantics::PoseSemantics other = Edge();
  other.ref_body = Bd("W");
  const auto X1 = Pose<B>{other, X0.value};
  auto d = Differentiate<B>(X0, X1, 1.0);
  ASSERT_FALSE(d.has_value());
  EXPECT_EQ(d.error().mismatch.operation, semantics::Operation::kDifferentiate);
  EXPECT_EQ(d.error().mismatch.lhs.field, semantics::Field::kRefBody);
  EXPECT_EQ(Differentiate<B>(X0, X0, 0.0).error().code, ErrorCode::kInvalidNumber);
  EXPECT_EQ(Differentiate<B>(X0, X0, NAN).error().code, ErrorCode::kInvalidNumber);
  auto i = Interpolate<B>(X0, X1, 0.5, Interpolation::kLinear);
  ASSERT_FALSE(i.has_value());
  EXPECT_EQ(i.error().mismatch.operation, semantics::Operation::kInterpolate);
  // Linear interpolation of a non-edge form is fine; screw interpolation is not.
  semantics::PoseSemantics in_h = Edge();
  in_h.coordinate_frame = F("h").axes();
  const auto Y = Pose<B>{in_h, X0.value};
  EXPECT_TRUE(Interpolate<B>(Y, Y, 0.5, Interpolation::kLinear).has_value());
  EXPECT_FALSE(Interpolate<B>(Y, Y, 0.5, Interpolation::kScrew).has_value());
  // Twists.
  const Twist V0{ScrewOfEdge(), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 2, 0)};
  Twist V1 = V0;
  V1.linear = Eigen::Vector3d(3, 0, 0);
  auto v = Interpolate(V0, V1, 0.25);
  ASSERT_TRUE(v.has_value());
  ExpectNear(v->linear, Eigen::Vector3d(1.5, 0, 0));
  V1.semantics.ref_body = Bd("W");
  EXPECT_EQ(Interpolate(V0, V1, 0.25).error().mismatch.lhs.field, semantics::Field::kRefBody);
}

}  // namespace
}  // namespace semgraph::coord
