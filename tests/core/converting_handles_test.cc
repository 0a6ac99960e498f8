// Converting handles (core/converting_handles.h, core/src/converting_handles.cc): values given
// in another form than the edge's, converted on the real-time path.
//
// Scene (both backends): a base {b}|B; a camera {c}|C mounted on it (pose of c wrt b, a turn
// about a tilted axis), with a second frame {c2}|C; an object {o}|O seen by the camera (pose of
// o wrt c), with a second frame {o2}|O; the object's twist relative to the camera. The
// expected edge values are computed here by hand with Eigen from the numbers the test chose
// (R_BC, p_BC, p_CC2, p_OO2), never through semgraph; and each converted update must equal
// what AddPose / AddTwist store for the same input on a twin graph (up to the association of
// the products: the handle composes its flattened chains top-down, the add walks the forest).
// Then: the build-time errors, kQueryInvalidated after an edge of the conversion is removed,
// invalid inputs, and no allocation on the real-time path (tests/support/alloc_counter.h).
//
// Legend: R_XY rotation of [y] in [x]; p_XY position of {y}'s origin wrt {x}'s, in [x].
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/alloc_counter.h"

namespace semgraph::core {
namespace {

using base::ErrorCode;
using Eigen::AngleAxisd;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

const Quaterniond q_BC(AngleAxisd(0.7, Vector3d(1, 2, -0.5).normalized()));
const Vector3d p_BC(0.4, -0.2, 1.1);
const Vector3d p_CC2(0.05, 0.1, -0.02);
const Quaterniond q_CO(AngleAxisd(-1.2, Vector3d(0.3, -1, 0.4).normalized()));
const Vector3d p_CO(0.2, 0.3, 1.5);
const Vector3d p_OO2(-0.1, 0.02, 0.3);

template <class G>
void Build(G& g) {
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"), q_BC, p_BC));
  ASSERT_TRUE(
      g.AddPose(PoseSpec::Of("c2", "C").RelativeTo("c", "C"), Quaterniond::Identity(), p_CC2));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("o", "O").RelativeTo("c", "C"), q_CO, p_CO));
  ASSERT_TRUE(
      g.AddPose(PoseSpec::Of("o2", "O").RelativeTo("o", "O"), Quaterniond::Identity(), p_OO2));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("o").RelativeTo("C").ExpressedIn("o"), Vector3d(0.1, 0, 0),
                         Vector3d::Zero()));
}

template <class B>
Matrix3d RotationOf(const SceneGraph<B>& g, const char* frame) {
  return B::ToMatrix(B::RotationOf(g.pose_value(g.FindFrame(frame))));
}
template <class B>
Vector3d TranslationOf(const SceneGraph<B>& g, const char* frame) {
  return B::TranslationOf(g.pose_value(g.FindFrame(frame)));
}

template <class B>
class ConvertingHandles : public ::testing::Test {
 protected:
  void SetUp() override {
    Build(graph_);
    Build(twin_);
  }
  SceneGraph<B> graph_, twin_;
};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(ConvertingHandles, Backends);

