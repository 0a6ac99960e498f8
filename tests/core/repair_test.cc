// Repair of rejected relations (core/src/repair.cc, docs/repair.md): each strategy on the
// paper's Fig. 4 and Fig. 6 cases with values built by hand, and random scenes whose every
// answer after repairs equals the ground truth of absolute poses and twists
// (tests/support/world_scene.h), on both backends.
//
// Legend: {x}|X frame x on body X; t -> h pose edge; D ~> {h} twist edge; X_AB pose of B in A.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/world_scene.h"

namespace semgraph::core {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;
using semgraph::testing::WorldScene;

template <class B>
class Repair : public ::testing::Test {};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(Repair, Backends);

Quaterniond Rot(double angle, const Vector3d& axis) {
  return Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

// X as (q, p): q = R_PC, p = p_PoCo_P.
struct Pose {
  Quaterniond q;
  Vector3d p;
  Pose operator*(const Pose& o) const { return {q * o.q, q * o.p + p}; }
  Pose inverse() const { return {q.conjugate(), -(q.conjugate() * p)}; }
};

template <class G>
void ExpectPose(const G& g, std::string_view of, std::string_view wrt, const Pose& X,
                const char* what) {
  using B = typename G::Backend;
  auto got = g.GetPose(PoseSpec::Of(of).RelativeTo(wrt));
  ASSERT_TRUE(got) << what << ": " << g.Describe(got.error());
  EXPECT_LT((B::TranslationOf(got->value) - X.p).norm(), 1e-12) << what;
  EXPECT_LT((B::ToMatrix(B::RotationOf(got->value)) - X.q.toRotationMatrix()).norm(), 1e-12)
      << what;
}

// Fig. 4:  {d}|D -> {c2}|C   {a}|A -> {c1}|C   {f}|F alone.
template <class G>
void Figure4(G& g, const Pose& X_DC2, const Pose& X_AC1) {
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c2", "C").RelativeTo("d", "D"), X_DC2.q, X_DC2.p));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c1", "C").RelativeTo("a", "A"), X_AC1.q, X_AC1.p));
  ASSERT_TRUE(g.AddBody("F"));
  ASSERT_TRUE(g.AddFrame("f", "F"));
}

TYPED_TEST(Repair, Figure4PoseOfC2WrtFIsAddedInverted) {
  SceneGraph<TypeParam> g;
  const Pose X_DC2{Rot(0.3, {0, 0, 1}), {1, 0, 0}}, X_AC1{Rot(-0.2, {1, 0, 0}), {0, 2, 0}};
  const Pose X_FC2{Rot(0.7, {0, 1, 1}), {0.5, -1, 2}};
  Figure4(g, X_DC2, X_AC1);
  // Without repair: refused, as the paper says.
  auto plain = g.AddPose(PoseSpec::Of("c2", "C").RelativeTo("f", "F"), X_FC2.q, X_FC2.p);
  ASSERT_FALSE(plain);
  EXPECT_EQ(plain.error().code, ErrorCode::kMultiplePoseParents);
  // With repair: the inverse PoseCoord({f}|F, {c2}|C, [c2]) is added instead.
  auto repaired =
      g.AddPose(PoseSpec::Of("c2", "C").RelativeTo("f", "F"), X_FC2.q, X_FC2.p, RepairPolicy{});
  ASSERT_TRUE(repaired) << repaired.error().message;
  EXPECT_EQ(repaired->applied, RepairKind::kInverted);
  EXPECT_NE(repaired->change.find("pose of {f}|F wrt {c2}|C"), std::string::npos)
      << repaired->change;
  EXPECT_EQ(g.frame_name(g.pose_parent(g.FindFrame("f"))), "c2");
  EXPECT_TRUE(CheckInvariants(g).empty());
  // The information is kept: c2 wrt f is X_FC2, and f wrt d is X_DC2 X_FC2^-1.
  ExpectPose(g, "c2", "f", X_FC2, "c2 wrt f");
  ExpectPose(g, "f", "d", X_DC2 * X_FC2.inverse(), "f wrt d");
}

