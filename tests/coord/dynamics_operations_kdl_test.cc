// The wrench operations of coord/dynamics_operations.h against KDL (liborocos-kdl-dev), a peer
// nobody here wrote, on 1,000 random cases each:
//   Wrench::RefPoint(v)   moment about a new point (v: from the old point to the new one)
//                         == ChangePoint with Position(old point wrt new point) = -v
//   Rotation * Wrench     re-expressed in another frame == ChangeCoordinateFrame
//   Frame * Wrench        moved along a pose (rotation and lever arm) == ScrewTransform
//   dot(Twist, Wrench)    power == PowerOf, and it stays the same after KDL's and semgraph's
//                         changes of point and frame (with Twist::RefPoint, Frame * Twist)
// on both shipped backends.
#include <gtest/gtest.h>

#include <kdl/frames.hpp>
#include <random>
#include <string>

#include "semgraph/coord/dynamics_operations.h"
#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/quaternion_backend.h"
#include "semgraph/semantics/describe.h"
#include "support/tolerance.h"
#include "support/world_scene.h"

namespace semgraph::coord {
namespace {

using semantics::Body;
using semantics::Frame;
using semantics::NameTable;
using semantics::OrientationFrame;
using semantics::Point;
using semgraph::testing::Near;
using semgraph::testing::RandomUnitQuaternion;
using semgraph::testing::RandomVector;
using Vec = Eigen::Vector3d;

constexpr int kCases = 1000;
constexpr double kTol = 1e-9;  // forces and moments O(10), lever arms O(1)

KDL::Vector ToKdl(const Vec& v) { return KDL::Vector(v.x(), v.y(), v.z()); }
Vec FromKdl(const KDL::Vector& v) { return Vec(v.x(), v.y(), v.z()); }
KDL::Rotation ToKdl(const Eigen::Matrix3d& R) {
  return KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1),
                       R(2, 2));
}

// Names: the wrench on C by D; points e, q; frames {a}, {b} (origin and axes); [r], [s].
// Monograms: F_DCe the wrench on C by D about e (F_DCe_s: expressed in [s]), V_DCa the twist of
// C relative to D at a; KDL values are named kW, kV.
template <class B>
class WrenchKdl : public ::testing::Test {
 protected:
  NameTable names_;
  const Body C{*names_.Intern("C")}, D{*names_.Intern("D")};
  const Point e{*names_.Intern("e")}, q{*names_.Intern("q")};
  const Frame a{*names_.Intern("a")}, b{*names_.Intern("b")};
  const OrientationFrame r{*names_.Intern("r")}, s{*names_.Intern("s")};
  std::mt19937_64 rng_{2024};

  Wrench RandomWrench(const WrenchSemantics& sem) {
    return *MakeWrench(sem, RandomVector(rng_, 10.0), RandomVector(rng_, 10.0));
  }
  template <class T>
  T Must(const Result<T>& result) const {
    if (!result) {
      ADD_FAILURE() << "refused: " << Describe(result.error(), names_);
      return T{};
    }
    return *result;
  }
};
struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};
using Backends = ::testing::Types<QuaternionBackend, HomogeneousBackend>;
TYPED_TEST_SUITE(WrenchKdl, Backends, BackendName);

TYPED_TEST(WrenchKdl, ChangeOfPointIsRefPoint) {
  auto& t = *this;
  for (int i = 0; i < kCases; ++i) {
    const Wrench F_DCe = t.RandomWrench({t.e, t.C, t.D, t.r});
    const Vec v_eq = RandomVector(t.rng_, 3.0);  // from the old point e to the new point q
    const KDL::Wrench kdl =
        KDL::Wrench(ToKdl(F_DCe.force), ToKdl(F_DCe.moment)).RefPoint(ToKdl(v_eq));
    const Wrench F_DCq =
        t.Must(ChangePoint(F_DCe, *MakePosition({t.e, t.C, t.q, t.C, t.r}, -v_eq)));
    ASSERT_EQ(F_DCq.semantics, (WrenchSemantics{t.q, t.C, t.D, t.r}));
    EXPECT_TRUE(Near(F_DCq.force, FromKdl(kdl.force), kTol));
    EXPECT_TRUE(Near(F_DCq.moment, FromKdl(kdl.torque), kTol));
  }
}

