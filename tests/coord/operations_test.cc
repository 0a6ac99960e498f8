// Every checked operation of coord/operations.h, on every backend (quaternion, homogeneous and
// the test-only rotation-matrix backend), checked against an independent ground truth.
//
// Method: for each of kSeeds random WorldScenes (tests/support/world_scene.h: frames with
// absolute poses in a world frame W, bodies with absolute twists in W), pick random points,
// orientation frames, bodies and coordinate frames; build the operands with Make* from numbers
// derived directly from the world quantities; apply the operation; and compare the result with
// the numbers derived directly from the world for the RESULT semantics (which are predicted
// here too, not read back from the library). Nothing is checked against another semgraph
// computation, and the ground truth does not call semgraph.
//
// Representation constraints (predicted from the spec, kSpec below, not from B::kConstraints):
// when a backend cannot hold an operand, Make* must fail with kRepresentationConstraint naming
// the backend; when it cannot hold the result, the operation must. Each test also breaks one
// semantic precondition per operation and checks kSemanticMismatch with the operands unchanged
// (operations without preconditions say so).
//
// Monogram legend. Lower-case letters are frame indices of the WorldScene (frame "f<i>": its
// origin point and its orientation frame share the name); upper-case letters are bodies.
//   p_FE_R     Position: point e wrt point f, expressed in [r]
//   O_BA_R     Orientation of [a] wrt [b] expressed in [r] (operator R_RB R_BA R_BR);
//              O_BA_B is the plain rotation matrix R_BA = R[b<-a]
//   X_FE_R     Pose of (e,[a]) wrt (f,[b]) expressed in [r] (monogram by the points; in frame
//              form e = a and f = b, and X_FE_F is the scene-graph edge {e} wrt {f} in [f])
//   v_DCe_R   LinearVelocity of the point of body C coinciding with e, relative to D, in [r]
//   w_DC_R     AngularVelocity of body C relative to body D, in [r]
//   V_DCe_R   Twist (v_DCe_R, w_DC_R)
// A trailing 2 marks the new entity of a change (e2 is the new point e', r2 the new [r]).
#include "semgraph/coord/operations.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/quaternion_backend.h"
#include "semgraph/semantics/describe.h"
#include "support/rotation_matrix_backend.h"
#include "support/tolerance.h"
#include "support/world_scene.h"

namespace semgraph::semantics {
// Readable ErrorCode in gtest failure messages (found by ADL).
void PrintTo(ErrorCode code, std::ostream* os) { *os << ToString(code); }
}  // namespace semgraph::semantics

namespace semgraph::coord {
namespace {

using base::ErrorCode;
using semantics::NameTable;
using semgraph::testing::ExpectNear;
using semgraph::testing::UniformIndex;
using semgraph::testing::WorldScene;

constexpr int kSeeds = 50;
constexpr int kFrames = 9;
constexpr int kBodies = 3;

// ------------------------------------------------------------------ what the spec says

/// The constraints each representation imposes, from docs/rules.md §11 and
/// docs/semantics.md D6, written independently of the backends' own declarations.
struct SpecConstraints {
  bool point_is_origin = false;       ///< pose: e = origin of [a]
  bool ref_point_is_origin = false;   ///< pose: f = origin of [b]
  bool r_is_ref_orientation = false;  ///< pose and orientation: [r] = [b]
};
template <class B>
inline constexpr SpecConstraints kSpec{};
template <>
inline constexpr SpecConstraints kSpec<QuaternionBackend>{false, false, false};
template <>
inline constexpr SpecConstraints kSpec<HomogeneousBackend>{true, true, true};
template <>
inline constexpr SpecConstraints kSpec<testing::RotationMatrixBackend>{false, false, true};

template <class B>
bool Admits(const OrientationSemantics& s) {
  return !(kSpec<B>.r_is_ref_orientation && !(s.coordinate_frame == s.ref_orientation));
}
template <class B>
bool Admits(const PoseSemantics& s) {
  if (kSpec<B>.point_is_origin && s.point.id() != s.orientation.id()) return false;
  if (kSpec<B>.ref_point_is_origin && s.ref_point.id() != s.ref_orientation.id()) return false;
  return !(kSpec<B>.r_is_ref_orientation && !(s.coordinate_frame == s.ref_orientation));
}

// ------------------------------------------------------------------ bookkeeping

/// What a test exercised, summed over its seeds.
struct Tally {
  int values = 0;             ///< results compared with the ground truth
  int input_rejected = 0;     ///< Make* refused by the representation (checked)
  int result_rejected = 0;    ///< operation refused by the representation (checked)
  int semantic_rejected = 0;  ///< kSemanticMismatch checked
};

/// The test did what it is for: at least one value checked when `values`, at least one
/// representation rejection when `representation`, at least one semantic rejection when
/// `semantic`.
void ExpectExercised(const Tally& t, bool values, bool representation, bool semantic) {
  if (values) {
    EXPECT_GT(t.values, 0) << "no result was checked against the ground truth";
  }
  if (representation) {
    EXPECT_GT(t.input_rejected + t.result_rejected, 0) << "no representation rejection checked";
  }
  if (semantic) {
    EXPECT_GT(t.semantic_rejected, 0) << "no semantic rejection checked";
  }
}

template <class B>
void ExpectRepresentationError(const Error& e, const NameTable& names) {
  const std::string text = Describe(e, names);
  EXPECT_EQ(e.code, ErrorCode::kRepresentationConstraint) << text;
  ASSERT_NE(e.representation, nullptr) << text;
  EXPECT_STREQ(e.representation, B::kName);
  EXPECT_NE(text.find(B::kName), std::string::npos) << text;
  EXPECT_NE(text.find("requires"), std::string::npos) << text;
  // The error names two fields that the representation requires equal, and they differ.
  using semantics::Field;
  const Field l = e.mismatch.lhs.field, r = e.mismatch.rhs.field;
  EXPECT_TRUE((l == Field::kPoint && r == Field::kOrientation) ||
              (l == Field::kRefPoint && r == Field::kRefOrientation) ||
              (l == Field::kCoordinateFrame && r == Field::kRefOrientation))
      << text;
  EXPECT_NE(e.mismatch.lhs.name, e.mismatch.rhs.name) << text;
}

template <class T>
void ExpectSemanticMismatch(const Result<T>& r, const NameTable& names) {
  ASSERT_FALSE(r.has_value()) << "expected a semantic mismatch";
  const Error& e = r.error();
  const std::string text = Describe(e, names);
  EXPECT_EQ(e.code, ErrorCode::kSemanticMismatch) << text;
  EXPECT_EQ(e.mismatch.code, ErrorCode::kSemanticMismatch) << text;
  EXPECT_EQ(e.representation, nullptr) << text;
  EXPECT_NE(text.find("does not match"), std::string::npos) << text;
}

// Exact equality of two values (semantics and coordinates), for "operands unchanged".
bool Same(const Position& a, const Position& b) {
  return a.semantics == b.semantics && a.value == b.value;
}
bool Same(const LinearVelocity& a, const LinearVelocity& b) {
  return a.semantics == b.semantics && a.value == b.value;
}
bool Same(const AngularVelocity& a, const AngularVelocity& b) {
  return a.semantics == b.semantics && a.value == b.value;
}
bool Same(const Twist& a, const Twist& b) {
  return a.semantics == b.semantics && a.linear == b.linear && a.angular == b.angular;
}
template <class B>
bool Same(const Orientation<B>& a, const Orientation<B>& b) {
  return a.semantics == b.semantics && B::ToMatrix(a.value) == B::ToMatrix(b.value) &&
         B::ToQuaternion(a.value).coeffs() == B::ToQuaternion(b.value).coeffs();
}
template <class B>
bool Same(const Pose<B>& a, const Pose<B>& b) {
  return a.semantics == b.semantics &&
         Same<B>(Orientation<B>{{}, B::RotationOf(a.value)},
                 Orientation<B>{{}, B::RotationOf(b.value)}) &&
         B::TranslationOf(a.value) == B::TranslationOf(b.value);
}

// The operations, as generic callables (overload sets cannot be passed directly).
constexpr auto kInverseInNewRef = [](const auto& x) { return InverseInNewRef(x); };
constexpr auto kCompose = [](const auto& x, const auto& y) { return Compose(x, y); };
constexpr auto kChangePoint = [](const auto& x, const auto& a) { return ChangePoint(x, a); };
constexpr auto kChangeRefPoint = [](const auto& x, const auto& a) { return ChangeRefPoint(x, a); };
constexpr auto kChangeOrientationFrame = [](const auto& x, const auto& a) {
  return ChangeOrientationFrame(x, a);
};
constexpr auto kChangeRefOrientationFrame = [](const auto& x, const auto& a) {
  return ChangeRefOrientationFrame(x, a);
};
constexpr auto kChangeCoordinateFrame = [](const auto& x, const auto& o) {
  return ChangeCoordinateFrame(x, o);
};
constexpr auto kScrewTransform = [](const auto& x, const auto& p) { return ScrewTransform(x, p); };
constexpr auto kCombine = [](const auto& x, const auto& y) { return Combine(x, y); };

/// Pose choice: point e and orientation frame [a] (on one body), reference point f and
/// reference orientation frame [b] (on one body), coordinate frame [r].
struct PoseChoice {
  int e, a, f, b, r;
};

// ------------------------------------------------------------------ one random scene

/// One seeded world plus the helpers that turn its ground truth into semgraph values and check
/// semgraph results against it.
template <class B>
class Scene {
 public:
  Scene(int seed, Tally& tally)
      : w(static_cast<std::uint64_t>(seed), kFrames, kBodies), t_(tally) {}