TYPED_TEST(Repair, ReRootsTheInverseHeadsTreeAndInvalidatesExactlyTheReversedEdges) {
  SceneGraph<TypeParam> g;
  const Pose X_DC2{Rot(0.3, {0, 0, 1}), {1, 0, 0}}, X_AC1{Rot(-0.2, {1, 0, 0}), {0, 2, 0}};
  Figure4(g, X_DC2, X_AC1);
  // {f} gets a pose parent: {h}|H -> {g}|G -> {f}|F, so the inverse of "c2 wrt f" is refused
  // by P1 as well; f's tree is re-rooted at f (two edges reversed) before it is added.
  const Pose X_HG{Rot(1.1, {1, 2, 3}), {0, 0, 3}}, X_GF{Rot(-0.4, {3, 1, 0}), {2, 1, 0}};
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("g", "G").RelativeTo("h", "H"), X_HG.q, X_HG.p));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("f", "F").RelativeTo("g", "G"), X_GF.q, X_GF.p));
  auto h_GF = g.FindPoseEdge("f", "g");
  auto h_DC2 = g.FindPoseEdge("c2", "d");
  auto q_HF = g.CompilePose(PoseSpec::Of("f").RelativeTo("h"));
  auto q_DC2 = g.CompilePose(PoseSpec::Of("c2").RelativeTo("d"));
  ASSERT_TRUE(h_GF && h_DC2 && q_HF && q_DC2);
  const Pose X_FC2{Rot(0.7, {0, 1, 1}), {0.5, -1, 2}};
  const std::string before = Dump(g);
  EXPECT_FALSE(g.AddPose(PoseSpec::Of("c2", "C").RelativeTo("f", "F"), X_FC2.q, X_FC2.p,
                         RepairPolicy{.invert = true, .reroot = false}));
  EXPECT_EQ(Dump(g), before) << "a repair that does not take changes nothing";
  auto repaired =
      g.AddPose(PoseSpec::Of("c2", "C").RelativeTo("f", "F"), X_FC2.q, X_FC2.p, RepairPolicy{});
  ASSERT_TRUE(repaired) << repaired.error().message;
  EXPECT_EQ(repaired->applied, RepairKind::kRerooted);
  EXPECT_EQ(repaired->reversed_edges, 2u);
  EXPECT_TRUE(CheckInvariants(g).empty()) << CheckInvariants(g);
  EXPECT_EQ(g.frame_name(g.pose_parent(g.FindFrame("g"))), "f");
  EXPECT_EQ(g.frame_name(g.pose_parent(g.FindFrame("h"))), "g");
  EXPECT_EQ(g.frame_name(g.pose_parent(g.FindFrame("f"))), "c2");
  // Every relation of the old tree is unchanged, and the new one holds.
  ExpectPose(g, "f", "h", X_HG * X_GF, "f wrt h");
  ExpectPose(g, "g", "f", X_GF.inverse(), "g wrt f");
  ExpectPose(g, "c2", "f", X_FC2, "c2 wrt f");
  ExpectPose(g, "h", "d", X_DC2 * X_FC2.inverse() * (X_HG * X_GF).inverse(), "h wrt d");
  // Handles and compiled queries of reversed edges report it; the others keep working.
  typename TypeParam::PoseCoords X;
  EXPECT_EQ(g.SetPose(*h_GF, Quaterniond::Identity(), Vector3d::Zero()), ErrorCode::kNoSuchEdge);
  EXPECT_EQ(q_HF->Evaluate(X), ErrorCode::kQueryInvalidated);
  EXPECT_EQ(g.SetPose(*h_DC2, X_DC2.q, X_DC2.p), ErrorCode::kOk);
  EXPECT_EQ(q_DC2->Evaluate(X), ErrorCode::kOk);
  EXPECT_TRUE(g.FindPoseEdge("g", "f"));  // the reversed edge's new handle is found as usual
}

