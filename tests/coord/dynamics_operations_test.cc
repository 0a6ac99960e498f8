// The checked operations of coord/dynamics_operations.h against motions and loads worked out by
// hand (a uniformly rotating and a spinning-up disc: centripetal and tangential acceleration; a
// bead sliding along a rotating rod: Coriolis; a weight on a lever), against finite differences
// of the same closed-form trajectories, and against invariants that hold whatever the numbers
// (power under every change of point and frame, on every backend; an acceleration composed with
// its inverse is zero). Refusals carry the semantic mismatch unchanged. The peers (DART for
// accelerations, KDL for wrenches) are in dynamics_operations_{dart,kdl}_test.cc.
//
// Monograms: A_DCe = (a_DCe, alpha_DC), the acceleration of C relative to D at e; V_DCe the
// twist; w_DC the angular velocity; p_qe the position of e relative to q; F_DCe the wrench on
// C by D about e; R_sr the rotation that re-expresses from [r] into [s].
#include "semgraph/coord/dynamics_operations.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/quaternion_backend.h"
#include "semgraph/semantics/describe.h"
#include "support/rotation_matrix_backend.h"
#include "support/tolerance.h"
#include "support/world_scene.h"

namespace semgraph::coord {
namespace {

using base::ErrorCode;
using semantics::Body;
using semantics::NameTable;
using semantics::OrientationFrame;
using semantics::Point;
using semgraph::testing::Near;
using semgraph::testing::RandomUnitQuaternion;
using semgraph::testing::RandomVector;
using Vec = Eigen::Vector3d;

// Bodies: M the world, B a rod, C the body moving (disc, bead), D the disc's base, E another.
// Points: o the disc's centre, e a point, q another point. Frames: [r], [s] coordinate frames.
class Dynamics : public ::testing::Test {
 protected:
  NameTable names_;
  const Body B{*names_.Intern("B")}, C{*names_.Intern("C")}, D{*names_.Intern("D")},
      E{*names_.Intern("E")}, M{*names_.Intern("M")};
  const Point o{*names_.Intern("o")}, e{*names_.Intern("e")}, q{*names_.Intern("q")};
  const OrientationFrame r{*names_.Intern("r")}, s{*names_.Intern("s")};

  static Acceleration Acc(const AccelerationSemantics& sem, const Vec& a, const Vec& alpha) {
    return *MakeAcceleration(sem, a, alpha);
  }
  static Twist Tw(const TwistSemantics& sem, const Vec& v, const Vec& w) {
    return *MakeTwist(sem, v, w);
  }
  static Wrench Wr(const WrenchSemantics& sem, const Vec& f, const Vec& m) {
    return *MakeWrench(sem, f, m);
  }
  static AngularVelocity Ang(const AngularVelocitySemantics& sem, const Vec& w) {
    return *MakeAngularVelocity(sem, w);
  }
  static Position Pos(const PositionSemantics& sem, const Vec& p) { return *MakePosition(sem, p); }