  WorldScene w;
  [[nodiscard]] const NameTable& names() const { return w.names(); }

  // ---------------------------------------------------------- semantics from indices
  PositionSemantics PosSem(int e, int f, int r) const {
    return {w.point(e), w.body_of(e), w.point(f), w.body_of(f), w.axes(r)};
  }
  OrientationSemantics OriSem(int a, int b, int r) const {
    return {w.axes(a), w.body_of(a), w.axes(b), w.body_of(b), w.axes(r)};
  }
  PoseSemantics PoseSem(const PoseChoice& x) const {
    return {w.point(x.e), w.axes(x.a),    w.body_of(x.e), w.point(x.f),
            w.axes(x.b),  w.body_of(x.f), w.axes(x.r)};
  }
  LinearVelocitySemantics LinSem(int e, int C, int D, int r) const {
    return {w.point(e), w.body(C), w.body(D), w.axes(r)};
  }
  AngularVelocitySemantics AngSem(int C, int D, int r) const {
    return {w.body(C), w.body(D), w.axes(r)};
  }
  TwistSemantics TwistSem(int e, int C, int D, int r) const {
    return {w.point(e), w.body(C), w.body(D), w.axes(r)};
  }

  /// A random pose of frames of C wrt frames of D. With `fit`, adjusted to what B can hold.
  PoseChoice RandomPose(int C, int D, bool fit) {
    PoseChoice x{w.RandomFrameOn(C), w.RandomFrameOn(C), w.RandomFrameOn(D), w.RandomFrameOn(D),
                 w.RandomFrame()};
    if (fit) Fit(x);
    return x;
  }
  /// Makes the choice admissible for B (point = origin, ref point = origin, [r] = [b]).
  void Fit(PoseChoice& x) const {
    if (kSpec<B>.point_is_origin) x.a = x.e;
    if (kSpec<B>.ref_point_is_origin) x.b = x.f;
    if (kSpec<B>.r_is_ref_orientation) x.r = x.b;
  }

  // ---------------------------------------------------------- values from the ground truth
  Position P(int e, int f, int r) {
    auto made = MakePosition(PosSem(e, f, r), w.Position(e, f, r));
    EXPECT_TRUE(made.has_value());
    return made ? *made : Position{PosSem(e, f, r), Eigen::Vector3d::Zero()};
  }
  LinearVelocity L(int e, int C, int D, int r) {
    auto made = MakeLinearVelocity(LinSem(e, C, D, r), w.LinearVelocity(e, C, D, r));
    EXPECT_TRUE(made.has_value());
    return made ? *made : LinearVelocity{LinSem(e, C, D, r), Eigen::Vector3d::Zero()};
  }
  AngularVelocity W(int C, int D, int r) {
    auto made = MakeAngularVelocity(AngSem(C, D, r), w.AngularVelocity(C, D, r));
    EXPECT_TRUE(made.has_value());
    return made ? *made : AngularVelocity{AngSem(C, D, r), Eigen::Vector3d::Zero()};
  }
  Twist V(int e, int C, int D, int r) {
    auto made =
        MakeTwist(TwistSem(e, C, D, r), w.LinearVelocity(e, C, D, r), w.AngularVelocity(C, D, r));
    EXPECT_TRUE(made.has_value());
    return made ? *made : Twist{TwistSem(e, C, D, r), {}, {}};
  }
  /// Orientation of [a] wrt [b] in [r], from a matrix or a quaternion (random), or nullopt
  /// after checking that B refuses it.
  std::optional<Orientation<B>> O(int a, int b, int r) {
    const OrientationSemantics s = OriSem(a, b, r);
    const Eigen::Matrix3d M = w.OrientationOperator(a, b, r);
    const auto made =
        w.Coin() ? MakeOrientation<B>(s, M) : MakeOrientation<B>(s, Eigen::Quaterniond(M));
    return Made(made, Admits<B>(s));
  }
  /// Pose from quaternion + vector, matrix + vector or a 4x4 matrix (random), or nullopt after
  /// checking that B refuses it.
  std::optional<Pose<B>> X(const PoseChoice& x) {
    const PoseSemantics s = PoseSem(x);
    const Eigen::Matrix3d M = w.OrientationOperator(x.a, x.b, x.r);
    const Eigen::Vector3d p = w.Position(x.e, x.f, x.r);
    switch (UniformIndex(w.rng(), 3)) {
      case 0:
        return Made(MakePose<B>(s, Eigen::Quaterniond(M), p), Admits<B>(s));
      case 1:
        return Made(MakePose<B>(s, M, p), Admits<B>(s));
      default: {
        Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
        T.topLeftCorner<3, 3>() = M;
        T.topRightCorner<3, 1>() = p;
        return Made(MakePose<B>(s, T), Admits<B>(s));
      }
    }
  }

  // ---------------------------------------------------------- results
  /// The result of an operation on admitted operands: the value when B can hold the result
  /// semantics (`admitted`), else checks the representation error. Returns nullptr when there
  /// is no value to compare.
  template <class T>
  // Returns a copy: the result is usually a temporary that dies with the full-expression.
  std::optional<T> Check(const coord::Result<T>& r, bool admitted) {
    if (admitted) {
      EXPECT_TRUE(r.has_value()) << Describe(r.error(), names());
      if (!r) return std::nullopt;
      ++t_.values;
      return *r;
    }
    EXPECT_FALSE(r.has_value()) << "the " << B::kName << " representation admitted the result";
    if (!r) ExpectRepresentationError<B>(r.error(), names());
    ++t_.result_rejected;
    return std::nullopt;
  }
  /// Counts a result that is not a Result<> (an operation that cannot fail).
  void Counted() { ++t_.values; }