TYPED_TEST(WrenchKdl, ChangeOfFrameIsRotationTimesWrench) {
  using B = TypeParam;
  auto& t = *this;
  for (int i = 0; i < kCases; ++i) {
    const Wrench F_DCe_r = t.RandomWrench({t.e, t.C, t.D, t.r});
    const Eigen::Matrix3d R_sr = RandomUnitQuaternion(t.rng_).toRotationMatrix();
    const KDL::Wrench kdl = ToKdl(R_sr) * KDL::Wrench(ToKdl(F_DCe_r.force), ToKdl(F_DCe_r.moment));
    const auto O_sr = *MakeOrientation<B>({t.r, t.D, t.s, t.D, t.s}, R_sr);
    const Wrench F_DCe_s = t.Must(ChangeCoordinateFrame(F_DCe_r, O_sr));
    ASSERT_EQ(F_DCe_s.semantics, (WrenchSemantics{t.e, t.C, t.D, t.s}));
    EXPECT_TRUE(Near(F_DCe_s.force, FromKdl(kdl.force), kTol));
    EXPECT_TRUE(Near(F_DCe_s.moment, FromKdl(kdl.torque), kTol));
  }
}

TYPED_TEST(WrenchKdl, ScrewTransformIsFrameTimesWrench) {
  using B = TypeParam;
  auto& t = *this;
  for (int i = 0; i < kCases; ++i) {
    // The wrench at {a}'s origin in [a]; the pose of {a} in {b} (KDL's Frame F_ba).
    const Wrench F_DCa = t.RandomWrench({t.a.origin(), t.C, t.D, t.a.axes()});
    const Eigen::Matrix3d R_ba = RandomUnitQuaternion(t.rng_).toRotationMatrix();
    const Vec p_ba = RandomVector(t.rng_, 3.0);
    const KDL::Frame F_ba(ToKdl(R_ba), ToKdl(p_ba));
    const KDL::Wrench kdl = F_ba * KDL::Wrench(ToKdl(F_DCa.force), ToKdl(F_DCa.moment));
    const auto X_ba =
        *MakePose<B>(PoseSemantics::OfFrame(t.a, t.C, t.b, t.D, t.b.axes()), R_ba, p_ba);
    const Wrench F_DCb = t.Must(ScrewTransform(F_DCa, X_ba));
    ASSERT_EQ(F_DCb.semantics, (WrenchSemantics{t.b.origin(), t.C, t.D, t.b.axes()}));
    EXPECT_TRUE(Near(F_DCb.force, FromKdl(kdl.force), kTol));
    EXPECT_TRUE(Near(F_DCb.moment, FromKdl(kdl.torque), kTol));
  }
}

TYPED_TEST(WrenchKdl, PowerIsKdlsDotAndSurvivesEveryChangeOfPointAndFrame) {
  using B = TypeParam;
  auto& t = *this;
  for (int i = 0; i < kCases; ++i) {
    const Wrench F_DCa = t.RandomWrench({t.a.origin(), t.C, t.D, t.a.axes()});
    const Twist V_a = *MakeTwist({t.a.origin(), t.C, t.D, t.a.axes()}, RandomVector(t.rng_, 2.0),
                                 RandomVector(t.rng_, 2.0));
    const KDL::Wrench kW(ToKdl(F_DCa.force), ToKdl(F_DCa.moment));
    const KDL::Twist kV(ToKdl(V_a.linear), ToKdl(V_a.angular));
    const double P = t.Must(PowerOf(F_DCa, V_a)).value;
    const double tol = kTol * (1.0 + std::abs(P));
    EXPECT_NEAR(P, KDL::dot(kV, kW), tol);
    // Along a pose, in both libraries.
    const Eigen::Matrix3d R_ba = RandomUnitQuaternion(t.rng_).toRotationMatrix();
    const Vec p_ba = RandomVector(t.rng_, 3.0);
    const KDL::Frame F_ba(ToKdl(R_ba), ToKdl(p_ba));
    const auto X_ba =
        *MakePose<B>(PoseSemantics::OfFrame(t.a, t.C, t.b, t.D, t.b.axes()), R_ba, p_ba);
    const double P_b =
        t.Must(PowerOf(t.Must(ScrewTransform(F_DCa, X_ba)), t.Must(ScrewTransform(V_a, X_ba))))
            .value;
    EXPECT_NEAR(P_b, KDL::dot(F_ba * kV, F_ba * kW), tol);
    EXPECT_NEAR(P_b, P, tol);
    // To another point, in both libraries.
    const Vec v_aq = RandomVector(t.rng_, 3.0);
    const Position p_qa = *MakePosition({t.a.origin(), t.C, t.q, t.C, t.a.axes()}, -v_aq);
    const double P_q =
        t.Must(PowerOf(t.Must(ChangePoint(F_DCa, p_qa)), t.Must(ChangePoint(V_a, p_qa)))).value;
    EXPECT_NEAR(P_q, KDL::dot(kV.RefPoint(ToKdl(v_aq)), kW.RefPoint(ToKdl(v_aq))), tol);
    EXPECT_NEAR(P_q, P, tol);
  }
}

}  // namespace
}  // namespace semgraph::coord