TYPED_TEST(Repair, AnAlreadyDeterminedPoseIsAcceptedWhenItAgreesAndRefusedWithTheDiscrepancy) {
  SceneGraph<TypeParam> g;
  const Pose X_AB{Rot(0.5, {1, 0, 0}), {1, 2, 3}}, X_BC{Rot(-1.0, {0, 1, 1}), {0, -1, 0}};
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("b", "B").RelativeTo("a", "A"), X_AB.q, X_AB.p));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"), X_BC.q, X_BC.p));
  const Pose X_CA = (X_AB * X_BC).inverse();  // a wrt c: closes the cycle (pose_cycle)
  const std::string before = Dump(g);
  RepairPolicy policy;
  policy.position_tolerance = 1e-6;
  policy.angle_tolerance = 1e-6;
  auto same = g.AddPose(PoseSpec::Of("a").RelativeTo("c"), X_CA.q, X_CA.p, policy);
  ASSERT_TRUE(same) << same.error().message;
  EXPECT_EQ(same->applied, RepairKind::kConsistent);
  EXPECT_LT(same->discrepancy.position, 1e-12);
  EXPECT_EQ(Dump(g), before);
  // At the boundary: half the tolerance is accepted, twice is refused with the numbers.
  auto close =
      g.AddPose(PoseSpec::Of("a").RelativeTo("c"), X_CA.q, X_CA.p + Vector3d(0.5e-6, 0, 0), policy);
  ASSERT_TRUE(close);
  EXPECT_NEAR(close->discrepancy.position, 0.5e-6, 1e-12);
  auto far = g.AddPose(PoseSpec::Of("a").RelativeTo("c"), X_CA.q * Rot(2e-6, {0, 0, 1}),
                       X_CA.p + Vector3d(0, 3e-3, 0), policy);
  ASSERT_FALSE(far);
  EXPECT_EQ(far.error().code, ErrorCode::kPoseCycle);
  ASSERT_TRUE(far.error().discrepancy.has_value());
  EXPECT_NEAR(far.error().discrepancy->position, 3e-3, 1e-12);
  EXPECT_NEAR(far.error().discrepancy->angle, 2e-6, 1e-9);
  EXPECT_NE(
      far.error().message.find("differs from the pose the graph derives by 0.003 m and 2e-06 rad"),
      std::string::npos)
      << far.error().message;
  EXPECT_EQ(Dump(g), before);
  // P1 within one tree is already determined too: c wrt a (c already has the parent b).
  auto also =
      g.AddPose(PoseSpec::Of("c").RelativeTo("a"), (X_AB * X_BC).q, (X_AB * X_BC).p, policy);
  ASSERT_TRUE(also) << also.error().message;
  EXPECT_EQ(also->applied, RepairKind::kConsistent);
}

TYPED_TEST(Repair, DuplicatePosePathIsNotRepairable) {
  SceneGraph<TypeParam> g;
  Figure4(g, {Rot(0.3, {0, 0, 1}), {1, 0, 0}}, {Rot(-0.2, {1, 0, 0}), {0, 2, 0}});
  const std::string before = Dump(g);
  auto r = g.AddPose(PoseSpec::Of("a").RelativeTo("d"), Quaterniond::Identity(), Vector3d(1, 1, 1),
                     RepairPolicy{});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kDuplicatePosePath);
  EXPECT_FALSE(r.error().discrepancy.has_value());
  EXPECT_EQ(Dump(g), before);
}