  /// op(x, a) must fail with kSemanticMismatch and leave x and a unchanged.
  template <class X, class A, class Op>
  void ExpectRejected(const X& x, const A& a, Op op) {
    const X x_before = x;
    const A a_before = a;
    ExpectSemanticMismatch(op(x, a), names());
    EXPECT_TRUE(Same(x, x_before)) << "the first operand changed";
    EXPECT_TRUE(Same(a, a_before)) << "the second operand changed";
    ++t_.semantic_rejected;
  }

  /// op(x) must fail with kSemanticMismatch and leave x unchanged.
  template <class X, class Op>
  void ExpectRejected(const X& x, Op op) {
    const X x_before = x;
    ExpectSemanticMismatch(op(x), names());
    EXPECT_TRUE(Same(x, x_before)) << "the operand changed";
    ++t_.semantic_rejected;
  }

  // ---------------------------------------------------------- comparisons with the world
  void ExpectPosition(const Position& got, int e, int f, int r) const {
    const PositionSemantics want = PosSem(e, f, r);
    EXPECT_TRUE(got.semantics == want) << semantics::Describe(got.semantics, names()) << " vs "
                                       << semantics::Describe(want, names());
    ExpectNear(got.value, w.Position(e, f, r));
  }
  void ExpectOrientation(const Orientation<B>& got, int a, int b, int r) const {
    const OrientationSemantics want = OriSem(a, b, r);
    EXPECT_TRUE(got.semantics == want) << semantics::Describe(got.semantics, names()) << " vs "
                                       << semantics::Describe(want, names());
    ExpectRotation(got.value, w.OrientationOperator(a, b, r));
  }
  void ExpectPose(const Pose<B>& got, const PoseChoice& x) const {
    const PoseSemantics want = PoseSem(x);
    EXPECT_TRUE(got.semantics == want) << semantics::Describe(got.semantics, names()) << " vs "
                                       << semantics::Describe(want, names());
    ExpectNear(B::TranslationOf(got.value), w.Position(x.e, x.f, x.r));
    ExpectRotation(B::RotationOf(got.value), w.OrientationOperator(x.a, x.b, x.r));
  }
  void ExpectLinear(const LinearVelocity& got, int e, int C, int D, int r) const {
    const LinearVelocitySemantics want = LinSem(e, C, D, r);
    EXPECT_TRUE(got.semantics == want) << semantics::Describe(got.semantics, names()) << " vs "
                                       << semantics::Describe(want, names());
    ExpectNear(got.value, w.LinearVelocity(e, C, D, r));
  }
  void ExpectAngular(const AngularVelocity& got, int C, int D, int r) const {
    const AngularVelocitySemantics want = AngSem(C, D, r);
    EXPECT_TRUE(got.semantics == want) << semantics::Describe(got.semantics, names()) << " vs "
                                       << semantics::Describe(want, names());
    ExpectNear(got.value, w.AngularVelocity(C, D, r));
  }
  void ExpectTwist(const Twist& got, int e, int C, int D, int r) const {
    const TwistSemantics want = TwistSem(e, C, D, r);
    EXPECT_TRUE(got.semantics == want) << semantics::Describe(got.semantics, names()) << " vs "
                                       << semantics::Describe(want, names());
    ExpectNear(got.linear, w.LinearVelocity(e, C, D, r));
    ExpectNear(got.angular, w.AngularVelocity(C, D, r));
  }

 private:
  template <class T>
  std::optional<T> Made(const coord::Result<T>& made, bool admitted) {
    if (admitted) {
      EXPECT_TRUE(made.has_value()) << Describe(made.error(), names());
      if (!made) return std::nullopt;
      return *made;
    }
    EXPECT_FALSE(made.has_value()) << "the " << B::kName << " representation admitted this";
    if (!made) ExpectRepresentationError<B>(made.error(), names());
    ++t_.input_rejected;
    return std::nullopt;
  }

  /// A backend rotation equals the expected operator: as a matrix, as a quaternion (up to
  /// sign), and it is still a proper rotation.
  static void ExpectRotation(const typename B::Rotation& got, const Eigen::Matrix3d& want) {
    const Eigen::Matrix3d M = B::ToMatrix(got);
    ExpectNear(M, want);
    ExpectNear(B::ToQuaternion(got), Eigen::Quaterniond(want));
    ExpectNear(M.transpose() * M, Eigen::Matrix3d::Identity());
    EXPECT_NEAR(M.determinant(), 1.0, 1e-9);
  }

  Tally& t_;
};

// ------------------------------------------------------------------ the suite

struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};

template <class B>
class CoordOperations : public ::testing::Test {};

using Backends =
    ::testing::Types<QuaternionBackend, HomogeneousBackend, testing::RotationMatrixBackend>;
TYPED_TEST_SUITE(CoordOperations, Backends, BackendName);

#define SEED_TRACE(seed) SCOPED_TRACE(::testing::Message() << "seed " << (seed))

template <class B>
constexpr bool kPinsCoordinateFrame = kSpec<B>.r_is_ref_orientation;
template <class B>
constexpr bool kPinsPoints = kSpec<B>.point_is_origin || kSpec<B>.ref_point_is_origin;

TYPED_TEST(CoordOperations, DeclaredConstraintsMatchTheSpec) {
  using B = TypeParam;
  EXPECT_EQ(B::kConstraints.pose_point_is_origin, kSpec<B>.point_is_origin);
  EXPECT_EQ(B::kConstraints.pose_ref_point_is_origin, kSpec<B>.ref_point_is_origin);
  EXPECT_EQ(B::kConstraints.coordinate_frame_is_ref_orientation, kSpec<B>.r_is_ref_orientation);
}

// ================================================================== Position

TYPED_TEST(CoordOperations, PositionInverse) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int e = s.w.RandomFrame(), f = s.w.RandomFrame(), r = s.w.RandomFrame();
    const Position p_FE_R = s.P(e, f, r);
    const Position p_EF_R = Inverse(p_FE_R);
    s.ExpectPosition(p_EF_R, f, e, r);
    s.Counted();
  }
  // Inverse has no precondition: there is no semantic rejection to check.
  ExpectExercised(t, true, false, false);
}

TYPED_TEST(CoordOperations, PositionCompose) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int e = s.w.RandomFrame(), f = s.w.RandomFrame(), g = s.w.RandomFrame();
    const int r = s.w.RandomFrame();
    const Position p_FE_R = s.P(e, f, r), p_GF_R = s.P(f, g, r);
    if (const auto p_GE_R = s.Check(Compose(p_FE_R, p_GF_R), true)) {
      s.ExpectPosition(*p_GE_R, e, g, r);
    }
    // The second's point is not the first's reference point; the coordinate frames differ.
    const int h = s.w.RandomFrameOtherThan(f);
    s.ExpectRejected(p_FE_R, s.P(h, g, r), kCompose);
    s.ExpectRejected(p_FE_R, s.P(f, g, s.w.RandomFrameOtherThan(r)), kCompose);
  }
  ExpectExercised(t, true, false, true);
}

TYPED_TEST(CoordOperations, PositionChangePoint) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int C = s.w.RandomBody();
    const int e = s.w.RandomFrameOn(C), e2 = s.w.RandomFrameOn(C);
    const int f = s.w.RandomFrame(), r = s.w.RandomFrame();
    const Position p_FE_R = s.P(e, f, r);
    const Position p_EE2_R = s.P(e2, e, r);  // new point wrt old point, both on C
    if (const auto p_FE2_R = s.Check(ChangePoint(p_FE_R, p_EE2_R), true)) {
      s.ExpectPosition(*p_FE2_R, e2, f, r);
    }
    // The new point is on another body than X's point.
    s.ExpectRejected(p_FE_R, s.P(s.w.RandomFrameNotOn(C), e, r), kChangePoint);
  }
  ExpectExercised(t, true, false, true);
}