// The camera measures the object's velocity in its own axes: v_CO_C, w_CO_C. The edge stores
// them in [o]: v_O = R_OC v_C = R_CO^T v_C.
TYPED_TEST(ConvertingHandles, TwistInTheCameraFrameIsRotatedIntoTheHeadFrame) {
  auto& g = this->graph_;
  auto handle = g.FindTwistEdge("o", "C", "c");
  ASSERT_TRUE(handle) << handle.error().message;
  EXPECT_GT(handle->num_pose_edges(), 0u);
  const Vector3d v_C(0.3, -0.2, 0.05), w_C(0.01, 0.4, -0.3);
  ASSERT_EQ(g.SetTwist(*handle, v_C, w_C), ErrorCode::kOk);
  const auto V = g.twist_value(g.FindFrame("o"));
  ASSERT_TRUE(V);
  const Matrix3d R_OC = q_CO.toRotationMatrix().transpose();
  EXPECT_LT((V->linear - R_OC * v_C).norm(), 1e-15);
  EXPECT_LT((V->angular - R_OC * w_C).norm(), 1e-15);
  // The same as AddTwist in [c].
  ASSERT_TRUE(this->twin_.AddTwist(TwistSpec::Of("o").RelativeTo("C").ExpressedIn("c"), v_C, w_C));
  const auto V_add = this->twin_.twist_value(this->twin_.FindFrame("o"));
  EXPECT_LT((V->linear - V_add->linear).norm(), 1e-15);
  EXPECT_LT((V->angular - V_add->angular).norm(), 1e-15);
  // From a frame of another body of the tree: [b], through the camera mount.
  auto from_base = g.FindTwistEdge("o", "C", "b");
  ASSERT_TRUE(from_base);
  ASSERT_EQ(g.SetTwist(*from_base, v_C, w_C), ErrorCode::kOk);
  const Matrix3d R_OB = (q_BC * q_CO).toRotationMatrix().transpose();
  EXPECT_LT((g.twist_value(g.FindFrame("o"))->linear - R_OB * v_C).norm(), 1e-15);
  // In the head's own frame it is SetTwist itself.
  auto own = g.FindTwistEdge("o", "C", "o");
  ASSERT_TRUE(own);
  EXPECT_EQ(own->num_pose_edges(), 0u);
  ASSERT_EQ(g.SetTwist(*own, v_C, w_C), ErrorCode::kOk);
  EXPECT_EQ(g.twist_value(g.FindFrame("o"))->linear, v_C);
}

// With a covariance of (v, w) in [b] (angular first, as a user may give it): the edge stores
// diag(R_OB, R_OB) S diag(R_OB, R_OB)^T in linear-first order (by hand), the same as AddTwist
// with that covariance in [b] stores, allocation-free; a bad covariance or a convention (a
// twist has none) writes nothing.
TYPED_TEST(ConvertingHandles, TwistCovarianceInAnotherFrameIsRotatedWithTheValue) {
  auto& g = this->graph_;
  auto handle = g.FindTwistEdge("o", "C", "b");
  ASSERT_TRUE(handle) << handle.error().message;
  const Vector3d v_B(0.3, -0.2, 0.05), w_B(0.01, 0.4, -0.3);
  Covariance6 S_angular_first = Covariance6::Identity() * 1e-4;
  S_angular_first(0, 0) = 9e-4;  // about [b]'s x
  S_angular_first(1, 4) = 2e-5;  // angular y with linear y
  S_angular_first(4, 1) = 2e-5;
  const CovarianceInput input{&S_angular_first, CovarianceOrder::kAngularLinear};
  std::size_t allocations = 0;
  {
    semgraph::testing::CountAllocations counting;
    EXPECT_EQ(g.SetTwist(*handle, v_B, w_B, input), ErrorCode::kOk);
    allocations = counting.count();
  }
  EXPECT_EQ(allocations, 0u);
  // By hand: reorder to (linear, angular), then rotate both halves by R_OB.
  Covariance6 S_B;
  S_B << S_angular_first.bottomRightCorner<3, 3>(), S_angular_first.bottomLeftCorner<3, 3>(),
      S_angular_first.topRightCorner<3, 3>(), S_angular_first.topLeftCorner<3, 3>();
  const Matrix3d R_OB = (q_BC * q_CO).toRotationMatrix().transpose();
  Covariance6 J = Covariance6::Zero();
  J.topLeftCorner<3, 3>() = R_OB;
  J.bottomRightCorner<3, 3>() = R_OB;
  const Covariance6 S_O = J * S_B * J.transpose();
  EXPECT_LT((g.twist_covariance(g.FindFrame("o")) - S_O).norm(), 1e-15);
  EXPECT_LT((g.twist_value(g.FindFrame("o"))->linear - R_OB * v_B).norm(), 1e-15);
  // The same as AddTwist in [b] with that covariance.
  ASSERT_TRUE(
      this->twin_.AddTwist(TwistSpec::Of("o").RelativeTo("C").ExpressedIn("b"), v_B, w_B, input));
  EXPECT_LT((g.twist_covariance(g.FindFrame("o")) -
             this->twin_.twist_covariance(this->twin_.FindFrame("o")))
                .norm(),
            1e-15);
  // Refused, nothing written.
  const std::string before = Dump(g);
  Covariance6 bad = S_B;
  bad(0, 1) = 1.0;
  EXPECT_EQ(g.SetTwist(*handle, 2 * v_B, w_B, CovarianceInput{&bad}),
            ErrorCode::kInvalidCovariance);
  EXPECT_EQ(g.SetTwist(*handle, 2 * v_B, w_B,
                       CovarianceInput{&S_B, CovarianceOrder::kLinearAngular,
                                       PoseCovarianceConvention::kBody}),
            ErrorCode::kInvalidCovariance);
  EXPECT_EQ(g.SetTwist(*handle, Vector3d(NAN, 0, 0), w_B, CovarianceInput{&S_B}),
            ErrorCode::kInvalidNumber);
  EXPECT_EQ(Dump(g), before);
  // Without one: the edge is exact again.
  ASSERT_EQ(g.SetTwist(*handle, v_B, w_B, CovarianceInput{}), ErrorCode::kOk);
  EXPECT_TRUE(g.twist_covariance(g.FindFrame("o")).isZero(0.0));
}

