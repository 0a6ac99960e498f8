// The paper's example scene (examples/spray_painting_scene.h) checked against world poses and
// twists built by hand from the same numbers, with plain Eigen (never through semgraph).
//
// Legend: W world (= {b}, the robot base is fixed), X_WF pose of frame F in W; V of a body =
// (w_WX_W angular velocity, v_WX_W(o) velocity of the body's point at the world origin).
#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <string>

#include "../../examples/spray_painting_scene.h"
#include "semgraph/core/scene_graph.h"

namespace semgraph::core {
namespace {

namespace scene = examples::spray_painting;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

struct WorldPose {
  Matrix3d R;
  Vector3d p;
};
struct WorldTwist {
  Vector3d w;    // w_WX_W
  Vector3d v_o;  // velocity of the body's point at the world origin, in W
  Vector3d VelocityAt(const Vector3d& p_WoP_W) const { return v_o + w.cross(p_WoP_W); }
};

class SprayPainting : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const scene::EdgePose& e : scene::kPoses) {
      ASSERT_TRUE(graph_.AddPose(PoseSpec::Of(e.of, e.of_body).RelativeTo(e.wrt, e.wrt_body),
                                 e.q_PF, e.p_PoFo_P));
    }
    ASSERT_TRUE(graph_.AddTwist(TwistSpec::Of("c", "C").RelativeTo("B").ExpressedIn("b"),
                                Vector3d::Zero(), Vector3d::Zero()));
    ASSERT_TRUE(graph_.AddTwist(TwistSpec::Of("o1", "O1").RelativeTo("C").ExpressedIn("c"),
                                scene::kV_CO1_c, scene::kW_CO1_c));
    ASSERT_TRUE(graph_.AddTwist(TwistSpec::Of("o2", "O2").RelativeTo("E").ExpressedIn("o2"),
                                Vector3d::Zero(), Vector3d::Zero()));
    ASSERT_TRUE(graph_.AddTwist(TwistSpec::Of("e", "E").RelativeTo("B").ExpressedIn("e"),
                                scene::kV_BE_e, scene::kW_BE_e));
    // World poses: chain the stated edge poses by hand, X_WF = X_WP * X_PF.
    X_W_["b"] = {Matrix3d::Identity(), Vector3d::Zero()};
    for (int pass = 0; pass < 3; ++pass) {
      for (const scene::EdgePose& e : scene::kPoses) {
        if (!X_W_.count(e.wrt) || X_W_.count(e.of)) continue;
        const WorldPose& P = X_W_[e.wrt];
        X_W_[e.of] = {P.R * e.q_PF.toRotationMatrix(), P.p + P.R * e.p_PoFo_P};
      }
    }
    ASSERT_EQ(X_W_.size(), 6u);
    // World twists. B and C are fixed. O1 moves relative to C (static): the measured twist at
    // o1 in [c] rotated into W. E moves relative to B (= W): screw twist at e in [e]. O2 = E.
    V_W_["B"] = V_W_["C"] = {Vector3d::Zero(), Vector3d::Zero()};
    const Matrix3d& R_Wc = X_W_["c"].R;
    const Vector3d w_O1 = R_Wc * scene::kW_CO1_c;
    V_W_["O1"] = {w_O1, R_Wc * scene::kV_CO1_c - w_O1.cross(X_W_["o1"].p)};
    const Matrix3d& R_We = X_W_["e"].R;
    const Vector3d w_E = R_We * scene::kW_BE_e;
    V_W_["E"] = {w_E, R_We * scene::kV_BE_e - w_E.cross(X_W_["e"].p)};
    V_W_["O2"] = V_W_["E"];
  }

  // Expected pose (e,[a]) wrt (f,[b]) in [r]: p = R_Wr^T (p_We - p_Wf); M = R_rb R_ba R_br.
  void ExpectPose(const std::string& e, const std::string& a, const std::string& f,
                  const std::string& b, const std::string& r, const Vector3d& p,
                  const Quaterniond& q) {
    const Vector3d p_expected = X_W_[r].R.transpose() * (X_W_[e].p - X_W_[f].p);
    const Matrix3d R_rb = X_W_[r].R.transpose() * X_W_[b].R;
    const Matrix3d R_ba = X_W_[b].R.transpose() * X_W_[a].R;
    const Matrix3d M_expected = R_rb * R_ba * R_rb.transpose();
    EXPECT_LT((p - p_expected).norm(), 1e-12) << p.transpose() << " vs " << p_expected.transpose();
    EXPECT_LT((q.toRotationMatrix() - M_expected).norm(), 1e-12);
  }

  // Expected twist of body C relative to D at point e, in [r].
  void ExpectTwist(const std::string& e, const std::string& C, const std::string& D,
                   const std::string& r, const Vector3d& v, const Vector3d& w) {
    const Vector3d& p_We = X_W_[e].p;
    const Vector3d w_W = V_W_[C].w - V_W_[D].w;
    const Vector3d v_W = V_W_[C].VelocityAt(p_We) - V_W_[D].VelocityAt(p_We);
    const Matrix3d R_rW = X_W_[r].R.transpose();
    EXPECT_LT((v - R_rW * v_W).norm(), 1e-12)
        << v.transpose() << " vs " << (R_rW * v_W).transpose();
    EXPECT_LT((w - R_rW * w_W).norm(), 1e-12);
  }

  SceneGraph<> graph_;
  std::map<std::string, WorldPose> X_W_;
  std::map<std::string, WorldTwist> V_W_;
};

