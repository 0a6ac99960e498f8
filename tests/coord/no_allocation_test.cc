// The checked operations of coord/operations.h (and their kernels) never allocate: every
// operation on every backend, accepted and rejected (semantic mismatch and representation
// constraint), run 1000 times with
//   - the global operator new/delete (all replaceable forms: plain, array, sized, aligned,
//     nothrow) replaced by counting versions, armed only around the loop, and
//   - Eigen's own heap guard (EIGEN_RUNTIME_NO_MALLOC, set_is_malloc_allowed(false)), which
//     asserts on any Eigen heap allocation (Eigen allocates with malloc, not operator new).
// The values are built before the counters are armed; nothing inside the loop formats text or
// uses gtest assertions (which may allocate): outcomes are tallied in plain integers and
// checked afterwards. Make* (validate.h, documented allocation-free) gets the same treatment, and
// so do the acceleration and wrench operations of coord/dynamics_operations.h.
#define EIGEN_RUNTIME_NO_MALLOC 1  // before any Eigen include

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <limits>
#include <new>
#include <optional>
#include <string>

#include "semgraph/coord/dynamics_operations.h"
#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/operations.h"
#include "semgraph/coord/quaternion_backend.h"
#include "support/rotation_matrix_backend.h"

// ================================================================== counting operator new/delete