// The same pose handle with a covariance of the given pose (angular first): stored as AddPose
// stores it for the same input (the twin), and asked back in the handle's form (the only
// uncertain edge: the query's Jacobian inverts the conversion's) it is the given covariance,
// reordered by hand. Allocation-free; a bad covariance, a body convention (the handle's form is
// not the edge form: refused as AddPose refuses it) or a bad rotation writes nothing.
TEST(ConvertingHandlesCovariance, PoseCovarianceInAnotherFormIsConvertedAsAddPoseConvertsIt) {
  SceneGraph<coord::QuaternionBackend> g, twin;
  Build(g);
  Build(twin);
  const PoseSpec spec =
      PoseSpec::Of("o").RelativeTo("c").RelativeToPoint("c2").AtPoint("o2").ExpressedIn("b");
  auto handle = g.FindPoseEdge(spec);
  ASSERT_TRUE(handle) << handle.error().message;
  const Quaterniond M(AngleAxisd(0.9, Vector3d(-0.2, 0.5, 1).normalized()));
  const Vector3d p(0.7, -0.4, 0.25);
  Covariance6 S_given = Covariance6::Identity() * 1e-4;  // angular first
  S_given(0, 0) = 4e-4;
  S_given(2, 4) = S_given(4, 2) = 3e-5;
  const CovarianceInput input{&S_given, CovarianceOrder::kAngularLinear};
  std::size_t allocations = 0;
  {
    semgraph::testing::CountAllocations counting;
    EXPECT_EQ(g.SetPose(*handle, M, p, input), ErrorCode::kOk);
    allocations = counting.count();
  }
  EXPECT_EQ(allocations, 0u);
  auto added = twin.AddPose(spec, M, p, input);
  ASSERT_TRUE(added) << added.error().message;
  EXPECT_LT(
      (g.pose_covariance(g.FindFrame("o")) - twin.pose_covariance(twin.FindFrame("o"))).norm(),
      1e-15);
  EXPECT_FALSE(g.pose_covariance(g.FindFrame("o")).isZero(0.0));
  Covariance6 S_coordinates;  // linear first
  S_coordinates << S_given.bottomRightCorner<3, 3>(), S_given.bottomLeftCorner<3, 3>(),
      S_given.topRightCorner<3, 3>(), S_given.topLeftCorner<3, 3>();
  const auto back = g.GetPoseWithCovariance(spec);
  ASSERT_TRUE(back);
  EXPECT_LT((back->covariance - S_coordinates).norm(), 1e-12 * S_coordinates.norm())
      << back->covariance << "\n\n"
      << S_coordinates;
  // Refused, nothing written.
  const std::string before = Dump(g);
  Covariance6 bad = S_given;
  bad(0, 0) = -1.0;
  EXPECT_EQ(g.SetPose(*handle, M, 2 * p, CovarianceInput{&bad}), ErrorCode::kInvalidCovariance);
  EXPECT_EQ(g.SetPose(*handle, M, 2 * p,
                      CovarianceInput{&S_given, CovarianceOrder::kAngularLinear,
                                      PoseCovarianceConvention::kBody}),
            ErrorCode::kInvalidCovariance);
  EXPECT_EQ(g.SetPose(*handle, Quaterniond(0, 0, 0, 0), p, input), ErrorCode::kInvalidRotation);
  EXPECT_EQ(Dump(g), before);
}