TYPED_TEST(CoordOperations, PositionChangeRefPoint) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int D = s.w.RandomBody();
    const int f = s.w.RandomFrameOn(D), f2 = s.w.RandomFrameOn(D);
    const int e = s.w.RandomFrame(), r = s.w.RandomFrame();
    const Position p_FE_R = s.P(e, f, r);
    const Position p_F2F_R = s.P(f, f2, r);  // old reference point wrt new one, both on D
    if (const auto p_F2E_R = s.Check(ChangeRefPoint(p_FE_R, p_F2F_R), true)) {
      s.ExpectPosition(*p_F2E_R, e, f2, r);
    }
    // The new reference point is on another body.
    s.ExpectRejected(p_FE_R, s.P(f, s.w.RandomFrameNotOn(D), r), kChangeRefPoint);
  }
  ExpectExercised(t, true, false, true);
}

TYPED_TEST(CoordOperations, PositionChangeCoordinateFrame) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int e = s.w.RandomFrame(), f = s.w.RandomFrame();
    const int r = s.w.RandomFrame(), r2 = s.w.RandomFrame();
    const Position p_FE_R = s.P(e, f, r);
    // O = [r] wrt [r2], expressed in [r] or [r2] (a matrix backend holds only the latter).
    const auto O_R2R = s.O(r, r2, s.w.Coin() ? r : r2);
    if (!O_R2R) continue;
    if (const auto p_FE_R2 = s.Check(ChangeCoordinateFrame(p_FE_R, *O_R2R), true)) {
      s.ExpectPosition(*p_FE_R2, e, f, r2);
    }
    // O is about another orientation frame than X's coordinate frame.
    const int r3 = s.w.RandomFrameOtherThan(r);
    if (const auto O_R2R3 = s.O(r3, r2, r2)) {
      s.ExpectRejected(p_FE_R, *O_R2R3, kChangeCoordinateFrame);
    }
  }
  ExpectExercised(t, true, kPinsCoordinateFrame<B>, true);
}

// ================================================================== Orientation

TYPED_TEST(CoordOperations, OrientationInverse) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int a = s.w.RandomFrame(), b = s.w.RandomFrame();
    const int r =
        seed % 5 == 0 ? s.w.RandomFrame() : (kPinsCoordinateFrame<B> ? b : s.w.RandomFrame());
    const auto O_BA_R = s.O(a, b, r);
    if (!O_BA_R) continue;
    // The generic inverse keeps [r]: a matrix backend can hold it only when [r] = [a] too.
    if (const auto O_AB_R = s.Check(Inverse(*O_BA_R), Admits<B>(s.OriSem(b, a, r)))) {
      s.ExpectOrientation(*O_AB_R, b, a, r);
    }
  }
  // No precondition: there is no semantic rejection to check.
  ExpectExercised(t, !kPinsCoordinateFrame<B>, kPinsCoordinateFrame<B>, false);
}

TYPED_TEST(CoordOperations, OrientationInverseInNewRef) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int a = s.w.RandomFrame(), b = s.w.RandomFrame();
    const auto O_BA_B = s.O(a, b, b);
    if (!O_BA_B) continue;
    if (const auto O_AB_A = s.Check(InverseInNewRef(*O_BA_B), true)) {
      s.ExpectOrientation(*O_AB_A, b, a, a);
    }
    // Not expressed in its reference frame (only the quaternion backend can hold such a value;
    // the matrix backends refuse it at Make*, so no semantic rejection is possible for them).
    const int r = s.w.RandomFrameOtherThan(b);
    if (const auto O_BA_R = s.O(a, b, r)) {
      s.ExpectRejected(*O_BA_R, kInverseInNewRef);
    }
  }
  ExpectExercised(t, true, kPinsCoordinateFrame<B>, !kPinsCoordinateFrame<B>);
}

TYPED_TEST(CoordOperations, OrientationComposeChain) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int a = s.w.RandomFrame(), b = s.w.RandomFrame(), c = s.w.RandomFrame();
    const auto O_BA_B = s.O(a, b, b);
    const auto O_CB_C = s.O(b, c, c);
    if (!O_BA_B || !O_CB_C) continue;
    if (const auto O_CA_C = s.Check(Compose(*O_BA_B, *O_CB_C), true)) {
      s.ExpectOrientation(*O_CA_C, a, c, c);
    }
    // The second is not about the first's reference orientation frame.
    const int d = s.w.RandomFrameOtherThan(b);
    if (const auto O_CD_C = s.O(d, c, c)) s.ExpectRejected(*O_BA_B, *O_CD_C, kCompose);
  }
  ExpectExercised(t, true, false, true);
}

TYPED_TEST(CoordOperations, OrientationComposeSameFrame) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int a = s.w.RandomFrame(), b = s.w.RandomFrame(), c = s.w.RandomFrame();
    const int r = s.w.RandomFrame();
    // Both in one [r]: a matrix backend holds them only when [r] = [b] = [c].
    const auto O_BA_R = s.O(a, b, r);
    const auto O_CB_R = s.O(b, c, r);
    if (!O_BA_R || !O_CB_R) continue;
    if (const auto O_CA_R = s.Check(Compose(*O_BA_R, *O_CB_R), true)) {
      s.ExpectOrientation(*O_CA_R, a, c, r);
    }
    // Different coordinate frames, and not the matrix chain either.
    const int r2 = s.w.RandomFrameOtherThan(r);
    if (!(r == b && r2 == c)) {
      if (const auto O_CB_R2 = s.O(b, c, r2)) s.ExpectRejected(*O_BA_R, *O_CB_R2, kCompose);
    }
    // The second is not about the first's reference orientation frame.
    if (const auto O_CD_R = s.O(s.w.RandomFrameOtherThan(b), c, r)) {
      s.ExpectRejected(*O_BA_R, *O_CD_R, kCompose);
    }
  }
  ExpectExercised(t, !kPinsCoordinateFrame<B>, kPinsCoordinateFrame<B>, true);
}

TYPED_TEST(CoordOperations, OrientationChangeOrientationFrame) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody();
    const int a = s.w.RandomFrameOn(C), a2 = s.w.RandomFrameOn(C), b = s.w.RandomFrame();
    // Chain form (X in [b], A in [a]) or same-frame form (both in one [r]).
    const bool chain = s.w.Coin();
    const int r = chain ? b : s.w.RandomFrame();
    const auto O_BA_R = s.O(a, b, r);
    const auto O_AA2 = s.O(a2, a, chain ? a : r);  // [a2] wrt [a]
    if (!O_BA_R || !O_AA2) continue;
    // The result keeps X's coordinate frame in both forms.
    if (const auto O_BA2_R = s.Check(ChangeOrientationFrame(*O_BA_R, *O_AA2), true)) {
      s.ExpectOrientation(*O_BA2_R, a2, b, r);
    }
    // The new orientation frame is on another body.
    const int a3 = s.w.RandomFrameNotOn(C);
    if (const auto O_AA3 = s.O(a3, a, chain ? a : r)) {
      s.ExpectRejected(*O_BA_R, *O_AA3, kChangeOrientationFrame);
    }
  }
  ExpectExercised(t, true, kPinsCoordinateFrame<B>, true);
}

