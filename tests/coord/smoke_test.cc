#include <gtest/gtest.h>

#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/operations.h"
#include "semgraph/coord/quaternion_backend.h"
#include "semgraph/semantics/describe.h"
#include "support/rotation_matrix_backend.h"

namespace semgraph::coord {
namespace {
using semantics::Body;
using semantics::Frame;
using semantics::NameTable;

template <class B>
void Exercise() {
  NameTable names;
  const Frame a(*names.Intern("a")), b(*names.Intern("b")), c(*names.Intern("c"));
  const Body A(*names.Intern("A")), Bb(*names.Intern("B")), C(*names.Intern("C"));
  auto X_BA = MakePose<B>(PoseSemantics::OfFrame(a, A, b, Bb, b.axes()),
                          Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())),
                          Eigen::Vector3d(1, 2, 3));
  auto X_CB = MakePose<B>(PoseSemantics::OfFrame(b, Bb, c, C, c.axes()),
                          Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX())),
                          Eigen::Vector3d(-1, 0, 2));
  ASSERT_TRUE(X_BA && X_CB);
  auto X_CA = Compose(*X_BA, *X_CB);
  ASSERT_TRUE(X_CA) << Describe(X_CA.error(), names);
  auto bad = Compose(*X_CB, *X_CB);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().code, semantics::ErrorCode::kSemanticMismatch);
  auto inv = Inverse(*X_BA);
  Twist t{{a.origin(), A, Bb, a.axes()}, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, 1)};
  auto s = ScrewTransform(t, *X_BA);
  ASSERT_TRUE(s) << Describe(s.error(), names);
  (void)inv;
}

TEST(CoordSmoke, QuaternionCompiles) { Exercise<QuaternionBackend>(); }
TEST(CoordSmoke, HomogeneousCompiles) { Exercise<HomogeneousBackend>(); }
TEST(CoordSmoke, RotationMatrixCompiles) { Exercise<testing::RotationMatrixBackend>(); }
}  // namespace
}  // namespace semgraph::coord