// PoseCoord((o2,[o])|O, (c2,[c])|C, [b]): the orientation operator carrying [c] onto [o]
// expressed in [b], and the position of o2 wrt c2 in [b]. By hand:
//   R_CO = R_BC^T M R_BC,  p_CO = R_BC^T p + p_CC2 - R_CO p_OO2.
TYPED_TEST(ConvertingHandles, PoseGivenAtOtherPointsInAThirdFrameIsStoredInEdgeForm) {
  using B = TypeParam;
  auto& g = this->graph_;
  const PoseSpec spec =
      PoseSpec::Of("o").RelativeTo("c").RelativeToPoint("c2").AtPoint("o2").ExpressedIn("b");
  auto handle = g.FindPoseEdge(spec);
  if constexpr (std::is_same_v<B, coord::HomogeneousBackend>) {
    // The homogeneous representation holds only edge forms.
    ASSERT_FALSE(handle);
    EXPECT_EQ(handle.error().code, ErrorCode::kRepresentationConstraint);
    EXPECT_EQ(
        handle.error().message.rfind("handle of the pose of (o2,[o]) wrt (c2,[c]) in [b] rejected "
                                     "(representation_constraint): ",
                                     0),
        0u)
        << handle.error().message;
    return;
  } else {
    ASSERT_TRUE(handle) << handle.error().message;
    const Quaterniond M(AngleAxisd(0.9, Vector3d(-0.2, 0.5, 1).normalized()));
    const Vector3d p(0.7, -0.4, 0.25);
    ASSERT_EQ(g.SetPose(*handle, M, p), ErrorCode::kOk);
    const Matrix3d R_BC = q_BC.toRotationMatrix();
    const Matrix3d R_CO = R_BC.transpose() * M.toRotationMatrix() * R_BC;
    const Vector3d p_expected = R_BC.transpose() * p + p_CC2 - R_CO * p_OO2;
    EXPECT_LT((RotationOf(g, "o") - R_CO).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_LT((TranslationOf(g, "o") - p_expected).norm(), 1e-15);
    // The same as AddPose with that spec, and the matrix overload the same as the quaternion one.
    ASSERT_TRUE(this->twin_.AddPose(spec, M, p));
    EXPECT_LT((RotationOf(g, "o") - RotationOf(this->twin_, "o")).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_LT((TranslationOf(g, "o") - TranslationOf(this->twin_, "o")).norm(), 1e-15);
    ASSERT_EQ(g.SetPose(*handle, Matrix3d(M.toRotationMatrix()), p), ErrorCode::kOk);
    EXPECT_LT((TranslationOf(g, "o") - p_expected).norm(), 1e-15);
    // Nothing else changed: the other edges keep their values.
    EXPECT_EQ(TranslationOf(g, "c"), p_BC);
  }
}

TYPED_TEST(ConvertingHandles, EdgeFormSpecIsThePlainHandle) {
  auto& g = this->graph_;
  auto handle = g.FindPoseEdge(PoseSpec::Of("o").RelativeTo("c"));
  ASSERT_TRUE(handle) << handle.error().message;
  EXPECT_EQ(handle->num_pose_edges(), 0u);
  EXPECT_EQ(handle->edge(), *g.FindPoseEdge("o", "c"));
  const Quaterniond q(AngleAxisd(0.2, Vector3d::UnitZ()));
  ASSERT_EQ(g.SetPose(*handle, q, Vector3d(1, 2, 3)), ErrorCode::kOk);
  EXPECT_EQ(TranslationOf(g, "o"), Vector3d(1, 2, 3));
  EXPECT_LT((RotationOf(g, "o") - q.toRotationMatrix()).cwiseAbs().maxCoeff(), 1e-15);
}

TYPED_TEST(ConvertingHandles, BuildTimeErrorsNameWhatIsWrongAndChangeNothing) {
  auto& g = this->graph_;
  const std::string before = Dump(g);
  // [o] hangs below the edge c -> o itself: the conversion would read the value being set.
  auto below = g.FindPoseEdge(PoseSpec::Of("o").RelativeTo("c").ExpressedIn("o2"));
  ASSERT_FALSE(below);
  if constexpr (std::is_same_v<TypeParam, coord::QuaternionBackend>) {
    EXPECT_EQ(below.error().code, ErrorCode::kPoseNotConvertible);
    EXPECT_EQ(below.error().message,
              "handle of the pose of {o} wrt {c} in [o2] rejected (pose_not_convertible): the "
              "coordinate frame "
              "{o2}|O lies below the edge {c}|C -> {o}|O itself, so converting from it would read "
              "the value being "
              "set");
  }
  auto unknown = g.FindPoseEdge(PoseSpec::Of("o").RelativeTo("c").ExpressedIn("nowhere"));
  ASSERT_FALSE(unknown);
  EXPECT_EQ(unknown.error().message,
            "handle of the pose of {o} wrt {c} in [nowhere] rejected (unknown_frame): the "
            "coordinate frame names "
            "frame {nowhere}, which does not exist");
  auto no_edge = g.FindPoseEdge(PoseSpec::Of("o").RelativeTo("b"));
  ASSERT_FALSE(no_edge);
  EXPECT_EQ(no_edge.error().code, ErrorCode::kNoSuchEdge);
  auto constant = g.FindPoseEdge(PoseSpec::Of("c2").RelativeTo("c"));
  ASSERT_FALSE(constant);
  EXPECT_EQ(constant.error().code, ErrorCode::kConstantPoseChange);
  // Twists: the frame must be in the head's pose tree, and exist.
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("x", "X").RelativeTo("y", "Y"), Quaterniond::Identity(),
                        Vector3d::Zero()));
  const std::string with_xy = Dump(g);
  auto apart = g.FindTwistEdge("o", "C", "x");
  ASSERT_FALSE(apart);
  EXPECT_EQ(apart.error().message,
            "handle of the twist of o wrt C in [x] rejected (twist_not_convertible): coordinate "
            "frame [x] must be a "
            "frame in the pose tree of {o}");
  auto missing = g.FindTwistEdge("o", "C", "nowhere");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().code, ErrorCode::kUnknownFrame);
  auto no_twist = g.FindTwistEdge("c", "B", "b");
  ASSERT_FALSE(no_twist);
  EXPECT_EQ(no_twist.error().code, ErrorCode::kNoSuchEdge);
  EXPECT_EQ(Dump(g), with_xy);
  EXPECT_NE(before, with_xy);
}