  template <class T>
  ::testing::AssertionResult RefusedWith(const Result<T>& result, semantics::Operation op,
                                         semantics::Field field) const {
    if (result) return ::testing::AssertionFailure() << "accepted";
    const Error& err = result.error();
    if (err.code == ErrorCode::kSemanticMismatch && err.mismatch.operation == op &&
        err.mismatch.lhs.field == field) {
      return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionFailure() << Describe(err, names_);
  }
};

/// Second derivative at t = 0 of a closed-form trajectory, by central differences (h = 1e-4:
/// error O(h^2) ~ 1e-8 relative on these O(1) motions).
Vec SecondDerivative(const std::function<Vec(double)>& p) {
  const double h = 1e-4;
  return (p(h) - 2.0 * p(0.0) + p(-h)) / (h * h);
}

// ================================================================ accelerations by hand

TEST_F(Dynamics, APointOnAUniformlyRotatingDiscAcceleratesTowardsTheCentre) {
  // Disc C turns about the z axis of D at w0; e is at radius R on the x axis; [r] = D's axes.
  const double w0 = 3.0, R = 0.5;
  const Acceleration A_DCo = Acc({o, C, D, r}, Vec::Zero(), Vec::Zero());
  const Position p_eo = Pos({o, C, e, C, r}, Vec(-R, 0, 0));  // old point o wrt new point e
  const AngularVelocity w_DC = Ang({C, D, r}, Vec(0, 0, w0));
  const auto A_DCe = ChangePoint(A_DCo, p_eo, w_DC);
  ASSERT_TRUE(A_DCe);
  EXPECT_EQ(A_DCe->semantics, (AccelerationSemantics{e, C, D, r}));
  EXPECT_TRUE(Near(A_DCe->linear, Vec(-w0 * w0 * R, 0, 0)));  // |a| = w0^2 R, inwards
  EXPECT_TRUE(Near(A_DCe->angular, Vec::Zero()));
}

TEST_F(Dynamics, ASpinningUpDiscAddsTheTangentialAcceleration) {
  const double w0 = 2.0, alpha0 = 5.0, R = 0.3;
  const Acceleration A_DCo = Acc({o, C, D, r}, Vec::Zero(), Vec(0, 0, alpha0));
  const auto A_DCe =
      ChangePoint(A_DCo, Pos({o, C, e, C, r}, Vec(-R, 0, 0)), Ang({C, D, r}, Vec(0, 0, w0)));
  ASSERT_TRUE(A_DCe);
  EXPECT_TRUE(Near(A_DCe->linear, Vec(-w0 * w0 * R, alpha0 * R, 0)));
  // The same from the trajectory of e: angle w0 t + alpha0 t^2 / 2.
  const Vec fd = SecondDerivative([&](double t) -> Vec {
    const double th = w0 * t + 0.5 * alpha0 * t * t;
    return Vec(R * std::cos(th), R * std::sin(th), 0);
  });
  EXPECT_TRUE(Near(A_DCe->linear, fd, 1e-6));
}

TEST_F(Dynamics, ABeadSlidingOnARotatingRodFeelsCoriolis) {
  // Rod B turns about z of M at w; bead C slides out along the rod at u and spins about the
  // rod's axis at spin. At t = 0 the rod lies on x and the bead is at rho.
  const double w = 1.5, u = 0.8, rho = 0.6, spin = 2.0;
  const AccelerationSemantics s_BC{e, C, B, r}, s_MB{e, B, M, r};
  const Acceleration A_BCe = Acc(s_BC, Vec::Zero(), Vec::Zero());
  const Acceleration A_MBe = Acc(s_MB, Vec(-w * w * rho, 0, 0), Vec::Zero());  // centripetal
  const Twist V_BCe = Tw({e, C, B, r}, Vec(u, 0, 0), Vec(spin, 0, 0));
  const AngularVelocity w_MB = Ang({B, M, r}, Vec(0, 0, w));
  const auto A_MC_e = Compose(A_BCe, A_MBe, V_BCe, w_MB);
  ASSERT_TRUE(A_MC_e);
  EXPECT_EQ(A_MC_e->semantics, (AccelerationSemantics{e, C, M, r}));
  // Polar coordinates: (rho'' - rho th'^2, rho th'' + 2 rho' th') = (-rho w^2, 2 u w).
  EXPECT_TRUE(Near(A_MC_e->linear, Vec(-rho * w * w, 2 * u * w, 0)));
  const Vec fd = SecondDerivative(
      [&](double t) -> Vec { return (rho + u * t) * Vec(std::cos(w * t), std::sin(w * t), 0); });
  EXPECT_TRUE(Near(A_MC_e->linear, fd, 1e-6));
  // alpha_MC = d/dt (w z + spin R_z(wt) x) = spin w y.
  EXPECT_TRUE(Near(A_MC_e->angular, Vec(0, spin * w, 0)));
  // Adding the accelerations (Coriolis forgotten) would give the centripetal term only.
  EXPECT_FALSE(Near(A_MC_e->linear, A_BCe.linear + A_MBe.linear, 1e-3));
}

TEST_F(Dynamics, TheInverseOfADiscsMotionIsNotItsNegation) {
  // Seen from the disc C, the point of D at e turns the other way on the same circle: its
  // acceleration is centripetal too, with the tangential part reversed.
  const double w0 = 2.0, alpha0 = 3.0, R = 0.4;
  const Acceleration A_DCe = Acc({e, C, D, r}, Vec(-w0 * w0 * R, alpha0 * R, 0), Vec(0, 0, alpha0));
  const Twist V_DCe = Tw({e, C, D, r}, Vec(0, w0 * R, 0), Vec(0, 0, w0));
  const auto A_CDe = Inverse(A_DCe, V_DCe);
  ASSERT_TRUE(A_CDe);
  EXPECT_EQ(A_CDe->semantics, (AccelerationSemantics{e, D, C, r}));
  EXPECT_TRUE(Near(A_CDe->angular, Vec(0, 0, -alpha0)));
  // In C's axes (aligned with [r] at t = 0), e of D sits at angle -th(t).
  const Vec fd = SecondDerivative([&](double t) -> Vec {
    const double th = w0 * t + 0.5 * alpha0 * t * t;
    return Vec(R * std::cos(-th), R * std::sin(-th), 0);
  });
  EXPECT_TRUE(Near(A_CDe->linear, fd, 1e-6));
  EXPECT_TRUE(Near(A_CDe->linear, Vec(-w0 * w0 * R, -alpha0 * R, 0)));
}

TEST_F(Dynamics, AnAccelerationComposedWithItsInverseIsZero) {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 1000; ++i) {
    const Acceleration A_DCe = Acc({e, C, D, r}, RandomVector(rng, 5), RandomVector(rng, 5));
    const Twist V_DCe = Tw({e, C, D, r}, RandomVector(rng, 2), RandomVector(rng, 2));
    const auto A_CDe = Inverse(A_DCe, V_DCe);
    ASSERT_TRUE(A_CDe);
    // C rel D, then D rel C: C rel C.
    const auto A_CCe = Compose(A_DCe, *A_CDe, V_DCe, Ang({D, C, r}, -V_DCe.angular));
    ASSERT_TRUE(A_CCe);
    EXPECT_EQ(A_CCe->semantics, (AccelerationSemantics{e, C, C, r}));
    EXPECT_TRUE(Near(A_CCe->linear, Vec::Zero(), 1e-12));
    EXPECT_TRUE(Near(A_CCe->angular, Vec::Zero(), 1e-12));
  }
}

TEST_F(Dynamics, ChangingThePointThereAndBackIsTheIdentity) {
  std::mt19937_64 rng(8);
  for (int i = 0; i < 1000; ++i) {
    const Acceleration A_DCe = Acc({e, C, D, r}, RandomVector(rng, 5), RandomVector(rng, 5));
    const AngularVelocity w_DC = Ang({C, D, r}, RandomVector(rng, 2));
    const Vec p = RandomVector(rng, 2);
    const auto A_DCq = ChangePoint(A_DCe, Pos({e, C, q, C, r}, p), w_DC);
    ASSERT_TRUE(A_DCq);
    const auto back = ChangePoint(*A_DCq, Pos({q, C, e, C, r}, -p), w_DC);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->semantics, A_DCe.semantics);
    EXPECT_TRUE(Near(back->linear, A_DCe.linear, 1e-12));
    EXPECT_TRUE(Near(back->angular, A_DCe.angular, 0));
  }
}

TEST_F(Dynamics, AccelerationOperationsRefuseMismatchesNamingTheField) {
  const Acceleration A_DCe = Acc({e, C, D, r}, Vec(1, 2, 3), Vec(4, 5, 6));
  const Twist V_CDe = Tw({e, D, C, r}, Vec(1, 0, 0), Vec(0, 1, 0));  // the inverse relation's
  using semantics::Field;
  using semantics::Operation;
  EXPECT_TRUE(RefusedWith(Inverse(A_DCe, V_CDe), Operation::kInverse, Field::kBody));
  EXPECT_TRUE(RefusedWith(
      ChangePoint(A_DCe, Pos({e, C, q, C, s}, Vec(1, 0, 0)), Ang({C, D, r}, Vec(0, 0, 1))),
      Operation::kChangePoint, Field::kCoordinateFrame));
  EXPECT_TRUE(RefusedWith(
      ChangePoint(A_DCe, Pos({e, C, q, C, r}, Vec(1, 0, 0)), Ang({C, E, r}, Vec(0, 0, 1))),
      Operation::kChangePoint, Field::kRefBody));
  const Acceleration A_EDe = Acc({e, D, E, r}, Vec::Zero(), Vec::Zero());
  EXPECT_TRUE(RefusedWith(Compose(A_DCe, A_EDe, Tw({e, C, D, r}, Vec::Zero(), Vec::Zero()),
                                  Ang({C, D, r}, Vec::Zero())),
                          Operation::kCompose, Field::kBody));
  const Acceleration A_DCe_s = Acc({e, C, D, s}, Vec::Zero(), Vec::Zero());
  EXPECT_TRUE(RefusedWith(Compose(A_DCe, A_DCe_s, Tw({e, C, D, r}, Vec::Zero(), Vec::Zero()),
                                  Ang({C, D, s}, Vec::Zero())),
                          Operation::kCompose, Field::kRefBody));
}

// ================================================================ wrenches by hand

TEST_F(Dynamics, AWeightOnALeverHasAMomentAboutThePivot) {
  // 10 N down (-z) at e; the pivot q is 1 m behind e along x: m_q = (e - q) x f = (0, 10, 0).
  const Wrench F_DCe = Wr({e, C, D, r}, Vec(0, 0, -10), Vec::Zero());
  const auto F_DCq = ChangePoint(F_DCe, Pos({e, C, q, C, r}, Vec(1, 0, 0)));
  ASSERT_TRUE(F_DCq);
  EXPECT_EQ(F_DCq->semantics, (WrenchSemantics{q, C, D, r}));
  EXPECT_TRUE(Near(F_DCq->force, Vec(0, 0, -10), 0));
  EXPECT_TRUE(Near(F_DCq->moment, Vec(0, 10, 0), 0));
}

TEST_F(Dynamics, RotatingAWrenchKeepsItsPointAndMovingItKeepsItsAxes) {
  // [s] is [r] turned by 90 degrees about z: R[s<-r] maps x to -y and y to x.
  const Wrench F_DCe = Wr({e, C, D, r}, Vec(1, 2, 3), Vec(4, 5, 6));
  const Eigen::Quaterniond q_sr(Eigen::AngleAxisd(-M_PI / 2, Vec::UnitZ()));
  const auto O_sr = *MakeOrientation<QuaternionBackend>({r, E, s, E, s}, q_sr);
  const auto F_DCe_s = ChangeCoordinateFrame(F_DCe, O_sr);
  ASSERT_TRUE(F_DCe_s);
  EXPECT_EQ(F_DCe_s->semantics, (WrenchSemantics{e, C, D, s}));
  EXPECT_TRUE(Near(F_DCe_s->force, Vec(2, -1, 3), 1e-15));
  EXPECT_TRUE(Near(F_DCe_s->moment, Vec(5, -4, 6), 1e-15));
}

TEST_F(Dynamics, AReactionIsTheOppositeWrenchOnTheOtherBody) {
  const Wrench F_DCe = Wr({e, C, D, r}, Vec(1, -2, 3), Vec(-4, 5, -6));
  const auto F_CDe = Reaction(F_DCe);
  ASSERT_TRUE(F_CDe);
  EXPECT_EQ(F_CDe->semantics, (WrenchSemantics{e, D, C, r}));
  EXPECT_EQ(F_CDe->force, Vec(-1, 2, -3));
  EXPECT_EQ(F_CDe->moment, Vec(4, -5, 6));
}

TEST_F(Dynamics, WrenchesOnOneBodyAddAtOnePoint) {
  const Wrench F_DCe = Wr({e, C, D, r}, Vec(1, 0, 0), Vec(0, 0, 1));
  const Wrench F_ECe = Wr({e, C, E, r}, Vec(0, 2, 0), Vec(0, 0, -3));
  const auto net = Sum(F_DCe, F_ECe);
  ASSERT_TRUE(net);
  EXPECT_EQ(net->semantics, (WrenchSemantics{e, C, Body(), r, true}));
  EXPECT_EQ(net->force, Vec(1, 2, 0));
  EXPECT_EQ(net->moment, Vec(0, 0, -2));
  using semantics::Field;
  using semantics::Operation;
  EXPECT_TRUE(RefusedWith(Reaction(*net), Operation::kReaction, Field::kRefBody));
  // Summed about different points, the moments would not be of one wrench.
  const Wrench F_ECq = Wr({q, C, E, r}, Vec(0, 2, 0), Vec(0, 0, -3));
  EXPECT_TRUE(RefusedWith(Sum(F_DCe, F_ECq), Operation::kSum, Field::kPoint));
  EXPECT_TRUE(RefusedWith(Sum(F_DCe, *Reaction(F_ECe)), Operation::kSum, Field::kBody));
}

TEST_F(Dynamics, PowerIsForceTimesVelocityPlusMomentTimesAngularVelocity) {
  const Wrench F_DCe = Wr({e, C, D, r}, Vec(1, 2, 3), Vec(4, 5, 6));
  const Twist V_DCe = Tw({e, C, D, r}, Vec(-1, 0, 2), Vec(0.5, -1, 0));
  const auto P = PowerOf(F_DCe, V_DCe);
  ASSERT_TRUE(P);
  EXPECT_EQ(P->semantics, (semantics::PowerSemantics{C, D}));
  EXPECT_EQ(P->value, (-1 + 0 + 6) + (2 - 5 + 0));
  using semantics::Field;
  using semantics::Operation;
  EXPECT_TRUE(RefusedWith(PowerOf(F_DCe, Tw({e, C, M, r}, Vec::Zero(), Vec::Zero())),
                          Operation::kPower, Field::kRefBody));
  EXPECT_TRUE(RefusedWith(PowerOf(F_DCe, Tw({q, C, D, r}, Vec::Zero(), Vec::Zero())),
                          Operation::kPower, Field::kPoint));
}

// ================================================================ every backend

template <class B>
class DynamicsTyped : public Dynamics {};
struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};
using Backends =
    ::testing::Types<QuaternionBackend, HomogeneousBackend, testing::RotationMatrixBackend>;
