// One answer, one type: a compiled query's Evaluate() gives the result type of the one-shot
// query (QueryResult<coord::Pose<B>> like GetPose, with the semantics), and poses convert to and
// from Eigen::Isometry3d (coord::Pose<B>::ToIsometry / FromIsometry, AddPose and SetPose from an
// isometry). Both backends.
//
// Scene by hand: {a}|A wrt {w}|W is a quarter turn about z and 1 m along x; {t}|T wrt {a}|A is
// 0.5 m along a's x. So X_WT: R_WT = Rz(90 deg), p_WT = (1, 0.5, 0). The twist of T wrt A at {t}
// in [t] is (v, w) = ((0, 0.2, 0), (0, 0, 1)).
#include <gtest/gtest.h>

#include <cmath>
#include <type_traits>

#include "semgraph/core/scene_graph.h"

namespace semgraph::core {
namespace {

using base::ErrorCode;
using Eigen::AngleAxisd;
using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

const Quaterniond q_WA(AngleAxisd(M_PI / 2, Vector3d::UnitZ()));

template <class B>
class ResultTypes : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(g_.AddPose(PoseSpec::Of("a", "A").RelativeTo("w", "W"), q_WA, Vector3d(1, 0, 0)));
    ASSERT_TRUE(g_.AddPose(PoseSpec::Of("t", "T").RelativeTo("a", "A"), Quaterniond::Identity(),
                           Vector3d(0.5, 0, 0)));
    ASSERT_TRUE(g_.AddTwist(TwistSpec::Of("t").RelativeTo("A").ExpressedIn("t"),
                            Vector3d(0, 0.2, 0), Vector3d(0, 0, 1)));
  }
  SceneGraph<B> g_;
};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(ResultTypes, Backends);