TYPED_TEST(CoordOperations, OrientationChangeRefOrientationFrame) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int D = s.w.RandomBody();
    const int b = s.w.RandomFrameOn(D), b2 = s.w.RandomFrameOn(D), a = s.w.RandomFrame();
    const bool chain = s.w.Coin();
    const int r = chain ? b : s.w.RandomFrame();
    const auto O_BA_R = s.O(a, b, r);
    const auto O_B2B = s.O(b, b2, chain ? b2 : r);  // [b] wrt [b2]
    if (!O_BA_R || !O_B2B) continue;
    // Chain: the result is expressed in [b2]; same frame: it stays in [r].
    const int r_result = chain ? b2 : r;
    if (const auto O_B2A = s.Check(ChangeRefOrientationFrame(*O_BA_R, *O_B2B), true)) {
      s.ExpectOrientation(*O_B2A, a, b2, r_result);
    }
    // The new reference orientation frame is on another body.
    const int b3 = s.w.RandomFrameNotOn(D);
    if (const auto O_B3B = s.O(b, b3, chain ? b3 : r)) {
      s.ExpectRejected(*O_BA_R, *O_B3B, kChangeRefOrientationFrame);
    }
    // Neither the same frame nor the chain (quaternion only: A in a third frame).
    if (chain) {
      const int r3 = s.w.RandomFrame();
      if (r3 != b && r3 != b2) {
        if (const auto O_B2B_R3 = s.O(b, b2, r3)) {
          s.ExpectRejected(*O_BA_R, *O_B2B_R3, kChangeRefOrientationFrame);
        }
      }
    }
  }
  ExpectExercised(t, true, kPinsCoordinateFrame<B>, true);
}

TYPED_TEST(CoordOperations, OrientationChangeCoordinateFrame) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int a = s.w.RandomFrame(), b = s.w.RandomFrame();
    const int r = kPinsCoordinateFrame<B> && seed % 5 != 0 ? b : s.w.RandomFrame();
    const int r2 = s.w.RandomFrame();
    const auto O_BA_R = s.O(a, b, r);
    const auto O_R2R = s.O(r, r2, s.w.Coin() ? r : r2);
    if (!O_BA_R || !O_R2R) continue;
    // A matrix backend cannot hold the result unless [r2] = [b].
    if (const auto O_BA_R2 =
            s.Check(ChangeCoordinateFrame(*O_BA_R, *O_R2R), Admits<B>(s.OriSem(a, b, r2)))) {
      s.ExpectOrientation(*O_BA_R2, a, b, r2);
    }
    // O is about another frame than X's coordinate frame.
    if (const auto O_R2R3 = s.O(s.w.RandomFrameOtherThan(r), r2, r2)) {
      s.ExpectRejected(*O_BA_R, *O_R2R3, kChangeCoordinateFrame);
    }
  }
  ExpectExercised(t, !kPinsCoordinateFrame<B>, kPinsCoordinateFrame<B>, true);
}

// ================================================================== Pose

TYPED_TEST(CoordOperations, PoseInverse) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBody();
    const PoseChoice x = s.RandomPose(C, D, seed % 5 != 0);
    const auto X_FE_R = s.X(x);
    if (!X_FE_R) continue;
    const PoseChoice inv{x.f, x.b, x.e, x.a, x.r};
    if (const auto X_EF_R = s.Check(Inverse(*X_FE_R), Admits<B>(s.PoseSem(inv)))) {
      s.ExpectPose(*X_EF_R, inv);
    }
  }
  // No precondition: there is no semantic rejection to check.
  ExpectExercised(t, !kPinsCoordinateFrame<B>, kPinsCoordinateFrame<B>, false);
}

TYPED_TEST(CoordOperations, PoseInverseInNewRef) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBody();
    PoseChoice x = s.RandomPose(C, D, seed % 5 != 0);
    x.r = x.b;
    const auto X_FE_F = s.X(x);
    if (!X_FE_F) continue;
    const PoseChoice inv{x.f, x.b, x.e, x.a, x.a};
    if (const auto X_EF_E = s.Check(InverseInNewRef(*X_FE_F), Admits<B>(s.PoseSem(inv)))) {
      s.ExpectPose(*X_EF_E, inv);
    }
    // Not expressed in its reference orientation frame (quaternion backend only).
    PoseChoice y = x;
    y.r = s.w.RandomFrameOtherThan(x.b);
    if (const auto X_FE_R = s.X(y)) {
      s.ExpectRejected(*X_FE_R, kInverseInNewRef);
    }
  }
  ExpectExercised(t, true, kPinsCoordinateFrame<B>, !kPinsCoordinateFrame<B>);
}

TYPED_TEST(CoordOperations, PoseComposeChain) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBody(), E = s.w.RandomBody();
    const bool fit = seed % 5 != 0;
    PoseChoice x = s.RandomPose(C, D, fit);  // (e,[a]) wrt (f,[b]) in [b]
    x.r = x.b;
    PoseChoice y = s.RandomPose(D, E, fit);  // (f,[b]) wrt (g,[c]) in [c]
    y.e = x.f;
    y.a = x.b;
    y.r = y.b;
    const auto X_FE_F = s.X(x);
    const auto X_GF_G = s.X(y);
    if (!X_FE_F || !X_GF_G) continue;
    const PoseChoice xy{x.e, x.a, y.f, y.b, y.b};
    if (const auto X_GE_G = s.Check(Compose(*X_FE_F, *X_GF_G), true)) {
      s.ExpectPose(*X_GE_G, xy);
    }
    // The second's point is not the first's reference point (same orientation frames).
    PoseChoice z = y;
    z.e = s.w.RandomFrameOtherThan(x.f);
    if (kSpec<B>.point_is_origin) z.a = z.e;
    if (const auto X_GH_G = s.X(z)) s.ExpectRejected(*X_FE_F, *X_GH_G, kCompose);
  }
  // In the chain form only a point constraint can refuse (in the unfitted seeds).
  ExpectExercised(t, true, kPinsPoints<B>, true);
}

TYPED_TEST(CoordOperations, PoseComposeSameFrame) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBody(), E = s.w.RandomBody();
    const int r = s.w.RandomFrame();
    PoseChoice x = s.RandomPose(C, D, false);
    x.r = r;
    PoseChoice y = s.RandomPose(D, E, false);
    y.e = x.f;
    y.a = x.b;
    y.r = r;
    const auto X_FE_R = s.X(x);
    const auto X_GF_R = s.X(y);
    if (!X_FE_R || !X_GF_R) continue;
    if (const auto X_GE_R = s.Check(Compose(*X_FE_R, *X_GF_R), true)) {
      s.ExpectPose(*X_GE_R, PoseChoice{x.e, x.a, y.f, y.b, r});
    }
    // Different coordinate frames and not the chain.
    PoseChoice z = y;
    z.r = s.w.RandomFrameOtherThan(r);
    if (!(x.r == x.b && z.r == z.b)) {
      if (const auto X_GF_R2 = s.X(z)) s.ExpectRejected(*X_FE_R, *X_GF_R2, kCompose);
    }
  }
  ExpectExercised(t, !kPinsCoordinateFrame<B>, kPinsCoordinateFrame<B>, !kPinsCoordinateFrame<B>);
}

TYPED_TEST(CoordOperations, PoseChangePoint) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBody();
    const PoseChoice x = s.RandomPose(C, D, seed % 5 != 0);
    const auto X_FE_R = s.X(x);
    if (!X_FE_R) continue;
    const int e2 = s.w.RandomFrameOn(C);
    const Position p_EE2_R = s.P(e2, x.e, x.r);
    const PoseChoice moved{e2, x.a, x.f, x.b, x.r};
    // Homogeneous: the new point must still be the origin of [a].
    if (const auto X_FE2_R = s.Check(ChangePoint(*X_FE_R, p_EE2_R), Admits<B>(s.PoseSem(moved)))) {
      s.ExpectPose(*X_FE2_R, moved);
    }
    // The new point is on another body; the position is in another coordinate frame. (For the
    // homogeneous backend the result would break its constraint too: the semantic check comes
    // first, so the code is still kSemanticMismatch.)
    s.ExpectRejected(*X_FE_R, s.P(s.w.RandomFrameNotOn(C), x.e, x.r), kChangePoint);
    s.ExpectRejected(*X_FE_R, s.P(e2, x.e, s.w.RandomFrameOtherThan(x.r)), kChangePoint);
  }
  ExpectExercised(t, !kSpec<B>.point_is_origin, kPinsPoints<B> || kPinsCoordinateFrame<B>, true);
}