TYPED_TEST_SUITE(DynamicsTyped, Backends, BackendName);

TYPED_TEST(DynamicsTyped, AccelerationsAreReexpressedByRotatingBothVectors) {
  using B = TypeParam;
  const Acceleration A =
      this->Acc({this->e, this->C, this->D, this->r}, Vec(1, 2, 3), Vec(-1, 0, 2));
  const Eigen::Matrix3d R_sr = Eigen::AngleAxisd(M_PI / 2, Vec::UnitX()).toRotationMatrix();
  // O = [r] wrt [s] expressed in [s] (the [r] = [b] form every backend holds).
  const auto O_sr = *MakeOrientation<B>({this->r, this->E, this->s, this->E, this->s}, R_sr);
  const auto A_s = ChangeCoordinateFrame(A, O_sr);
  ASSERT_TRUE(A_s);
  EXPECT_EQ(A_s->semantics, (AccelerationSemantics{this->e, this->C, this->D, this->s}));
  EXPECT_TRUE(Near(A_s->linear, Vec(1, -3, 2), 1e-15));  // x about x: y -> z, z -> -y
  EXPECT_TRUE(Near(A_s->angular, Vec(-1, -2, 0), 1e-15));
  const auto O_bad = *MakeOrientation<B>({this->s, this->E, this->r, this->E, this->r}, R_sr);
  EXPECT_TRUE(this->RefusedWith(ChangeCoordinateFrame(A, O_bad),
                                semantics::Operation::kChangeCoordinateFrame,
                                semantics::Field::kOrientation));
}