// Fig. 6 with a frame {f}|F in the pose tree of {c2}: the twist of c2 wrt F is refused (c2 has
// the twist parent D) and added inverted, on {f}; the twist of c3 wrt A is derivable.
TYPED_TEST(Repair, Figure6TwistsAreInvertedOrCheckedForConsistency) {
  SceneGraph<TypeParam> g;
  const Pose X_C1C3{Rot(0.4, {0, 1, 0}), {0.2, 0, 0.1}}, X_C2F{Rot(0.9, {1, 1, 0}), {0, 0.5, 0}};
  const Vector3d v_AC1_C1(0.1, 0.2, 0.3), w_AC_C1(0, 0, 0.5), v_DC2_C2(1, 0, 0), w_DC_C2(0, 0.2, 0);
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c3", "C").RelativeTo("c1", "C"), X_C1C3.q, X_C1C3.p));
  ASSERT_TRUE(
      g.AddTwist(TwistSpec::Of("c1", "C").RelativeTo("A").ExpressedIn("c1"), v_AC1_C1, w_AC_C1));
  ASSERT_TRUE(
      g.AddTwist(TwistSpec::Of("c2", "C").RelativeTo("D").ExpressedIn("c2"), v_DC2_C2, w_DC_C2));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("f", "F").RelativeTo("c2", "C"), X_C2F.q, X_C2F.p));
  // (a) TwistCoord(c2|C, F, [c2]) with C moving relative to F at (v, w) at c2.
  const Vector3d v_FC2_C2(0.3, -0.1, 0.2), w_FC_C2(0.1, 0.1, -0.3);
  const TwistSpec c2_wrt_F = TwistSpec::Of("c2", "C").RelativeTo("F").ExpressedIn("c2");
  auto a = g.AddTwist(c2_wrt_F, v_FC2_C2, w_FC_C2, RepairPolicy{});
  ASSERT_TRUE(a) << a.error().message;
  EXPECT_EQ(a->applied, RepairKind::kInverted);
  EXPECT_EQ(g.body_name(g.twist_parent(g.FindFrame("f"))), "C");
  // The graph now answers the refused relation exactly.
  auto V = g.GetTwist(c2_wrt_F);
  ASSERT_TRUE(V) << g.Describe(V.error());
  EXPECT_LT((V->linear - v_FC2_C2).norm(), 1e-12);
  EXPECT_LT((V->angular - w_FC_C2).norm(), 1e-12);
  // ... and the stored screw twist is F wrt C at f in [f], by hand: w_CF = -w_FC, and the
  // velocity of the point of F at f relative to C is -(v_FC2 + w_FC x p_C2F), all in [f].
  const Eigen::Matrix3d R_FC2 = X_C2F.q.conjugate().toRotationMatrix();
  const auto stored = g.twist_value(g.FindFrame("f"));
  ASSERT_TRUE(stored);
  EXPECT_LT((stored->angular - R_FC2 * -w_FC_C2).norm(), 1e-12);
  EXPECT_LT((stored->linear - R_FC2 * -(v_FC2_C2 + w_FC_C2.cross(X_C2F.p))).norm(), 1e-12);
  // (b) TwistCoord(c3|C, A, [c3]) follows from A ~> {c1} and X_C1C3: consistent, or refused.
  const Eigen::Matrix3d R_C3C1 = X_C1C3.q.conjugate().toRotationMatrix();
  const Vector3d w_AC_C3 = R_C3C1 * w_AC_C1,
                 v_AC3_C3 = R_C3C1 * (v_AC1_C1 + w_AC_C1.cross(X_C1C3.p));
  const TwistSpec c3_wrt_A = TwistSpec::Of("c3", "C").RelativeTo("A").ExpressedIn("c3");
  const std::string before = Dump(g);
  auto b = g.AddTwist(c3_wrt_A, v_AC3_C3, w_AC_C3,
                      RepairPolicy{.position_tolerance = 1e-9, .angle_tolerance = 1e-9});
  ASSERT_TRUE(b) << b.error().message;
  EXPECT_EQ(b->applied, RepairKind::kConsistent);
  auto off = g.AddTwist(c3_wrt_A, v_AC3_C3 + Vector3d(0, 0, 0.01), w_AC_C3, RepairPolicy{});
  ASSERT_FALSE(off);
  EXPECT_EQ(off.error().code, ErrorCode::kDuplicateTwistPath);
  ASSERT_TRUE(off.error().discrepancy);
  EXPECT_NEAR(off.error().discrepancy->position, 0.01, 1e-12);
  EXPECT_NE(off.error().message.find("m/s"), std::string::npos);
  EXPECT_EQ(Dump(g), before);
}