TYPED_TEST(CoordOperations, PoseChangeRefPoint) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBody();
    const PoseChoice x = s.RandomPose(C, D, seed % 5 != 0);
    const auto X_FE_R = s.X(x);
    if (!X_FE_R) continue;
    const int f2 = s.w.RandomFrameOn(D);
    const Position p_F2F_R = s.P(x.f, f2, x.r);
    const PoseChoice moved{x.e, x.a, f2, x.b, x.r};
    if (const auto X_F2E_R =
            s.Check(ChangeRefPoint(*X_FE_R, p_F2F_R), Admits<B>(s.PoseSem(moved)))) {
      s.ExpectPose(*X_F2E_R, moved);
    }
    s.ExpectRejected(*X_FE_R, s.P(x.f, s.w.RandomFrameNotOn(D), x.r), kChangeRefPoint);
  }
  ExpectExercised(t, !kSpec<B>.ref_point_is_origin, kPinsPoints<B> || kPinsCoordinateFrame<B>,
                  true);
}

TYPED_TEST(CoordOperations, PoseChangeOrientationFrame) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBody();
    PoseChoice x = s.RandomPose(C, D, seed % 5 != 0);
    const bool chain = s.w.Coin();
    if (chain) x.r = x.b;
    const auto X_FE_R = s.X(x);
    if (!X_FE_R) continue;
    const int a2 = s.w.RandomFrameOn(C);
    const auto O_AA2 = s.O(a2, x.a, chain ? x.a : x.r);  // [a2] wrt [a]
    if (!O_AA2) continue;
    const PoseChoice changed{x.e, a2, x.f, x.b, x.r};  // position unchanged, X's [r] kept
    if (const auto X_FE_R2 =
            s.Check(ChangeOrientationFrame(*X_FE_R, *O_AA2), Admits<B>(s.PoseSem(changed)))) {
      s.ExpectPose(*X_FE_R2, changed);
    }
    if (const auto O_AA3 = s.O(s.w.RandomFrameNotOn(C), x.a, chain ? x.a : x.r)) {
      s.ExpectRejected(*X_FE_R, *O_AA3, kChangeOrientationFrame);
    }
  }
  ExpectExercised(t, !kSpec<B>.point_is_origin, kPinsPoints<B> || kPinsCoordinateFrame<B>, true);
}

TYPED_TEST(CoordOperations, PoseChangeRefOrientationFrame) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBody();
    PoseChoice x = s.RandomPose(C, D, seed % 5 != 0);
    const bool chain = s.w.Coin();
    if (chain) x.r = x.b;
    const auto X_FE_R = s.X(x);
    if (!X_FE_R) continue;
    const int b2 = s.w.RandomFrameOn(D);
    const auto O_B2B = s.O(x.b, b2, chain ? b2 : x.r);  // [b] wrt [b2]
    if (!O_B2B) continue;
    // Chain: re-expressed in [b2] (the position too); same frame: stays in [r].
    const PoseChoice changed{x.e, x.a, x.f, b2, chain ? b2 : x.r};
    if (const auto X_F2E =
            s.Check(ChangeRefOrientationFrame(*X_FE_R, *O_B2B), Admits<B>(s.PoseSem(changed)))) {
      s.ExpectPose(*X_F2E, changed);
    }
    const int b3 = s.w.RandomFrameNotOn(D);
    if (const auto O_B3B = s.O(x.b, b3, chain ? b3 : x.r)) {
      s.ExpectRejected(*X_FE_R, *O_B3B, kChangeRefOrientationFrame);
    }
  }
  ExpectExercised(t, !kSpec<B>.ref_point_is_origin, kPinsPoints<B> || kPinsCoordinateFrame<B>,
                  true);
}

TYPED_TEST(CoordOperations, PoseChangeCoordinateFrame) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBody();
    const PoseChoice x = s.RandomPose(C, D, seed % 5 != 0);
    const auto X_FE_R = s.X(x);
    if (!X_FE_R) continue;
    const int r2 = s.w.RandomFrame();
    const auto O_R2R = s.O(x.r, r2, s.w.Coin() ? x.r : r2);
    if (!O_R2R) continue;
    const PoseChoice changed{x.e, x.a, x.f, x.b, r2};
    if (const auto X_FE_R2 =
            s.Check(ChangeCoordinateFrame(*X_FE_R, *O_R2R), Admits<B>(s.PoseSem(changed)))) {
      s.ExpectPose(*X_FE_R2, changed);
    }
    if (const auto O_R2R3 = s.O(s.w.RandomFrameOtherThan(x.r), r2, r2)) {
      s.ExpectRejected(*X_FE_R, *O_R2R3, kChangeCoordinateFrame);
    }
  }
  ExpectExercised(t, !kPinsCoordinateFrame<B>, kPinsCoordinateFrame<B>, true);
}

TYPED_TEST(CoordOperations, PosePositionOf) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const PoseChoice x = s.RandomPose(s.w.RandomBody(), s.w.RandomBody(), seed % 5 != 0);
    const auto X_FE_R = s.X(x);
    if (!X_FE_R) continue;
    s.ExpectPosition(PositionOf(*X_FE_R), x.e, x.f, x.r);
    s.Counted();
  }
  // No precondition: there is no semantic rejection to check.
  ExpectExercised(t, true, kPinsPoints<B> || kPinsCoordinateFrame<B>, false);
}

TYPED_TEST(CoordOperations, PoseOrientationOf) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const PoseChoice x = s.RandomPose(s.w.RandomBody(), s.w.RandomBody(), seed % 5 != 0);
    const auto X_FE_R = s.X(x);
    if (!X_FE_R) continue;
    // Any pose a backend holds has an orientation part it holds ([r] = [b] carries over).
    if (const auto O_BA_R = s.Check(OrientationOf(*X_FE_R), Admits<B>(s.OriSem(x.a, x.b, x.r)))) {
      s.ExpectOrientation(*O_BA_R, x.a, x.b, x.r);
    }
  }
  // No precondition: there is no semantic rejection to check.
  ExpectExercised(t, true, kPinsPoints<B> || kPinsCoordinateFrame<B>, false);
}

TYPED_TEST(CoordOperations, PoseCombine) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBody();
    const PoseChoice x = s.RandomPose(C, D, seed % 5 != 0);
    const Position p_FE_R = s.P(x.e, x.f, x.r);
    const auto O_BA_R = s.O(x.a, x.b, x.r);
    if (!O_BA_R) continue;
    // Homogeneous: point and reference point must be the origins of [a] and [b].
    if (const auto X_FE_R = s.Check(Combine(p_FE_R, *O_BA_R), Admits<B>(s.PoseSem(x)))) {
      s.ExpectPose(*X_FE_R, x);
    }
    // The position is of a point on another body than the orientation's frame.
    s.ExpectRejected(s.P(s.w.RandomFrameNotOn(C), x.f, x.r), *O_BA_R, kCombine);
    // The position is in another coordinate frame.
    s.ExpectRejected(s.P(x.e, x.f, s.w.RandomFrameOtherThan(x.r)), *O_BA_R, kCombine);
  }
  ExpectExercised(t, true, kPinsPoints<B> || kPinsCoordinateFrame<B>, true);
}