TYPED_TEST(DynamicsTyped, PowerIsInvariantUnderEveryChangeOfPointAndFrame) {
  using B = TypeParam;
  const auto& t = *this;
  std::mt19937_64 rng(11);
  int checked = 0;
  for (int i = 0; i < 1000; ++i) {
    const Wrench W = t.Wr({t.e, t.C, t.D, t.r}, RandomVector(rng, 10), RandomVector(rng, 10));
    const Twist V = t.Tw({t.e, t.C, t.D, t.r}, RandomVector(rng, 2), RandomVector(rng, 2));
    const double P = PowerOf(W, V)->value;
    const double scale = 1.0 + std::abs(P);
    // Another point.
    const Position p_qe = t.Pos({t.e, t.C, t.q, t.C, t.r}, RandomVector(rng, 3));
    const auto P_q = PowerOf(*ChangePoint(W, p_qe), *ChangePoint(V, p_qe));
    ASSERT_TRUE(P_q);
    EXPECT_NEAR(P_q->value, P, 1e-12 * scale * 30);
    // Another frame.
    const Eigen::Quaterniond q_sr = RandomUnitQuaternion(rng);
    const auto O_sr = *MakeOrientation<B>({t.r, t.E, t.s, t.E, t.s}, q_sr);
    const auto P_s = PowerOf(*ChangeCoordinateFrame(W, O_sr), *ChangeCoordinateFrame(V, O_sr));
    ASSERT_TRUE(P_s);
    EXPECT_NEAR(P_s->value, P, 1e-12 * scale * 30);
    // Both at once, along a pose (KDL's Frame*Wrench and Frame*Twist).
    const semantics::Frame fa(t.r.id()), fb(t.s.id());
    const Wrench F_DCa = t.Wr({fa.origin(), t.C, t.D, t.r}, W.force, W.moment);
    const Twist V_a = t.Tw({fa.origin(), t.C, t.D, t.r}, V.linear, V.angular);
    const auto X_ba = *MakePose<B>(PoseSemantics::OfFrame(fa, t.C, fb, t.D, fb.axes()), q_sr,
                                   RandomVector(rng, 3));
    const auto P_b = PowerOf(*ScrewTransform(F_DCa, X_ba), *ScrewTransform(V_a, X_ba));
    ASSERT_TRUE(P_b);
    EXPECT_NEAR(P_b->value, P, 1e-12 * scale * 30);
    ++checked;
  }
  EXPECT_EQ(checked, 1000);
}