TYPED_TEST(ConvertingHandles, RemovedConversionEdgeInvalidatesAndWritesNothing) {
  auto& g = this->graph_;
  auto twist = g.FindTwistEdge("o", "C", "b");  // reads c -> o and b -> c
  ASSERT_TRUE(twist);
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c").RelativeTo("b"), q_BC, p_BC));  // an update: still valid
  ASSERT_EQ(g.SetTwist(*twist, Vector3d(1, 0, 0), Vector3d::Zero()), ErrorCode::kOk);
  ASSERT_TRUE(twist->is_valid());
  ASSERT_TRUE(g.RemovePose("c", "b"));
  EXPECT_FALSE(twist->is_valid());
  const auto V = g.twist_value(g.FindFrame("o"));
  EXPECT_EQ(g.SetTwist(*twist, Vector3d(5, 5, 5), Vector3d(5, 5, 5)), ErrorCode::kQueryInvalidated);
  EXPECT_EQ(g.twist_value(g.FindFrame("o"))->linear, V->linear);
  // Removing the edge itself: SetTwist's own code.
  auto own = g.FindTwistEdge("o", "C", "c");
  ASSERT_TRUE(own);
  ASSERT_TRUE(g.RemoveTwist("o", "C"));
  EXPECT_EQ(g.SetTwist(*own, Vector3d(1, 0, 0), Vector3d::Zero()), ErrorCode::kNoSuchEdge);
}