// ================================================================== Linear / angular velocity

/// O = [r] wrt [r2], expressed in [r] or [r2] at random, or nullopt (after checking the refusal).
template <class B>
std::optional<Orientation<B>> CoordinateChange(Scene<B>& s, int r, int r2) {
  return s.O(r, r2, s.w.Coin() ? r : r2);
}

TYPED_TEST(CoordOperations, LinearVelocityInverse) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int e = s.w.RandomFrame(), C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C);
    const int r = s.w.RandomFrame();
    const LinearVelocity v_DCe_R = s.L(e, C, D, r);
    s.ExpectLinear(Inverse(v_DCe_R), e, D, C, r);
    s.Counted();
  }
  // No precondition: there is no semantic rejection to check.
  ExpectExercised(t, true, false, false);
}

TYPED_TEST(CoordOperations, LinearVelocityCompose) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int e = s.w.RandomFrame(), r = s.w.RandomFrame();
    const int C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C), E = s.w.RandomBodyOtherThan(D);
    const LinearVelocity v_DCe_R = s.L(e, C, D, r), v_EDe_R = s.L(e, D, E, r);
    if (const auto v_ECe_R = s.Check(Compose(v_DCe_R, v_EDe_R), true)) {
      s.ExpectLinear(*v_ECe_R, e, C, E, r);
    }
    // Velocities of different points do not add.
    s.ExpectRejected(v_DCe_R, s.L(s.w.RandomFrameOtherThan(e), D, E, r), kCompose);
    // The first's reference body is not the second's body.
    s.ExpectRejected(v_DCe_R, s.L(e, s.w.RandomBodyOtherThan(D), E, r), kCompose);
  }
  ExpectExercised(t, true, false, true);
}

TYPED_TEST(CoordOperations, LinearVelocityChangeCoordinateFrame) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int e = s.w.RandomFrame(), C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C);
    const int r = s.w.RandomFrame(), r2 = s.w.RandomFrame();
    const LinearVelocity v_DCe_R = s.L(e, C, D, r);
    const auto O_R2R = CoordinateChange(s, r, r2);
    if (!O_R2R) continue;
    if (const auto v_D_CE_R2 = s.Check(ChangeCoordinateFrame(v_DCe_R, *O_R2R), true)) {
      s.ExpectLinear(*v_D_CE_R2, e, C, D, r2);
    }
    if (const auto O_R2R3 = s.O(s.w.RandomFrameOtherThan(r), r2, r2)) {
      s.ExpectRejected(v_DCe_R, *O_R2R3, kChangeCoordinateFrame);
    }
  }
  ExpectExercised(t, true, kPinsCoordinateFrame<B>, true);
}

TYPED_TEST(CoordOperations, AngularVelocityInverse) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C), r = s.w.RandomFrame();
    const AngularVelocity w_DC_R = s.W(C, D, r);
    s.ExpectAngular(Inverse(w_DC_R), D, C, r);
    s.Counted();
  }
  // No precondition: there is no semantic rejection to check.
  ExpectExercised(t, true, false, false);
}

TYPED_TEST(CoordOperations, AngularVelocityCompose) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int r = s.w.RandomFrame();
    const int C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C), E = s.w.RandomBodyOtherThan(D);
    const AngularVelocity w_DC_R = s.W(C, D, r), w_ED_R = s.W(D, E, r);
    if (const auto w_EC_R = s.Check(Compose(w_DC_R, w_ED_R), true)) {
      s.ExpectAngular(*w_EC_R, C, E, r);
    }
    s.ExpectRejected(w_DC_R, s.W(s.w.RandomBodyOtherThan(D), E, r), kCompose);
    s.ExpectRejected(w_DC_R, s.W(D, E, s.w.RandomFrameOtherThan(r)), kCompose);
  }
  ExpectExercised(t, true, false, true);
}

TYPED_TEST(CoordOperations, AngularVelocityChangeCoordinateFrame) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C);
    const int r = s.w.RandomFrame(), r2 = s.w.RandomFrame();
    const AngularVelocity w_DC_R = s.W(C, D, r);
    const auto O_R2R = CoordinateChange(s, r, r2);
    if (!O_R2R) continue;
    if (const auto w_DC_R2 = s.Check(ChangeCoordinateFrame(w_DC_R, *O_R2R), true)) {
      s.ExpectAngular(*w_DC_R2, C, D, r2);
    }
    if (const auto O_R2R3 = s.O(s.w.RandomFrameOtherThan(r), r2, r2)) {
      s.ExpectRejected(w_DC_R, *O_R2R3, kChangeCoordinateFrame);
    }
  }
  ExpectExercised(t, true, kPinsCoordinateFrame<B>, true);
}

// ================================================================== Twist

TYPED_TEST(CoordOperations, TwistInverse) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int e = s.w.RandomFrame(), C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C);
    const int r = s.w.RandomFrame();
    const Twist V_DCe_R = s.V(e, C, D, r);
    s.ExpectTwist(Inverse(V_DCe_R), e, D, C, r);
    s.Counted();
  }
  // No precondition: there is no semantic rejection to check.
  ExpectExercised(t, true, false, false);
}

TYPED_TEST(CoordOperations, TwistCompose) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int e = s.w.RandomFrame(), r = s.w.RandomFrame();
    const int C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C), E = s.w.RandomBodyOtherThan(D);
    const Twist V_DCe_R = s.V(e, C, D, r), V_EDe_R = s.V(e, D, E, r);
    if (const auto V_ECe_R = s.Check(Compose(V_DCe_R, V_EDe_R), true)) {
      s.ExpectTwist(*V_ECe_R, e, C, E, r);
    }
    // Twists with different velocity reference points do not add.
    s.ExpectRejected(V_DCe_R, s.V(s.w.RandomFrameOtherThan(e), D, E, r), kCompose);
    s.ExpectRejected(V_DCe_R, s.V(e, D, E, s.w.RandomFrameOtherThan(r)), kCompose);
  }
  ExpectExercised(t, true, false, true);
}

TYPED_TEST(CoordOperations, TwistChangePoint) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int e = s.w.RandomFrame(), f = s.w.RandomFrameOtherThan(e), r = s.w.RandomFrame();
    const int C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C);
    const Twist V_DCe_R = s.V(e, C, D, r);
    const Position p_FE_R = s.P(e, f, r);  // old point wrt new point
    if (const auto V_DCf_R = s.Check(ChangePoint(V_DCe_R, p_FE_R), true)) {
      s.ExpectTwist(*V_DCf_R, f, C, D, r);
    }
    // The position is not of the twist's point; it is in another coordinate frame.
    s.ExpectRejected(V_DCe_R, s.P(s.w.RandomFrameOtherThan(e), f, r), kChangePoint);
    s.ExpectRejected(V_DCe_R, s.P(e, f, s.w.RandomFrameOtherThan(r)), kChangePoint);
  }
  ExpectExercised(t, true, false, true);
}