TYPED_TEST(DynamicsTyped, AWrenchScrewTransformIsAChangeOfFrameThenOfPoint) {
  using B = TypeParam;
  const auto& t = *this;
  std::mt19937_64 rng(12);
  const semantics::Frame fa(t.r.id()), fb(t.s.id());
  for (int i = 0; i < 200; ++i) {
    const Wrench F_DCa =
        t.Wr({fa.origin(), t.C, t.D, fa.axes()}, RandomVector(rng, 10), RandomVector(rng, 10));
    const Eigen::Quaterniond q_ba = RandomUnitQuaternion(rng);
    const Vec p_ba = RandomVector(rng, 3);  // origin of {a} wrt origin of {b}, in [b]
    const auto X_ba = *MakePose<B>(PoseSemantics::OfFrame(fa, t.C, fb, t.D, fb.axes()), q_ba, p_ba);
    const auto F_DCb = ScrewTransform(F_DCa, X_ba);
    ASSERT_TRUE(F_DCb);
    EXPECT_EQ(F_DCb->semantics, (WrenchSemantics{fb.origin(), t.C, t.D, fb.axes()}));
    const auto O_ba = *MakeOrientation<B>({fa.axes(), t.E, fb.axes(), t.E, fb.axes()}, q_ba);
    const auto F_DCa_B = *ChangeCoordinateFrame(F_DCa, O_ba);
    const auto F_DCb2 =
        ChangePoint(F_DCa_B, t.Pos({fa.origin(), t.C, fb.origin(), t.D, fb.axes()}, p_ba));
    ASSERT_TRUE(F_DCb2);
    EXPECT_EQ(F_DCb2->semantics, F_DCb->semantics);
    EXPECT_TRUE(Near(F_DCb->force, F_DCb2->force, 1e-12));
    EXPECT_TRUE(Near(F_DCb->moment, F_DCb2->moment, 1e-12));
  }
}

}  // namespace
}  // namespace semgraph::coord