TYPED_TEST(ConvertingHandles, InvalidInputsAreRefusedAndWriteNothing) {
  auto& g = this->graph_;
  auto twist = g.FindTwistEdge("o", "C", "c");
  auto pose = g.FindPoseEdge(PoseSpec::Of("o").RelativeTo("c"));
  ASSERT_TRUE(twist && pose);
  const std::string before = Dump(g);
  EXPECT_EQ(g.SetTwist(*twist, Vector3d(NAN, 0, 0), Vector3d::Zero()), ErrorCode::kInvalidNumber);
  EXPECT_EQ(g.SetTwist(*twist, Vector3d::Zero(), Vector3d(0, 2e12, 0)), ErrorCode::kInvalidNumber);
  EXPECT_EQ(g.SetPose(*pose, Quaterniond(1.1, 0, 0, 0), Vector3d::Zero()),
            ErrorCode::kInvalidRotation);
  EXPECT_EQ(g.SetPose(*pose, Quaterniond::Identity(), Vector3d(0, INFINITY, 0)),
            ErrorCode::kInvalidNumber);
  Matrix3d reflection = Matrix3d::Identity();
  reflection(2, 2) = -1;
  EXPECT_EQ(g.SetPose(*pose, reflection, Vector3d::Zero()), ErrorCode::kInvalidRotation);
  EXPECT_EQ(Dump(g), before);
}

TYPED_TEST(ConvertingHandles, RealTimeCallsDoNotAllocate) {
  using B = TypeParam;
  auto& g = this->graph_;
  auto twist = g.FindTwistEdge("o", "C", "b");
  auto pose =
      g.FindPoseEdge(std::is_same_v<B, coord::QuaternionBackend>
                         ? PoseSpec::Of("o").RelativeTo("c").RelativeToPoint("c2").ExpressedIn("b")
                         : PoseSpec::Of("o").RelativeTo("c"));
  ASSERT_TRUE(twist && pose);
  int failures = 0;
  std::size_t allocations = 0;
  {
    testing::CountAllocations counting;
    for (int i = 0; i < 200; ++i) {
      const double s = 1e-3 * i;
      failures += g.SetTwist(*twist, Vector3d(s, 0, 0), Vector3d(0, s, 0)) != ErrorCode::kOk;
      failures += g.SetPose(*pose, Quaterniond(AngleAxisd(s, Vector3d::UnitZ())),
                            Vector3d(s, 0, 1)) != ErrorCode::kOk;
      failures += g.SetPose(*pose, Matrix3d(AngleAxisd(s, Vector3d::UnitX())), Vector3d(0, s, 1)) !=
                  ErrorCode::kOk;
      failures +=
          g.SetTwist(*twist, Vector3d(NAN, 0, 0), Vector3d::Zero()) != ErrorCode::kInvalidNumber;
    }
    allocations = counting.count();
  }
  EXPECT_EQ(failures, 0);
  EXPECT_EQ(allocations, 0u);
}

}  // namespace
}  // namespace semgraph::core