// Spec §5: moving a twist's reference point is v_new = v_old + w x (p_new - p_old).
TYPED_TEST(CoordOperations, TwistChangePointAddsAngularVelocityCrossLeverArm) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int e = s.w.RandomFrame(), f = s.w.RandomFrameOtherThan(e), r = s.w.RandomFrame();
    const int C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C);
    const Twist V_DCe_R = s.V(e, C, D, r);
    const auto V_DCf_R = ChangePoint(V_DCe_R, s.P(e, f, r));
    ASSERT_TRUE(V_DCf_R) << Describe(V_DCf_R.error(), s.names());
    // p_new - p_old = position of f wrt e in [r], straight from the world.
    const Eigen::Vector3d p_EF_R = s.w.Position(f, e, r);
    const Eigen::Vector3d shift = V_DCe_R.angular.cross(p_EF_R);
    ASSERT_GT(shift.norm(), 1e-6) << "degenerate scene: the lever arm changes nothing";
    ExpectNear(V_DCf_R->linear, V_DCe_R.linear + shift);
    ExpectNear(V_DCf_R->angular, V_DCe_R.angular);
    // And moving it back restores the original.
    const auto V_D_CE_R_again = ChangePoint(*V_DCf_R, s.P(f, e, r));
    ASSERT_TRUE(V_D_CE_R_again);
    ExpectNear(V_D_CE_R_again->linear, V_DCe_R.linear);
    EXPECT_TRUE(V_D_CE_R_again->semantics == V_DCe_R.semantics);
    s.Counted();
  }
  ExpectExercised(t, true, false, false);
}

TYPED_TEST(CoordOperations, TwistChangeCoordinateFrame) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int e = s.w.RandomFrame(), C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C);
    const int r = s.w.RandomFrame(), r2 = s.w.RandomFrame();
    const Twist V_DCe_R = s.V(e, C, D, r);
    const auto O_R2R = CoordinateChange(s, r, r2);
    if (!O_R2R) continue;
    if (const auto V_D_CE_R2 = s.Check(ChangeCoordinateFrame(V_DCe_R, *O_R2R), true)) {
      s.ExpectTwist(*V_D_CE_R2, e, C, D, r2);
    }
    if (const auto O_R2R3 = s.O(s.w.RandomFrameOtherThan(r), r2, r2)) {
      s.ExpectRejected(V_DCe_R, *O_R2R3, kChangeCoordinateFrame);
    }
  }
  ExpectExercised(t, true, kPinsCoordinateFrame<B>, true);
}

TYPED_TEST(CoordOperations, TwistScrewTransform) {
  using B = TypeParam;
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<B> s(seed, t);
    const int C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C);
    // P = Pose((e,[a]), (f,[b]), [b]); the twist is at e, expressed in [a].
    PoseChoice x = s.RandomPose(s.w.RandomBody(), s.w.RandomBody(), seed % 5 != 0);
    x.r = x.b;
    const auto X_FE_F = s.X(x);
    if (!X_FE_F) continue;
    const Twist V_DCe_A = s.V(x.e, C, D, x.a);
    if (const auto V_DCf_B = s.Check(ScrewTransform(V_DCe_A, *X_FE_F), true)) {
      s.ExpectTwist(*V_DCf_B, x.f, C, D, x.b);
    }
    // The twist is at another point; it is expressed in another frame than [a].
    s.ExpectRejected(s.V(s.w.RandomFrameOtherThan(x.e), C, D, x.a), *X_FE_F, kScrewTransform);
    s.ExpectRejected(s.V(x.e, C, D, s.w.RandomFrameOtherThan(x.a)), *X_FE_F, kScrewTransform);
    // The pose is not expressed in its reference frame (quaternion backend only).
    PoseChoice y = x;
    y.r = s.w.RandomFrameOtherThan(x.b);
    if (const auto X_FE_R = s.X(y)) s.ExpectRejected(V_DCe_A, *X_FE_R, kScrewTransform);
  }
  ExpectExercised(t, true, kPinsPoints<B> || kPinsCoordinateFrame<B>, true);
}

TYPED_TEST(CoordOperations, TwistLinearOf) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int e = s.w.RandomFrame(), C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C);
    const int r = s.w.RandomFrame();
    s.ExpectLinear(LinearOf(s.V(e, C, D, r)), e, C, D, r);
    s.Counted();
  }
  // No precondition: there is no semantic rejection to check.
  ExpectExercised(t, true, false, false);
}

TYPED_TEST(CoordOperations, TwistAngularOf) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int e = s.w.RandomFrame(), C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C);
    const int r = s.w.RandomFrame();
    s.ExpectAngular(AngularOf(s.V(e, C, D, r)), C, D, r);
    s.Counted();
  }
  // No precondition: there is no semantic rejection to check.
  ExpectExercised(t, true, false, false);
}

TYPED_TEST(CoordOperations, TwistCombine) {
  Tally t;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SEED_TRACE(seed);
    Scene<TypeParam> s(seed, t);
    const int e = s.w.RandomFrame(), C = s.w.RandomBody(), D = s.w.RandomBodyOtherThan(C);
    const int r = s.w.RandomFrame();
    const LinearVelocity v_DCe_R = s.L(e, C, D, r);
    const AngularVelocity w_DC_R = s.W(C, D, r);
    if (const auto V_DCe_R = s.Check(Combine(v_DCe_R, w_DC_R), true)) {
      s.ExpectTwist(*V_DCe_R, e, C, D, r);
    }
    // Different reference bodies; different coordinate frames.
    s.ExpectRejected(v_DCe_R, s.W(C, s.w.RandomBodyOtherThan(D), r), kCombine);
    s.ExpectRejected(v_DCe_R, s.W(C, D, s.w.RandomFrameOtherThan(r)), kCombine);
  }
  ExpectExercised(t, true, false, true);
}

// ================================================================== cross-checks of the ground
// truth

// The world's relative linear velocity is the time derivative, seen from D, of the position of
// the C-fixed point at e wrt a D-fixed point: checked by integrating the absolute motion over a
// short step (central difference), so that the ground truth itself is not taken on faith.
TEST(WorldScene, LinearVelocityIsTheDerivativeSeenFromTheReferenceBody) {
  for (int seed = 1; seed <= 20; ++seed) {
    SEED_TRACE(seed);
    WorldScene w(static_cast<std::uint64_t>(seed), kFrames, kBodies);
    const int e = w.RandomFrame(), C = w.RandomBody(), D = w.RandomBodyOtherThan(C);
    const int d = w.RandomFrameOn(D);  // a frame of D: a D-fixed point and axes
    const double h = 1e-5;
    // Position at time t of the point of C that is at e at time 0, wrt d, in [d]: rigid motion
    // of each body is x(t) = Rot(w t) (x0 - o) + o + v_o t for a constant twist; use exact
    // exponentials about the world origin: x(t) = exp([w]t) x0 + (integral) v term.
    auto moved = [&](int body, const Eigen::Vector3d& x0, double t) {
      const auto& b = w.body_data(body);
      const double angle = b.w_WB_W.norm() * t;
      const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, b.w_WB_W.normalized()).toRotationMatrix();
      // Constant twist (w, v at origin): dx/dt = v + w x x. Second order Taylor is enough for h.
      return Eigen::Vector3d(R * x0 + t * b.v_WBo_W + 0.5 * t * t * b.w_WB_W.cross(b.v_WBo_W));
    };
    auto rel = [&](double t) {
      const Eigen::Vector3d x_e = moved(C, w.frame_data(e).p_WF_W, t);
      const Eigen::Vector3d x_d = moved(D, w.frame_data(d).p_WF_W, t);
      const auto& bD = w.body_data(D);
      const Eigen::Matrix3d R_D =
          Eigen::AngleAxisd(bD.w_WB_W.norm() * t, bD.w_WB_W.normalized()).toRotationMatrix();
      const Eigen::Matrix3d R_Wd = R_D * w.frame_data(d).R_WF;
      return Eigen::Vector3d(R_Wd.transpose() * (x_e - x_d));
    };
    const Eigen::Vector3d fd = (rel(h) - rel(-h)) / (2 * h);
    ExpectNear(fd, w.LinearVelocity(e, C, D, d), 1e-6);
  }
}

}  // namespace
}  // namespace semgraph::coord
