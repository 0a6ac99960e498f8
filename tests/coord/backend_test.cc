// B::Identity() of every backend (backend.h): the identity rotation and a zero translation, as
// the matrices written here say, and neutral for the chain operations bit for bit (products
// with exact ones and zeros round nothing).
#include "semgraph/coord/backend.h"

#include <gtest/gtest.h>

#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/quaternion_backend.h"
#include "support/rotation_matrix_backend.h"

namespace semgraph::coord {
namespace {

template <class B>
class BackendIdentityTest : public ::testing::Test {};

using Backends = ::testing::Types<QuaternionBackend, HomogeneousBackend,
                                  semgraph::testing::RotationMatrixBackend>;
TYPED_TEST_SUITE(BackendIdentityTest, Backends);

template <class B>
void ExpectSamePose(const typename B::PoseCoords& X, const typename B::PoseCoords& Y) {
  EXPECT_EQ(B::ToMatrix(B::RotationOf(X)), B::ToMatrix(B::RotationOf(Y)));
  EXPECT_EQ(B::TranslationOf(X), B::TranslationOf(Y));
}

TYPED_TEST(BackendIdentityTest, IsTheIdentityAndNeutralInChains) {
  using B = TypeParam;
  const typename B::PoseCoords I = B::Identity();
  const Eigen::Matrix3d one{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  EXPECT_EQ(B::ToMatrix(B::RotationOf(I)), one);
  EXPECT_EQ(B::TranslationOf(I), Eigen::Vector3d(0, 0, 0));
  const Eigen::Quaterniond q = Eigen::Quaterniond(0.5, -0.5, 0.5, 0.5);  // unit: 4 * 0.25
  const typename B::PoseCoords X =
      B::MakePose(B::FromQuaternion(q), Eigen::Vector3d(1.5, -2, 0.25));
  ExpectSamePose<B>(B::ComposeChain(X, I), X);
  ExpectSamePose<B>(B::ComposeChain(I, X), X);
  ExpectSamePose<B>(B::InvertChain(I), I);
  static_assert(noexcept(B::Identity()));
}

}  // namespace
}  // namespace semgraph::coord