// Random relations between the frames of a world scene, each derived from the absolute poses
// and twists, added with repair: whatever strategy each add takes, every pose and twist the
// graph answers afterwards equals the world's.
TYPED_TEST(Repair, RandomScenesAnswerLikeTheWorldAfterRepairs) {
  using B = TypeParam;
  std::map<RepairKind, int> applied;
  int refused = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    WorldScene w(seed, 14, 9);
    SceneGraph<B> g;
    const auto name = [](int i) { return "f" + std::to_string(i); };
    const auto body = [](int k) { return "B" + std::to_string(k); };
    for (int op = 0; op < 40; ++op) {
      const int i = w.RandomFrame(), j = w.RandomFrameOtherThan(i);
      if (op % 4 == 3) {  // a twist of body(i) wrt another body, at f_i in [f_i]
        const int C = w.BodyOf(i), D = w.RandomBodyOtherThan(C);
        auto r =
            g.AddTwist(TwistSpec::Of(name(i), body(C)).RelativeTo(body(D)).ExpressedIn(name(i)),
                       w.LinearVelocity(i, C, D, i), w.AngularVelocity(C, D, i), RepairPolicy{});
        if (r)
          ++applied[r->applied];
        else
          ++refused;
      } else {
        const Quaterniond q_JI(w.Rotation(j, i));
        auto r = g.AddPose(
            PoseSpec::Of(name(i), body(w.BodyOf(i))).RelativeTo(name(j), body(w.BodyOf(j))), q_JI,
            w.Position(i, j, j), RepairPolicy{.position_tolerance = 1e-9, .angle_tolerance = 1e-9});
        if (r)
          ++applied[r->applied];
        else
          ++refused;
      }
      ASSERT_TRUE(CheckInvariants(g).empty()) << CheckInvariants(g);
    }
    for (int i = 0; i < w.num_frames(); ++i) {
      if (!g.FindFrame(name(i)).is_valid()) continue;
      for (int j = 0; j < w.num_frames(); ++j) {
        if (!g.FindFrame(name(j)).is_valid()) continue;
        auto X = g.GetPose(PoseSpec::Of(name(i)).RelativeTo(name(j)));
        if (!X) {
          EXPECT_EQ(X.error().code, ErrorCode::kNoPosePath);
          continue;
        }
        EXPECT_LT((B::TranslationOf(X->value) - w.Position(i, j, j)).norm(), 1e-9) << seed;
        EXPECT_LT((B::ToMatrix(B::RotationOf(X->value)) - w.Rotation(j, i)).norm(), 1e-9) << seed;
        for (int D = 0; D < w.num_bodies(); ++D) {
          const int C = w.BodyOf(i);
          if (C == D || !g.FindBody(body(D)).is_valid()) continue;
          auto V = g.GetTwist(TwistSpec::Of(name(i)).RelativeTo(body(D)).ExpressedIn(name(j)));
          if (!V) continue;  // no twist path
          EXPECT_LT((V->linear - w.LinearVelocity(i, C, D, j)).norm(), 1e-9) << seed;
          EXPECT_LT((V->angular - w.AngularVelocity(C, D, j)).norm(), 1e-9) << seed;
        }
      }
    }
  }
  // Every strategy took part (the scenes are dense enough for each).
  EXPECT_GT(applied[RepairKind::kNone], 0);
  EXPECT_GT(applied[RepairKind::kInverted], 0);
  EXPECT_GT(applied[RepairKind::kRerooted], 0);
  EXPECT_GT(applied[RepairKind::kConsistent], 0);
  std::printf("repairs: none %d, inverted %d, rerooted %d, consistent %d; refused %d\n",
              applied[RepairKind::kNone], applied[RepairKind::kInverted],
              applied[RepairKind::kRerooted], applied[RepairKind::kConsistent], refused);
}

// Re-rooting a 100,000-frame chain at its leaf: O(|T|), every edge reversed with its value.
// Regression (found by the differential fuzzer): a re-root through a stamped edge moved the
// edge's value to the other frame's slot but left its sample history in the head frame's slot,
// so the new edge into that frame answered timed queries with the old edge's samples. A path
// with a stamped edge is not re-rooted now: the relation keeps its error, nothing changes.
TYPED_TEST(Repair, ReRootingThroughAStampedEdgeIsRefusedAndChangesNothing) {
  auto g = *SceneGraph<TypeParam>::Create(TimeOptions{});
  const Pose X_BE1{Rot(0.2, {0, 0, 1}), {1, 0, 0}}, X_BE2{Rot(0.6, {0, 0, 1}), {2, 0, 0}};
  const auto spec_e = PoseSpec::Of("e", "E").RelativeTo("b", "D");
  ASSERT_TRUE(g.AddPose(spec_e, X_BE1.q, X_BE1.p, Stamp::Nanoseconds(1000000000)));
  ASSERT_TRUE(g.AddPose(spec_e, X_BE2.q, X_BE2.p, Stamp::Nanoseconds(2000000000)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c", "F").RelativeTo("f", "A"), Rot(0.1, {1, 0, 0}),
                        Vector3d(0, 1, 0)));
  const std::string before = Dump(g);
  // c wrt e: c has the parent f (P1); the inverse e wrt c: e has the parent b (P1); re-rooting
  // e's tree would reverse the stamped edge b -> e.
  auto r = g.AddPose(PoseSpec::Of("c").RelativeTo("e"), Rot(0.3, {0, 1, 0}), Vector3d(0, 0, 1),
                     RepairPolicy{});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kMultiplePoseParents);
  EXPECT_EQ(Dump(g), before);
  // The stamped edge still interpolates its own samples: at 1.5 s, halfway (a rotation about z
  // by 0.4 rad; screw motion between (Rz(0.2), (1,0,0)) and (Rz(0.6), (2,0,0))).
  auto X = g.GetPose(PoseSpec::Of("e").RelativeTo("b"), At(Stamp::Nanoseconds(1500000000)));
  ASSERT_TRUE(X) << g.Describe(X.error());
  using B = TypeParam;
  EXPECT_LT(
      (B::ToMatrix(B::RotationOf(X->value.value)) - Rot(0.4, {0, 0, 1}).toRotationMatrix()).norm(),
      1e-12);
  // The screw motion's position halfway: X_1 Exp(Log(X_1^-1 X_2) / 2), built by hand: a planar
  // rotation by 0.4 rad about z; X_1^-1 X_2 = (Rz(0.4), Rz(-0.2) (1, 0, 0)); its half screw
  // turns by 0.2 about the same fixed point c of the plane: p(1/2) = c + Rz(0.2) (p_1 - c).
  const Pose rel = X_BE1.inverse() * X_BE2;
  const Eigen::Matrix2d I2 = Eigen::Matrix2d::Identity();
  const Eigen::Matrix2d R04 = Eigen::Rotation2Dd(0.4).toRotationMatrix();
  const Eigen::Vector2d c =
      (I2 - R04).inverse() * rel.p.head<2>();  // fixed point of rel in X_1's frame
  const Eigen::Vector2d half = c + Eigen::Rotation2Dd(0.2).toRotationMatrix() * (-c);
  const Vector3d p_half = X_BE1.q * Vector3d(half.x(), half.y(), 0) + X_BE1.p;
  EXPECT_LT((B::TranslationOf(X->value.value) - p_half).norm(), 1e-12);
}