namespace {
std::atomic<bool> g_armed{false};
std::atomic<long> g_allocations{0};    // while armed
std::atomic<long> g_deallocations{0};  // while armed

void* CountedAlloc(std::size_t size, std::size_t alignment) noexcept {
  if (g_armed.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (size == 0) size = 1;
  if (alignment <= alignof(std::max_align_t)) return std::malloc(size);
  const std::size_t rounded = (size + alignment - 1) / alignment * alignment;
  return std::aligned_alloc(alignment, rounded);
}
void CountedFree(void* p) noexcept {
  if (p == nullptr) return;
  if (g_armed.load(std::memory_order_relaxed)) g_deallocations.fetch_add(1);
  std::free(p);
}
void* CountedAllocOrThrow(std::size_t size, std::size_t alignment) {
  if (void* p = CountedAlloc(size, alignment)) return p;
  throw std::bad_alloc();
}
constexpr std::size_t kDefault = alignof(std::max_align_t);
std::size_t AlignOf(std::align_val_t al) { return static_cast<std::size_t>(al); }
}  // namespace

void* operator new(std::size_t n) { return CountedAllocOrThrow(n, kDefault); }
void* operator new[](std::size_t n) { return CountedAllocOrThrow(n, kDefault); }
void* operator new(std::size_t n, std::align_val_t al) {
  return CountedAllocOrThrow(n, AlignOf(al));
}
void* operator new[](std::size_t n, std::align_val_t al) {
  return CountedAllocOrThrow(n, AlignOf(al));
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  return CountedAlloc(n, kDefault);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  return CountedAlloc(n, kDefault);
}
void* operator new(std::size_t n, std::align_val_t al, const std::nothrow_t&) noexcept {
  return CountedAlloc(n, AlignOf(al));
}
void* operator new[](std::size_t n, std::align_val_t al, const std::nothrow_t&) noexcept {
  return CountedAlloc(n, AlignOf(al));
}
void operator delete(void* p) noexcept { CountedFree(p); }
void operator delete[](void* p) noexcept { CountedFree(p); }
void operator delete(void* p, std::size_t) noexcept { CountedFree(p); }
void operator delete[](void* p, std::size_t) noexcept { CountedFree(p); }
void operator delete(void* p, std::align_val_t) noexcept { CountedFree(p); }
void operator delete[](void* p, std::align_val_t) noexcept { CountedFree(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { CountedFree(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { CountedFree(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { CountedFree(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { CountedFree(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { CountedFree(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  CountedFree(p);
}

namespace semgraph::coord {
namespace {

using base::ErrorCode;
using semantics::Body;
using semantics::Frame;
using semantics::NameTable;

constexpr int kIterations = 1000;

/// Arms both guards for its lifetime.
class NoAllocationScope {
 public:
  NoAllocationScope() {
    g_allocations = 0;
    g_deallocations = 0;
    Eigen::internal::set_is_malloc_allowed(false);
    g_armed = true;
  }
  ~NoAllocationScope() {
    g_armed = false;
    Eigen::internal::set_is_malloc_allowed(true);
  }
  NoAllocationScope(const NoAllocationScope&) = delete;
  NoAllocationScope& operator=(const NoAllocationScope&) = delete;
};

/// Outcomes of one pass, tallied without allocating.
struct Outcomes {
  int ok = 0;
  int semantic = 0;        // kSemanticMismatch
  int representation = 0;  // kRepresentationConstraint
  int other = 0;           // anything else: a bug
  double checksum = 0.0;   // keeps the results observable

  template <class T>
  void Add(const Result<T>& r) {
    if (r) {
      ++ok;
      Sum(*r);
    } else if (r.error().code == ErrorCode::kSemanticMismatch) {
      ++semantic;
    } else if (r.error().code == ErrorCode::kRepresentationConstraint) {
      ++representation;
    } else {
      ++other;
    }
  }
  template <class T>
  void AddValue(const T& v) {
    ++ok;
    Sum(v);
  }
  void Sum(const Position& v) { checksum += v.value.sum(); }
  void Sum(const LinearVelocity& v) { checksum += v.value.sum(); }
  void Sum(const AngularVelocity& v) { checksum += v.value.sum(); }
  void Sum(const Twist& v) { checksum += v.linear.sum() + v.angular.sum(); }
  void Sum(const Eigen::Vector3d& v) { checksum += v.sum(); }
  void Sum(const Acceleration& v) { checksum += v.linear.sum() + v.angular.sum(); }
  void Sum(const Wrench& v) { checksum += v.force.sum() + v.moment.sum(); }
  void Sum(const Power& v) { checksum += v.value; }
  template <class B>
  void Sum(const Orientation<B>& v) {
    checksum += B::ToMatrix(v.value).sum();
  }
  template <class B>
  void Sum(const Pose<B>& v) {
    checksum += B::ToMatrix(B::RotationOf(v.value)).sum() + B::TranslationOf(v.value).sum();
  }
};

/// Every value the operations need, built (and validated) before the guards are armed.
/// Frames: a, a2 on body A; b, b2 on body B; c on body C. All orientations and poses are in
/// the form every backend holds (frame form, [r] = [b]); the same-frame operands exist only
/// for backends that can hold them.
template <class B>
struct Operands {
  NameTable names;
  Frame a{*names.Intern("a")}, a2{*names.Intern("a2")}, b{*names.Intern("b")},
      b2{*names.Intern("b2")}, c{*names.Intern("c")};
  Body A{*names.Intern("A")}, Bb{*names.Intern("B")}, C{*names.Intern("C")};

  Eigen::Quaterniond q1{Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized())};
  Eigen::Quaterniond q2{Eigen::AngleAxisd(-1.1, Eigen::Vector3d(0, 1, -1).normalized())};
  Eigen::Vector3d p1{0.5, -1.0, 2.0}, p2{-0.25, 1.5, 0.75};

  Position p_BA_B = *MakePosition({a.origin(), A, b.origin(), Bb, b.axes()}, p1);
  Position p_CB_B = *MakePosition({b.origin(), Bb, c.origin(), C, b.axes()}, p2);
  Position p_AA2_B = *MakePosition({a2.origin(), A, a.origin(), A, b.axes()}, p2);
  Position p_B2B_B = *MakePosition({b.origin(), Bb, b2.origin(), Bb, b.axes()}, p1);
  Position p_Aa_A = *MakePosition({a.origin(), A, a2.origin(), A, a.axes()}, p1);

  Orientation<B> O_BA_B = *MakeOrientation<B>({a.axes(), A, b.axes(), Bb, b.axes()}, q1);
  Orientation<B> O_CB_C = *MakeOrientation<B>({b.axes(), Bb, c.axes(), C, c.axes()}, q2);
  Orientation<B> O_AA2_A = *MakeOrientation<B>({a2.axes(), A, a.axes(), A, a.axes()}, q2);
  Orientation<B> O_B2B_B2 = *MakeOrientation<B>({b.axes(), Bb, b2.axes(), Bb, b2.axes()}, q1);
  // Operands expressed outside their reference frame (the quaternion backend only).
  std::optional<Orientation<B>> O_BA_C;  // [a] wrt [b] in [c]

  Pose<B> X_BA_B = *MakePose<B>(PoseSemantics::OfFrame(a, A, b, Bb, b.axes()), q1, p1);
  Pose<B> X_CB_C = *MakePose<B>(PoseSemantics::OfFrame(b, Bb, c, C, c.axes()), q2, p2);
  std::optional<Pose<B>> X_BA_C;  // {a} wrt {b} in [c]
  std::optional<Pose<B>> X_CB_B;  // {b} wrt {c} in [b]

  LinearVelocity v_BAa_B = *MakeLinearVelocity({a.origin(), A, Bb, b.axes()}, p1);
  LinearVelocity v_CBa_B = *MakeLinearVelocity({a.origin(), Bb, C, b.axes()}, p2);
  AngularVelocity w_BA_B = *MakeAngularVelocity({A, Bb, b.axes()}, p2);
  AngularVelocity w_CB_B = *MakeAngularVelocity({Bb, C, b.axes()}, p1);
  Twist V_BAa_B = *MakeTwist({a.origin(), A, Bb, b.axes()}, p1, p2);
  Twist V_CBa_B = *MakeTwist({a.origin(), Bb, C, b.axes()}, p2, p1);
  Twist V_BAa_A = *MakeTwist({a.origin(), A, Bb, a.axes()}, p2, p1);

  Operands() {
    if (auto o = MakeOrientation<B>({a.axes(), A, b.axes(), Bb, c.axes()}, q1)) O_BA_C = *o;
    if (auto x = MakePose<B>(PoseSemantics::OfFrame(a, A, b, Bb, c.axes()), q1, p1)) X_BA_C = *x;
    if (auto x = MakePose<B>(PoseSemantics::OfFrame(b, Bb, c, C, b.axes()), q2, p2)) X_CB_B = *x;
  }
};

/// Accelerations and wrenches (dynamics_operations.h), on the names of Operands: A moves
/// relative to B, B relative to C, all at point a in [b]; wrenches on A by B.
template <class B>
struct DynamicsOperands {
  Operands<B> o;
  Acceleration A_BA = *MakeAcceleration({o.a.origin(), o.A, o.Bb, o.b.axes()}, o.p1, o.p2);
  Acceleration A_CB = *MakeAcceleration({o.a.origin(), o.Bb, o.C, o.b.axes()}, o.p2, o.p1);
  Wrench W_AB = *MakeWrench({o.a.origin(), o.A, o.Bb, o.b.axes()}, o.p1, o.p2);
  Wrench W_AC = *MakeWrench({o.a.origin(), o.A, o.C, o.b.axes()}, o.p2, o.p1);
  Wrench W_BA = *MakeWrench({o.a.origin(), o.Bb, o.A, o.b.axes()}, o.p2, o.p1);
  Wrench W_Aa_A = *MakeWrench({o.a.origin(), o.A, o.Bb, o.a.axes()}, o.p2, o.p1);
};

/// One pass over every operation of dynamics_operations.h. Comments name the expected outcome.
template <class B>
void RunDynamics(const DynamicsOperands<B>& d, Outcomes& out) {
  const Operands<B>& o = d.o;
  out.Add(Inverse(d.A_BA, o.V_BAa_B));                         // ok
  out.Add(Inverse(d.A_BA, o.V_CBa_B));                         // semantic
  out.Add(Compose(d.A_BA, d.A_CB, o.V_BAa_B, o.w_CB_B));       // ok
  out.Add(Compose(d.A_BA, d.A_CB, o.V_CBa_B, o.w_CB_B));       // semantic
  out.Add(ChangePoint(d.A_BA, o.p_AA2_B, o.w_BA_B));           // semantic: p of a2 wrt a
  out.Add(ChangePoint(d.A_BA, Inverse(o.p_AA2_B), o.w_BA_B));  // ok
  out.Add(ChangeCoordinateFrame(d.A_BA, o.O_CB_C));            // ok
  out.Add(ChangeCoordinateFrame(d.A_BA, o.O_BA_B));            // semantic
  out.Add(ChangePoint(d.W_AB, Inverse(o.p_AA2_B)));            // ok
  out.Add(ChangePoint(d.W_AB, o.p_CB_B));                      // semantic
  out.Add(ChangeCoordinateFrame(d.W_AB, o.O_CB_C));            // ok
  out.Add(ScrewTransform(d.W_Aa_A, o.X_BA_B));                 // ok
  out.Add(ScrewTransform(d.W_AB, o.X_BA_B));                   // semantic
  out.Add(Reaction(d.W_AB));                                   // ok
  out.Add(Reaction(*Sum(d.W_AB, d.W_AC)));                     // semantic: by several
  out.Add(Sum(d.W_AB, d.W_AC));                                // ok
  out.Add(Sum(d.W_AB, d.W_BA));                                // semantic
  out.Add(PowerOf(d.W_AB, o.V_BAa_B));                         // ok
  out.Add(PowerOf(d.W_BA, o.V_BAa_B));                         // semantic
  out.Sum(kernels::ShiftAcceleration(o.p1, o.p2, o.p1, o.p2));
  out.Sum(kernels::ComposeAccelerations(o.p1, o.p2, o.p2, o.p1, o.p1, o.p2, o.p1).linear);
  out.Sum(kernels::InvertAcceleration(o.p1, o.p2, o.p1, o.p2).linear);
  out.Sum(kernels::ShiftMoment(o.p1, o.p2, o.p1));
}

/// One pass over every operation of operations.h. Comments name the expected outcome.
template <class B>
void RunAll(const Operands<B>& o, Outcomes& out) {
  // ---------------------------------------------------------------- Position
  out.AddValue(Inverse(o.p_BA_B));
  out.Add(Compose(o.p_BA_B, o.p_CB_B));                 // ok
  out.Add(Compose(o.p_CB_B, o.p_CB_B));                 // semantic
  out.Add(ChangePoint(o.p_BA_B, o.p_AA2_B));            // ok
  out.Add(ChangePoint(o.p_BA_B, o.p_CB_B));             // semantic
  out.Add(ChangeRefPoint(o.p_BA_B, o.p_B2B_B));         // ok
  out.Add(ChangeRefPoint(o.p_BA_B, o.p_AA2_B));         // semantic
  out.Add(ChangeCoordinateFrame(o.p_BA_B, o.O_CB_C));   // ok: [b] -> [c]
  out.Add(ChangeCoordinateFrame(o.p_BA_B, o.O_AA2_A));  // semantic
  // ---------------------------------------------------------------- Orientation
  out.Add(Inverse(o.O_BA_B));                                // quaternion ok, others representation
  out.Add(InverseInNewRef(o.O_BA_B));                        // ok
  out.Add(Compose(o.O_BA_B, o.O_CB_C));                      // ok (chain)
  out.Add(Compose(o.O_CB_C, o.O_BA_B));                      // semantic
  out.Add(ChangeOrientationFrame(o.O_BA_B, o.O_AA2_A));      // ok
  out.Add(ChangeOrientationFrame(o.O_BA_B, o.O_CB_C));       // semantic
  out.Add(ChangeRefOrientationFrame(o.O_BA_B, o.O_B2B_B2));  // ok
  out.Add(ChangeRefOrientationFrame(o.O_BA_B, o.O_AA2_A));   // semantic
  out.Add(ChangeCoordinateFrame(o.O_BA_B, o.O_CB_C));        // quaternion ok, others representation
  out.Add(ChangeCoordinateFrame(o.O_BA_B, o.O_AA2_A));       // semantic
  if (o.O_BA_C) {
    out.Add(Compose(*o.O_BA_C, o.O_CB_C));  // ok (same frame [c])
    out.Add(InverseInNewRef(*o.O_BA_C));    // semantic
  }
  // ---------------------------------------------------------------- Pose
  out.Add(Inverse(o.X_BA_B));                            // quaternion ok, others representation
  out.Add(InverseInNewRef(o.X_BA_B));                    // ok
  out.Add(Compose(o.X_BA_B, o.X_CB_C));                  // ok (chain)
  out.Add(Compose(o.X_CB_C, o.X_BA_B));                  // semantic
  out.Add(ChangePoint(o.X_BA_B, o.p_AA2_B));             // homogeneous representation, others ok
  out.Add(ChangePoint(o.X_BA_B, o.p_CB_B));              // semantic
  out.Add(ChangeRefPoint(o.X_BA_B, o.p_B2B_B));          // homogeneous representation, others ok
  out.Add(ChangeRefPoint(o.X_BA_B, o.p_AA2_B));          // semantic
  out.Add(ChangeOrientationFrame(o.X_BA_B, o.O_AA2_A));  // homogeneous representation, others ok
  out.Add(ChangeOrientationFrame(o.X_BA_B, o.O_CB_C));   // semantic
  out.Add(ChangeRefOrientationFrame(o.X_BA_B, o.O_B2B_B2));  // homogeneous representation
  out.Add(ChangeRefOrientationFrame(o.X_BA_B, o.O_AA2_A));   // semantic
  out.Add(ChangeCoordinateFrame(o.X_BA_B, o.O_CB_C));        // quaternion ok, others representation
  out.Add(ChangeCoordinateFrame(o.X_BA_B, o.O_AA2_A));       // semantic
  out.AddValue(PositionOf(o.X_BA_B));
  out.Add(OrientationOf(o.X_BA_B));       // ok
  out.Add(Combine(o.p_BA_B, o.O_BA_B));   // ok
  out.Add(Combine(o.p_AA2_B, o.O_BA_B));  // semantic (ref bodies differ)
  if (o.X_BA_C && o.X_CB_B) {
    out.Add(Compose(o.X_BA_B, *o.X_CB_B));   // ok (same frame [b])
    out.Add(Compose(*o.X_BA_C, *o.X_CB_B));  // semantic (coordinate forms)
  }
  // ---------------------------------------------------------------- Linear / angular velocity
  out.AddValue(Inverse(o.v_BAa_B));
  out.Add(Compose(o.v_BAa_B, o.v_CBa_B));                // ok
  out.Add(Compose(o.v_CBa_B, o.v_BAa_B));                // semantic
  out.Add(ChangeCoordinateFrame(o.v_BAa_B, o.O_CB_C));   // ok
  out.Add(ChangeCoordinateFrame(o.v_BAa_B, o.O_AA2_A));  // semantic
  out.AddValue(Inverse(o.w_BA_B));
  out.Add(Compose(o.w_BA_B, o.w_CB_B));                 // ok
  out.Add(Compose(o.w_CB_B, o.w_BA_B));                 // semantic
  out.Add(ChangeCoordinateFrame(o.w_BA_B, o.O_CB_C));   // ok
  out.Add(ChangeCoordinateFrame(o.w_BA_B, o.O_AA2_A));  // semantic
  // ---------------------------------------------------------------- Twist
  out.AddValue(Inverse(o.V_BAa_B));
  out.Add(Compose(o.V_BAa_B, o.V_CBa_B));                // ok
  out.Add(Compose(o.V_CBa_B, o.V_BAa_B));                // semantic
  out.Add(ChangePoint(o.V_BAa_B, o.p_BA_B));             // ok: a -> b
  out.Add(ChangePoint(o.V_BAa_B, o.p_CB_B));             // semantic
  out.Add(ChangeCoordinateFrame(o.V_BAa_B, o.O_CB_C));   // ok
  out.Add(ChangeCoordinateFrame(o.V_BAa_B, o.O_AA2_A));  // semantic
  out.Add(ScrewTransform(o.V_BAa_A, o.X_BA_B));          // ok
  out.Add(ScrewTransform(o.V_BAa_B, o.X_BA_B));          // semantic
  out.AddValue(LinearOf(o.V_BAa_B));
  out.AddValue(AngularOf(o.V_BAa_B));
  out.Add(Combine(o.v_BAa_B, o.w_BA_B));  // ok
  out.Add(Combine(o.v_BAa_B, o.w_CB_B));  // semantic
  // ---------------------------------------------------------------- kernels
  out.Sum(B::TranslationOf(kernels::ComposeSameFrame<B>(o.X_BA_B.value, o.X_CB_C.value)));
  out.Sum(B::TranslationOf(kernels::InverseSameFrame<B>(o.X_BA_B.value)));
  out.Sum(B::TranslationOf(kernels::Reexpress<B>(o.X_BA_B.value, o.O_CB_C.value)));
  out.Sum(kernels::ShiftLinear(o.V_BAa_B.linear, o.V_BAa_B.angular, o.p_BA_B.value));
}

template <class B>
class NoAllocation : public ::testing::Test {};
struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};
using Backends =
    ::testing::Types<QuaternionBackend, HomogeneousBackend, testing::RotationMatrixBackend>;
TYPED_TEST_SUITE(NoAllocation, Backends, BackendName);

TYPED_TEST(NoAllocation, EveryOperationAcceptedOrRejected) {
  using B = TypeParam;
  const Operands<B> operands;
  Outcomes first;  // one pass before arming: what every armed pass must reproduce
  RunAll(operands, first);
  ASSERT_EQ(first.other, 0);
  ASSERT_GT(first.ok, 0);
  ASSERT_GT(first.semantic, 0);
  // Only the matrix backends refuse results ([r] = [b] on orientations and poses).
  if (B::kConstraints.coordinate_frame_is_ref_orientation) {
    ASSERT_GT(first.representation, 0);
  } else {
    ASSERT_EQ(first.representation, 0);
  }

  Outcomes armed;
  long allocations = 0, deallocations = 0;
  {
    NoAllocationScope guard;
    for (int i = 0; i < kIterations; ++i) RunAll(operands, armed);
    allocations = g_allocations.load();
    deallocations = g_deallocations.load();
  }
  EXPECT_EQ(allocations, 0) << "operator new called inside the loop";
  EXPECT_EQ(deallocations, 0) << "operator delete called inside the loop";
  EXPECT_EQ(armed.ok, kIterations * first.ok);
  EXPECT_EQ(armed.semantic, kIterations * first.semantic);
  EXPECT_EQ(armed.representation, kIterations * first.representation);
  EXPECT_EQ(armed.other, 0);
  EXPECT_NEAR(armed.checksum, kIterations * first.checksum, 1e-6 * kIterations);
}

// Make* are documented allocation-free too (validate.h); the rejections included.
TYPED_TEST(NoAllocation, MakeAcceptedOrRejected) {
  using B = TypeParam;
  const Operands<B> o;
  const PoseSemantics edge = PoseSemantics::OfFrame(o.a, o.A, o.b, o.Bb, o.b.axes());
  const PoseSemantics off = PoseSemantics::OfFrame(o.a, o.A, o.b, o.Bb, o.c.axes());
  const OrientationSemantics edge_o{o.a.axes(), o.A, o.b.axes(), o.Bb, o.b.axes()};
  const Eigen::Matrix3d R = o.q1.toRotationMatrix();
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = R;
  T.topRightCorner<3, 1>() = o.p1;
  const Eigen::Quaterniond q_bad(2, 0, 0, 0);
  const Eigen::Vector3d nan_v(0, std::numeric_limits<double>::quiet_NaN(), 0);

  Outcomes armed;
  int invalid = 0;
  long allocations = 0;
  {
    NoAllocationScope guard;
    for (int i = 0; i < kIterations; ++i) {
      armed.Add(MakePose<B>(edge, o.q1, o.p1));
      armed.Add(MakePose<B>(edge, R, o.p1));
      armed.Add(MakePose<B>(edge, T));
      armed.Add(MakePose<B>(off, o.q1, o.p1));  // representation for matrix backends
      armed.Add(MakeOrientation<B>(edge_o, o.q2));
      armed.Add(MakeOrientation<B>(edge_o, R));
      armed.Add(MakePosition(o.p_BA_B.semantics, o.p2));
      armed.Add(MakeTwist(o.V_BAa_B.semantics, o.p1, o.p2));
      invalid += !MakePose<B>(edge, q_bad, o.p1).has_value();
      invalid += !MakePose<B>(edge, o.q1, nan_v).has_value();
      invalid += !MakeOrientation<B>(edge_o, Eigen::Matrix3d(-R)).has_value();
    }
    allocations = g_allocations.load();
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(invalid, 3 * kIterations);
  EXPECT_EQ(armed.other, 0);
  EXPECT_EQ(armed.ok + armed.representation, 8 * kIterations);
}

TYPED_TEST(NoAllocation, EveryDynamicsOperationAcceptedOrRejected) {
  using B = TypeParam;
  const DynamicsOperands<B> operands;
  Outcomes first;
  RunDynamics(operands, first);
  ASSERT_EQ(first.ok, 10);
  ASSERT_EQ(first.semantic, 9);
  ASSERT_EQ(first.representation + first.other, 0);
  Outcomes armed;
  long allocations = 0, deallocations = 0;
  int invalid = 0;
  const Eigen::Vector3d nan_v(0, std::numeric_limits<double>::quiet_NaN(), 0);
  {
    NoAllocationScope guard;
    for (int i = 0; i < kIterations; ++i) {
      RunDynamics(operands, armed);
      invalid += !MakeAcceleration(operands.A_BA.semantics, nan_v, nan_v).has_value();
      invalid += !MakeWrench(operands.W_AB.semantics, operands.o.p1, nan_v).has_value();
    }
    allocations = g_allocations.load();
    deallocations = g_deallocations.load();
  }
  EXPECT_EQ(allocations, 0) << "operator new called inside the loop";
  EXPECT_EQ(deallocations, 0) << "operator delete called inside the loop";
  EXPECT_EQ(invalid, 2 * kIterations);
  EXPECT_EQ(armed.ok, kIterations * first.ok);
  EXPECT_EQ(armed.semantic, kIterations * first.semantic);
  EXPECT_NEAR(armed.checksum, kIterations * first.checksum, 1e-6 * kIterations);
}

// The guards work: an allocation inside the scope is seen by both.
TEST(NoAllocationGuard, CountsOperatorNew) {
  long allocations = 0;
  {
    NoAllocationScope guard;
    int* volatile escaped = new int(7);  // volatile: clang may elide `delete new int(7)`
    delete escaped;
    auto* aligned = new (std::align_val_t(64)) double[4];
    ::operator delete[](aligned, std::align_val_t(64));
    void* nothrow = ::operator new(16, std::nothrow);
    ::operator delete(nothrow);
    allocations = g_allocations.load();
  }
  EXPECT_EQ(allocations, 3);
  EXPECT_TRUE(Eigen::internal::is_malloc_allowed());  // restored after the scope
}

TEST(NoAllocationGuard, EigenHeapGuardIsArmed) {
  {
    NoAllocationScope guard;
    EXPECT_FALSE(Eigen::internal::is_malloc_allowed());
  }
#ifndef NDEBUG  // eigen_assert is compiled out with NDEBUG
  EXPECT_DEATH(
      {
        NoAllocationScope guard;
        Eigen::MatrixXd m(8, 8);
        m.setZero();
      },
      "heap allocation is forbidden");
#endif
}

}  // namespace
}  // namespace semgraph::coord