TEST_F(SprayPainting, ListingTwoPoseOfPaintPointWrtGun) {
  auto X = graph_.GetPose(PoseSpec::Of("f1", "O1").RelativeTo("o2", "O2"));
  ASSERT_TRUE(X);
  ExpectPose("f1", "f1", "o2", "o2", "o2", X->value.translation, X->value.rotation);
}

TEST_F(SprayPainting, ListingTwoTwistOfPaintPointWrtGunInGunFrame) {
  auto V = graph_.GetTwist(TwistSpec::Of("f1", "O1").RelativeTo("O2").ExpressedIn("o2"));
  ASSERT_TRUE(V);
  ExpectTwist("f1", "O1", "O2", "o2", V->linear, V->angular);
}

TEST_F(SprayPainting, PaintPointInRobotBase) {
  auto X = graph_.GetPose(PoseSpec::Of("f1", "O1").RelativeTo("b", "B"));
  ASSERT_TRUE(X);
  ExpectPose("f1", "f1", "b", "b", "b", X->value.translation, X->value.rotation);
}

TEST_F(SprayPainting, PoseWithPointRefPointAndCoordinateFrameChanged) {
  PoseSpec s = PoseSpec::Of("o1", "O1").RelativeTo("o2", "O2").ExpressedIn("c");
  s.point = "f1";
  s.ref_point = "o2";
  auto X = graph_.GetPose(s);
  ASSERT_TRUE(X);
  ExpectPose("f1", "o1", "o2", "o2", "c", X->value.translation, X->value.rotation);
}

TEST_F(SprayPainting, VelocitiesAtCoincidentPointsInEveryFrame) {
  for (const char* point : {"f1", "o2", "e", "c", "b"}) {
    for (const char* frame : {"b", "c", "o1", "f1", "e", "o2"}) {
      auto V = graph_.GetTwist(TwistSpec::Of(point, "O1").RelativeTo("E").ExpressedIn(frame));
      ASSERT_TRUE(V) << point << " " << frame;
      ExpectTwist(point, "O1", "E", frame, V->linear, V->angular);
      auto v =
          graph_.GetLinearVelocity(TwistSpec::Of(point, "C").RelativeTo("O2").ExpressedIn(frame));
      ASSERT_TRUE(v);
      const Vector3d w_expected = X_W_[frame].R.transpose() * (V_W_["C"].w - V_W_["O2"].w);
      ExpectTwist(point, "C", "O2", frame, v->value, w_expected);
    }
  }
}

TEST_F(SprayPainting, ConvertedCameraTwistIsAScrewTwistAtO1) {
  const FrameIndex o1 = graph_.FindFrame("o1");
  const std::optional<coord::Twist> V = graph_.twist_value(o1);
  ASSERT_TRUE(V.has_value());
  // Stored: TwistCoord(o1|O1, C, [o1]) = the measured twist rotated from [c] into [o1].
  const Matrix3d R_o1c = X_W_["o1"].R.transpose() * X_W_["c"].R;
  EXPECT_LT((V->linear - R_o1c * scene::kV_CO1_c).norm(), 1e-12);
  EXPECT_LT((V->angular - R_o1c * scene::kW_CO1_c).norm(), 1e-12);
}

TEST_F(SprayPainting, AngularVelocityOfCylinderInBase) {
  auto w = graph_.GetAngularVelocity(TwistSpec::Of("", "O1").RelativeTo("B").ExpressedIn("b"));
  ASSERT_TRUE(w);
  EXPECT_LT((w->value - V_W_["O1"].w).norm(), 1e-12);
}

}  // namespace
}  // namespace semgraph::core