TEST(RepairDeep, ReRootingALongChainReversesEveryEdgeExactly) {
  constexpr int kFrames = 100000;
  SceneGraph<> g;
  g.Reserve(kFrames + 2, kFrames + 2);
  const Pose step{Rot(1e-3, {0, 0, 1}), {1e-3, 0, 0}};
  for (int i = 1; i <= kFrames; ++i) {
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("n" + std::to_string(i), "N" + std::to_string(i))
                              .RelativeTo("n" + std::to_string(i - 1), "N" + std::to_string(i - 1)),
                          step.q, step.p));
  }
  const std::string leaf = "n" + std::to_string(kFrames);
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("x", "X").RelativeTo(leaf, "N" + std::to_string(kFrames)),
                        Quaterniond::Identity(), Vector3d::Zero()));
  // {q}|Q below {qq}|QQ. "q wrt x" is refused by P1 (q has the parent qq); its inverse "x wrt q"
  // too (x has the parent leaf); so the chain's tree is re-rooted at x (100,001 edges reversed)
  // and x is added below q.
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("q", "Q").RelativeTo("qq", "QQ"), Quaterniond::Identity(),
                        Vector3d(0, 1, 0)));
  const Pose X_XQ{Rot(0.5, {1, 0, 0}), {0, 0, 2}};
  auto r = g.AddPose(PoseSpec::Of("q").RelativeTo("x"), X_XQ.q, X_XQ.p, RepairPolicy{});
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->applied, RepairKind::kRerooted);
  EXPECT_EQ(r->reversed_edges, static_cast<std::size_t>(kFrames + 1));
  // n0 wrt x: the chain composed by hand, inverted.
  Pose X_0L{Quaterniond::Identity(), Vector3d::Zero()};
  for (int i = 0; i < kFrames; ++i) X_0L = X_0L * step;
  auto X = g.GetPose(PoseSpec::Of("n0").RelativeTo("x"));
  ASSERT_TRUE(X);
  EXPECT_LT((X->value.translation - X_0L.inverse().p).norm(), 1e-9);
  EXPECT_LT(X->value.rotation.angularDistance(X_0L.inverse().q), 1e-9);
  auto Y = g.GetPose(PoseSpec::Of("qq").RelativeTo("n0"));  // qq wrt n0 = X_0L X_XQ X_QQQ
  ASSERT_TRUE(Y);
  const Pose expected = X_0L * X_XQ * Pose{Quaterniond::Identity(), Vector3d(0, 1, 0)}.inverse();
  EXPECT_LT((Y->value.translation - expected.p).norm(), 1e-9);
  EXPECT_EQ(g.frame_name(g.tree_root(g.FindFrame("n0"))), "qq");
}

}  // namespace
}  // namespace semgraph::core