TYPED_TEST(ResultTypes, CompiledAndOneShotGiveTheSameTypeAndAnswer) {
  auto& g = this->g_;
  const PoseSpec spec = PoseSpec::Of("t").RelativeTo("w");
  const auto compiled = g.CompilePose(spec);
  ASSERT_TRUE(compiled);
  static_assert(std::is_same_v<decltype(g.GetPose(spec)), decltype(compiled->Evaluate())>);
  const auto one_shot = g.GetPose(spec);
  const auto evaluated = compiled->Evaluate();
  ASSERT_TRUE(one_shot && evaluated);
  EXPECT_EQ(evaluated->semantics, one_shot->semantics);
  const Isometry3d X = evaluated->ToIsometry();
  EXPECT_LT((X.translation() - Vector3d(1, 0.5, 0)).norm(), 1e-15);
  EXPECT_LT((X.linear() - q_WA.toRotationMatrix()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((X.matrix() - one_shot->ToIsometry().matrix()).cwiseAbs().maxCoeff(), 1e-15);
  // With a memo: the same answer.
  auto cache = compiled->MakeCache();
  const auto cached = compiled->Evaluate(cache);
  ASSERT_TRUE(cached);
  EXPECT_LT((cached->ToIsometry().matrix() - X.matrix()).cwiseAbs().maxCoeff(), 1e-15);

  const auto position = g.CompilePosition(spec);
  ASSERT_TRUE(position);
  static_assert(std::is_same_v<decltype(g.GetPosition(spec)), decltype(position->Evaluate())>);
  ASSERT_TRUE(position->Evaluate());
  EXPECT_EQ(position->Evaluate()->semantics, g.GetPosition(spec)->semantics);
  EXPECT_LT((position->Evaluate()->value - Vector3d(1, 0.5, 0)).norm(), 1e-15);

  const auto orientation = g.CompileOrientation(spec);
  ASSERT_TRUE(orientation);
  static_assert(
      std::is_same_v<decltype(g.GetOrientation(spec)), decltype(orientation->Evaluate())>);
  ASSERT_TRUE(orientation->Evaluate());
  EXPECT_EQ(orientation->Evaluate()->semantics, g.GetOrientation(spec)->semantics);
  EXPECT_LT((TypeParam::ToMatrix(orientation->Evaluate()->value) - q_WA.toRotationMatrix())
                .cwiseAbs()
                .maxCoeff(),
            1e-15);

  // The twist of T wrt A at {t} in [w]: R_WT (v, w) = ((-0.2, 0, 0), (0, 0, 1)).
  const TwistSpec V_spec = TwistSpec::Of("t").RelativeTo("A").ExpressedIn("w");
  const auto twist = g.CompileTwist(V_spec);
  ASSERT_TRUE(twist);
  static_assert(std::is_same_v<decltype(g.GetTwist(V_spec)), decltype(twist->Evaluate())>);
  const auto V = twist->Evaluate();
  ASSERT_TRUE(V);
  EXPECT_EQ(V->semantics, g.GetTwist(V_spec)->semantics);
  EXPECT_LT((V->linear - Vector3d(-0.2, 0, 0)).norm(), 1e-15);
  EXPECT_LT((V->angular - Vector3d(0, 0, 1)).norm(), 1e-15);
}

TYPED_TEST(ResultTypes, AnInvalidatedCompiledQueryIsAQueryError) {
  auto& g = this->g_;
  const auto compiled = g.CompilePose(PoseSpec::Of("t").RelativeTo("w"));
  const auto twist = g.CompileTwist(TwistSpec::Of("t").RelativeTo("A").ExpressedIn("w"));
  ASSERT_TRUE(compiled && twist);
  ASSERT_TRUE(g.RemovePose("a", "w"));
  const auto r = compiled->Evaluate();
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kQueryInvalidated);
  EXPECT_EQ(
      g.Describe(r.error()),
      "query failed (query_invalidated): an edge the compiled query reads was removed after it was "
      "compiled; compile it again");
  EXPECT_EQ(twist->Evaluate().error().code, ErrorCode::kQueryInvalidated);
}

TYPED_TEST(ResultTypes, IsometriesInAndOut) {
  using B = TypeParam;
  auto& g = this->g_;
  // AddPose and SetPose from an isometry store what the matrix forms store.
  Isometry3d X_AK = Isometry3d::Identity();
  X_AK.linear() = AngleAxisd(0.3, Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  X_AK.translation() = Vector3d(0.1, -0.2, 0.3);
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("k", "K").RelativeTo("a"), X_AK));
  const auto X = g.GetPose(PoseSpec::Of("k").RelativeTo("a"));
  ASSERT_TRUE(X);
  EXPECT_LT((X->ToIsometry().matrix() - X_AK.matrix()).cwiseAbs().maxCoeff(), 1e-15);
  auto handle = g.FindPoseEdge("k", "a");
  ASSERT_TRUE(handle);
  X_AK.translation() = Vector3d(2, 3, 4);
  ASSERT_EQ(g.SetPose(*handle, X_AK), ErrorCode::kOk);
  EXPECT_EQ(B::TranslationOf(g.pose_value(g.FindFrame("k"))), Vector3d(2, 3, 4));
  Isometry3d bad = X_AK;
  bad.linear()(0, 0) += 1e-3;
  EXPECT_EQ(g.SetPose(*handle, bad), ErrorCode::kInvalidRotation);

  // FromIsometry: checked as MakePose is; ToIsometry gives it back.
  const auto s = X->semantics;
  const auto made = coord::Pose<B>::FromIsometry(s, X_AK);
  ASSERT_TRUE(made);
  EXPECT_EQ(made->semantics, s);
  EXPECT_LT((made->ToIsometry().matrix() - X_AK.matrix()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(coord::Pose<B>::FromIsometry(s, bad).error().code, ErrorCode::kInvalidRotation);
  Isometry3d nan = X_AK;
  nan.translation().x() = NAN;
  EXPECT_EQ(coord::Pose<B>::FromIsometry(s, nan).error().code, ErrorCode::kInvalidNumber);
  // A pose the homogeneous representation cannot hold: (k, [a]) wrt w in [w] is not an edge form.
  semantics::PoseSemantics third = s;
  third.coordinate_frame = semantics::OrientationFrame(g.names().Find("w"));
  const auto held = coord::Pose<B>::FromIsometry(third, X_AK);
  if constexpr (std::is_same_v<B, coord::HomogeneousBackend>) {
    EXPECT_EQ(held.error().code, ErrorCode::kRepresentationConstraint);
  } else {
    EXPECT_TRUE(held);
  }
}

}  // namespace
}  // namespace semgraph::core
