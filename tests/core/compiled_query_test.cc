// Compiled queries and value handles (the real-time path): same numbers as the one-shot queries,
// invalidation by topology changes only where affected, no allocation, untorn concurrent reads.
//
// Legend: the paper's spray-painting scene (examples/spray_painting_scene.h): B base {b},
// E end effector {e}, O2 gun {o2}, O1 cylinder {o1} with paint point {f1}, C camera {c}.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>
#include <thread>

#include "../../examples/spray_painting_scene.h"
#include "semgraph/core/scene_graph.h"
#include "support/alloc_counter.h"

// Allocations are counted by the suite's one replacement of operator new/delete
// (support/alloc_counter.h: every form, so it links with sanitizer runtimes too).
using semgraph::testing::AllocationCounter;

namespace semgraph::core {
namespace {

namespace scene = examples::spray_painting;
using Eigen::Quaterniond;
using Eigen::Vector3d;

template <class B>
class CompiledQueryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const scene::EdgePose& e : scene::kPoses) {
      ASSERT_TRUE(graph_.AddPose(PoseSpec::Of(e.of, e.of_body).RelativeTo(e.wrt, e.wrt_body),
                                 e.q_PF, e.p_PoFo_P));
    }
    ASSERT_TRUE(graph_.AddTwist(TwistSpec::Of("c", "C").RelativeTo("B").ExpressedIn("c"),
                                Vector3d::Zero(), Vector3d::Zero()));
    ASSERT_TRUE(graph_.AddTwist(TwistSpec::Of("o1", "O1").RelativeTo("C").ExpressedIn("o1"),
                                scene::kV_CO1_c, scene::kW_CO1_c));
    ASSERT_TRUE(graph_.AddTwist(TwistSpec::Of("o2", "O2").RelativeTo("E").ExpressedIn("o2"),
                                Vector3d(0.01, 0.02, 0.0), Vector3d(0.0, 0.0, 0.3)));
    ASSERT_TRUE(graph_.AddTwist(TwistSpec::Of("e", "E").RelativeTo("B").ExpressedIn("e"),
                                scene::kV_BE_e, scene::kW_BE_e));
  }
  SceneGraph<B> graph_;
};

using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(CompiledQueryTest, Backends);

const char* const kFrames[] = {"b", "c", "o1", "f1", "e", "o2"};
const char* const kBodies[] = {"B", "C", "O1", "O1", "E", "O2"};

TYPED_TEST(CompiledQueryTest, FrameToFramePosesEqualOneShot) {
  using B = TypeParam;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      const PoseSpec spec = PoseSpec::Of(kFrames[i]).RelativeTo(kFrames[j]);
      auto one_shot = this->graph_.GetPose(spec);
      auto compiled = this->graph_.CompilePose(spec);
      ASSERT_TRUE(one_shot && compiled);
      typename B::PoseCoords X;
      ASSERT_EQ(compiled->Evaluate(X), ErrorCode::kOk);
      EXPECT_LT((B::TranslationOf(X) - B::TranslationOf(one_shot->value)).norm(), 1e-12);
      EXPECT_LT(
          (B::ToMatrix(B::RotationOf(X)) - B::ToMatrix(B::RotationOf(one_shot->value))).norm(),
          1e-12);
      EXPECT_EQ(compiled->semantics(), one_shot->semantics);
    }
  }
}

TEST(CompiledQuery, GeneralPosesPositionsOrientationsEqualOneShot) {
  using B = coord::QuaternionBackend;
  SceneGraph<B> graph;
  for (const scene::EdgePose& e : scene::kPoses) {
    ASSERT_TRUE(graph.AddPose(PoseSpec::Of(e.of, e.of_body).RelativeTo(e.wrt, e.wrt_body), e.q_PF,
                              e.p_PoFo_P));
  }
  int checked = 0;
  for (int e = 0; e < 6; ++e) {
    for (int a = 0; a < 6; ++a) {
      if (std::string_view(kBodies[e]) != kBodies[a]) continue;
      for (int f = 0; f < 6; ++f) {
        for (int b = 0; b < 6; ++b) {
          if (std::string_view(kBodies[f]) != kBodies[b]) continue;
          for (int r = 0; r < 6; ++r) {
            PoseSpec spec = PoseSpec::Of(kFrames[a]).RelativeTo(kFrames[b]).ExpressedIn(kFrames[r]);
            spec.point = kFrames[e];
            spec.ref_point = kFrames[f];
            auto one_shot = graph.GetPose(spec);
            auto compiled = graph.CompilePose(spec);
            ASSERT_TRUE(one_shot && compiled);
            B::PoseCoords X;
            ASSERT_EQ(compiled->Evaluate(X), ErrorCode::kOk);
            EXPECT_LT((X.translation - one_shot->value.translation).norm(), 1e-12);
            EXPECT_LT(X.rotation.angularDistance(one_shot->value.rotation), 1e-12);
            auto p1 = graph.GetPosition(spec);
            auto p2 = graph.CompilePosition(spec);
            ASSERT_TRUE(p1 && p2);
            Eigen::Vector3d p;
            ASSERT_EQ(p2->Evaluate(p), ErrorCode::kOk);
            EXPECT_LT((p - p1->value).norm(), 1e-12);
            auto o1 = graph.GetOrientation(spec);
            auto o2 = graph.CompileOrientation(spec);
            ASSERT_TRUE(o1 && o2);
            Eigen::Quaterniond M;
            ASSERT_EQ(o2->Evaluate(M), ErrorCode::kOk);
            EXPECT_LT(M.angularDistance(o1->value), 1e-12);
            ++checked;
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 300);
}

TYPED_TEST(CompiledQueryTest, TwistsEqualOneShotForEveryPointFrameAndBodyPair) {
  const char* const bodies[] = {"B", "C", "O1", "E", "O2"};
  for (const char* point : kFrames) {
    for (const char* frame : kFrames) {
      for (const char* C : bodies) {
        for (const char* D : bodies) {
          const TwistSpec spec = TwistSpec::Of(point, C).RelativeTo(D).ExpressedIn(frame);
          auto one_shot = this->graph_.GetTwist(spec);
          auto compiled = this->graph_.CompileTwist(spec);
          ASSERT_TRUE(one_shot && compiled) << point << frame << C << D;
          Vector3d v, w;
          ASSERT_EQ(compiled->Evaluate(v, w), ErrorCode::kOk);
          EXPECT_LT((v - one_shot->linear).norm(), 1e-12);
          EXPECT_LT((w - one_shot->angular).norm(), 1e-12);
        }
      }
    }
  }
}

TYPED_TEST(CompiledQueryTest, CompileReportsTheOneShotError) {
  auto c = this->graph_.CompilePose(PoseSpec::Of("f1", "O1").RelativeTo("o2", "E"));
  ASSERT_FALSE(c);
  EXPECT_EQ(c.error().code, ErrorCode::kFrameBodyMismatch);
  auto t = this->graph_.CompileTwist(TwistSpec::Of("f1", "O1").RelativeTo("Z").ExpressedIn("b"));
  ASSERT_FALSE(t);
  EXPECT_EQ(t.error().code, ErrorCode::kUnknownBody);
}

TYPED_TEST(CompiledQueryTest, UpdatesByHandleAreSeenAndConstantEdgesHaveNoHandle) {
  using B = TypeParam;
  auto handle = this->graph_.FindPoseEdge("e", "b");
  ASSERT_TRUE(handle);
  auto query = this->graph_.CompilePose(PoseSpec::Of("o2").RelativeTo("b"));
  ASSERT_TRUE(query);
  const Quaterniond q_BE = scene::Rpy(0.3, -0.2, 0.1);
  const Vector3d p_BE(0.1, 0.2, 0.3);
  ASSERT_EQ(this->graph_.SetPose(*handle, q_BE, p_BE), ErrorCode::kOk);
  typename B::PoseCoords X;
  ASSERT_EQ(query->Evaluate(X), ErrorCode::kOk);
  // Independent: X_BO2 = X_BE * X_EO2 with the stated mounting.
  const scene::EdgePose& mount = scene::kPoses[3];
  const Vector3d p_expected = p_BE + q_BE * mount.p_PoFo_P;
  EXPECT_LT((B::TranslationOf(X) - p_expected).norm(), 1e-12);
  EXPECT_EQ(this->graph_.FindPoseEdge("f1", "o1").error().code, ErrorCode::kConstantPoseChange);
  EXPECT_EQ(this->graph_.SetPose(*handle, Quaterniond(2, 0, 0, 0), p_BE),
            ErrorCode::kInvalidRotation);
  EXPECT_EQ(this->graph_.SetPose(*handle, q_BE, Vector3d(NAN, 0, 0)), ErrorCode::kInvalidNumber);
  auto twist = this->graph_.FindTwistEdge("e", "B");
  ASSERT_TRUE(twist);
  EXPECT_EQ(this->graph_.SetTwist(*twist, Vector3d(1, 2, 3), Vector3d(0, 0, 1)), ErrorCode::kOk);
  EXPECT_EQ(this->graph_.twist_value(this->graph_.FindFrame("e"))->linear, Vector3d(1, 2, 3));
}

TYPED_TEST(CompiledQueryTest, RemovalInvalidatesOnlyAffectedQueriesUntilRecompiled) {
  using B = TypeParam;
  auto through_e = this->graph_.CompilePose(PoseSpec::Of("o2").RelativeTo("b"));
  auto camera_side = this->graph_.CompilePose(PoseSpec::Of("f1").RelativeTo("c"));
  auto twist =
      this->graph_.CompileTwist(TwistSpec::Of("f1", "O1").RelativeTo("C").ExpressedIn("c"));
  auto handle = this->graph_.FindPoseEdge("e", "b");
  ASSERT_TRUE(through_e && camera_side && twist && handle);
  ASSERT_TRUE(this->graph_.RemovePose("e", "b"));
  typename B::PoseCoords X;
  EXPECT_EQ(through_e->Evaluate(X), ErrorCode::kQueryInvalidated);
  EXPECT_FALSE(through_e->is_valid());
  EXPECT_EQ(camera_side->Evaluate(X), ErrorCode::kOk);
  Vector3d v, w;
  EXPECT_EQ(twist->Evaluate(v, w), ErrorCode::kOk);
  EXPECT_EQ(this->graph_.SetPose(*handle, Quaterniond::Identity(), Vector3d::Zero()),
            ErrorCode::kNoSuchEdge);
  // Re-adding the edge does not revive old queries or handles; recompiling does.
  ASSERT_TRUE(this->graph_.AddPose(PoseSpec::Of("e", "E").RelativeTo("b", "B"),
                                   Quaterniond::Identity(), Vector3d(1, 0, 0)));
  EXPECT_EQ(through_e->Evaluate(X), ErrorCode::kQueryInvalidated);
  auto again = this->graph_.CompilePose(PoseSpec::Of("o2").RelativeTo("b"));
  ASSERT_TRUE(again);
  EXPECT_EQ(again->Evaluate(X), ErrorCode::kOk);
  ASSERT_TRUE(this->graph_.RemoveTwist("o1", "C"));
  EXPECT_EQ(twist->Evaluate(v, w), ErrorCode::kQueryInvalidated);
}

TYPED_TEST(CompiledQueryTest, RejectedOperationsLeaveCompiledQueriesAndHandlesValid) {
  using B = TypeParam;
  auto pose = this->graph_.CompilePose(PoseSpec::Of("f1").RelativeTo("o2"));
  auto twist =
      this->graph_.CompileTwist(TwistSpec::Of("f1", "O1").RelativeTo("O2").ExpressedIn("o2"));
  auto handle = this->graph_.FindPoseEdge("e", "b");
  ASSERT_TRUE(pose && twist && handle);
  typename B::PoseCoords before, after;
  ASSERT_EQ(pose->Evaluate(before), ErrorCode::kOk);
  // Every kind of rejection: multiple parents, cycle, duplicate path, constant change, twist
  // duplicate path, invalid number, removal of a missing edge.
  EXPECT_FALSE(this->graph_.AddPose(PoseSpec::Of("o1", "O1").RelativeTo("e", "E"),
                                    Quaterniond::Identity(), Vector3d::Zero()));
  EXPECT_FALSE(this->graph_.AddPose(PoseSpec::Of("b", "B").RelativeTo("f1", "O1"),
                                    Quaterniond::Identity(), Vector3d::Zero()));
  EXPECT_FALSE(this->graph_.AddPose(PoseSpec::Of("c2", "C").RelativeTo("o2", "O2"),
                                    Quaterniond::Identity(), Vector3d::Zero()));
  EXPECT_FALSE(this->graph_.AddPose(PoseSpec::Of("f1", "O1").RelativeTo("o1", "O1"),
                                    Quaterniond::Identity(), Vector3d::Zero()));
  EXPECT_FALSE(this->graph_.AddTwist(TwistSpec::Of("f1", "O1").RelativeTo("B").ExpressedIn("f1"),
                                     Vector3d::Zero(), Vector3d::Zero()));
  EXPECT_FALSE(this->graph_.AddPose(PoseSpec::Of("e", "E").RelativeTo("b", "B"),
                                    Quaterniond::Identity(), Vector3d(NAN, 0, 0)));
  EXPECT_FALSE(this->graph_.RemovePose("b", "e"));
  EXPECT_FALSE(this->graph_.RemoveTwist("f1", "B"));
  EXPECT_TRUE(pose->is_valid());
  ASSERT_EQ(pose->Evaluate(after), ErrorCode::kOk);
  EXPECT_EQ(B::TranslationOf(after), B::TranslationOf(before));
  Vector3d v, w;
  EXPECT_EQ(twist->Evaluate(v, w), ErrorCode::kOk);
  EXPECT_EQ(this->graph_.SetPose(*handle, Quaterniond::Identity(), Vector3d::Zero()),
            ErrorCode::kOk);
}

TYPED_TEST(CompiledQueryTest, EvaluateAndSetAllocateNothing) {
  using B = TypeParam;
  // The homogeneous representation cannot express a pose in a third frame: use [o2] there.
  const char* pose_frame = std::is_same_v<B, coord::HomogeneousBackend> ? "o2" : "c";
  auto pose = this->graph_.CompilePose(PoseSpec::Of("f1").RelativeTo("o2").ExpressedIn(pose_frame));
  auto position = this->graph_.CompilePosition(PoseSpec::Of("f1").RelativeTo("e").ExpressedIn("c"));
  auto orientation = this->graph_.CompileOrientation(PoseSpec::Of("f1").RelativeTo("o2"));
  auto twist =
      this->graph_.CompileTwist(TwistSpec::Of("f1", "O1").RelativeTo("O2").ExpressedIn("c"));
  // An angular velocity is the angular part of any point's twist: the coordinate frame's origin.
  auto angular =
      this->graph_.CompileTwist(TwistSpec::Of("b", "O1").RelativeTo("B").ExpressedIn("b"));
  auto pose_edge = this->graph_.FindPoseEdge("e", "b");
  auto twist_edge = this->graph_.FindTwistEdge("e", "B");
  ASSERT_TRUE(pose && position && orientation && twist && angular && pose_edge && twist_edge);
  typename B::PoseCoords X;
  typename B::Rotation M;
  Vector3d p, v, w;
  const std::size_t before = AllocationCounter::total();
  for (int i = 0; i < 1000; ++i) {
    const double s = 1e-3 * i;
    ASSERT_EQ(this->graph_.SetPose(*pose_edge, scene::Rpy(s, 0.2, -s), Vector3d(s, 0.1, 0.7)),
              ErrorCode::kOk);
    ASSERT_EQ(this->graph_.SetTwist(*twist_edge, Vector3d(s, 0, 0), Vector3d(0, s, 0)),
              ErrorCode::kOk);
    ASSERT_EQ(pose->Evaluate(X), ErrorCode::kOk);
    ASSERT_EQ(position->Evaluate(p), ErrorCode::kOk);
    ASSERT_EQ(orientation->Evaluate(M), ErrorCode::kOk);
    ASSERT_EQ(twist->Evaluate(v, w), ErrorCode::kOk);
    ASSERT_EQ(angular->Evaluate(v, w), ErrorCode::kOk);
  }
  EXPECT_EQ(AllocationCounter::total(), before);
}

// A twist query needs its point, compiled or not: an empty point is invalid_name in both, and
// compiling must not substitute another point (it once used the coordinate frame's origin).
TYPED_TEST(CompiledQueryTest, CompileTwistWithoutPointIsInvalidNameLikeGetTwist) {
  const TwistSpec spec = TwistSpec::Of("", "O1").RelativeTo("B").ExpressedIn("b");
  auto one_shot = this->graph_.GetTwist(spec);
  auto compiled = this->graph_.CompileTwist(spec);
  ASSERT_FALSE(one_shot);
  ASSERT_FALSE(compiled);
  EXPECT_EQ(one_shot.error().code, ErrorCode::kInvalidName);
  EXPECT_EQ(compiled.error().code, ErrorCode::kInvalidName);
  EXPECT_EQ(compiled.error().field, semantics::Field::kPoint);
}

// The memoized evaluation (PoseCache) equals the plain one after any interleaving of value
// updates and evaluations: a 40-frame chain with branches (so the queries have two chains and
// every step of Algorithm 1), where each round changes none, one, a few or every edge.
TYPED_TEST(CompiledQueryTest, CachedEvaluationEqualsUncachedAfterRandomUpdates) {
  using B = TypeParam;
  SceneGraph<B> g;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto random_q = [&] {
    return Quaterniond(u(rng), u(rng), u(rng), u(rng) + 2).normalized();
  };
  const auto random_p = [&] { return Vector3d(u(rng), u(rng), u(rng)); };
  std::vector<PoseHandle> handles;
  for (int i = 1; i <= 40; ++i) {
    const int parent = i <= 30 ? i - 1 : 10 + (i - 31);  // a trunk of 30, and branches off it
    const std::string of = "n" + std::to_string(i), wrt = "n" + std::to_string(parent);
    ASSERT_TRUE(g.AddPose(
        PoseSpec::Of(of, "N" + std::to_string(i)).RelativeTo(wrt, "N" + std::to_string(parent)),
        random_q(), random_p()));
    auto h = g.FindPoseEdge(of, wrt);
    ASSERT_TRUE(h);
    handles.push_back(*h);
  }
  // A point on the body of [a] and a reference point on the body of [b] (constant mounts).
  ASSERT_TRUE(
      g.AddPose(PoseSpec::Of("pe", "N29").RelativeTo("n29", "N29"), random_q(), random_p()));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("pf", "N3").RelativeTo("n3", "N3"), random_q(), random_p()));
  const std::string e = "pe", a = "n29", f = "pf", b = "n3",
                    r = "n38";  // frames on several branches
  // The homogeneous representation only holds poses of frames in the reference frame.
  constexpr bool kHomogeneous = std::is_same_v<B, coord::HomogeneousBackend>;
  PoseSpec general = PoseSpec::Of(a).RelativeTo(b).ExpressedIn(kHomogeneous ? b : r);
  if (!kHomogeneous) {
    general.point = e;
    general.ref_point = f;
  }
  auto pose = g.CompilePose(general);
  auto position = g.CompilePosition(PoseSpec::Of("n40").RelativeTo("n35").ExpressedIn(r));
  auto orientation = g.CompileOrientation(PoseSpec::Of(a).RelativeTo(b));
  ASSERT_TRUE(pose && position && orientation);
  auto pose_cache = pose->MakeCache();
  auto position_cache = position->MakeCache();
  auto orientation_cache = orientation->MakeCache();
  for (int round = 0; round < 400; ++round) {
    const int changes = round % 7 == 0 ? 40 : round % 3;  // every edge, none, one or two
    for (int k = 0; k < changes; ++k) {
      const PoseHandle h = changes == 40 ? handles[k] : handles[rng() % handles.size()];
      ASSERT_EQ(g.SetPose(h, random_q(), random_p()), ErrorCode::kOk);
    }
    typename B::PoseCoords X, X_cached;
    ASSERT_EQ(pose->Evaluate(X), ErrorCode::kOk);
    ASSERT_EQ(pose->Evaluate(X_cached, pose_cache), ErrorCode::kOk);
    EXPECT_LT((B::TranslationOf(X) - B::TranslationOf(X_cached)).norm(), 1e-12)
        << "round " << round;
    EXPECT_LT((B::ToMatrix(B::RotationOf(X)) - B::ToMatrix(B::RotationOf(X_cached))).norm(), 1e-12);
    Vector3d p, p_cached;
    ASSERT_EQ(position->Evaluate(p), ErrorCode::kOk);
    ASSERT_EQ(position->Evaluate(p_cached, position_cache), ErrorCode::kOk);
    EXPECT_LT((p - p_cached).norm(), 1e-12);
    typename B::Rotation R, R_cached;
    ASSERT_EQ(orientation->Evaluate(R), ErrorCode::kOk);
    ASSERT_EQ(orientation->Evaluate(R_cached, orientation_cache), ErrorCode::kOk);
    EXPECT_LT((B::ToMatrix(R) - B::ToMatrix(R_cached)).norm(), 1e-12);
  }
  // The cache allocates nothing when evaluating, and a removed edge invalidates it too.
  typename B::PoseCoords X;
  const std::size_t before = AllocationCounter::total();
  for (int i = 0; i < 100; ++i) {
    ASSERT_EQ(g.SetPose(handles[i % 40], random_q(), random_p()), ErrorCode::kOk);
    ASSERT_EQ(pose->Evaluate(X, pose_cache), ErrorCode::kOk);
  }
  EXPECT_EQ(AllocationCounter::total(), before);
  ASSERT_TRUE(g.RemovePose("n25", "n24"));
  EXPECT_EQ(pose->Evaluate(X, pose_cache), ErrorCode::kQueryInvalidated);
  EXPECT_GT(pose_cache.bytes(), 0u);
}

// One writer flips the two joint edges between two poses; readers must only ever see one of
// the four combinations of untorn edge values (each edge is read under its sequence lock).
TEST(CompiledQueryConcurrency, ReadersNeverSeeTornEdgeValues) {
  using B = coord::QuaternionBackend;
  SceneGraph<B> graph;
  ASSERT_TRUE(graph.AddPose(PoseSpec::Of("l1", "L1").RelativeTo("base", "Base"),
                            Quaterniond::Identity(), Vector3d(1, 0, 0)));
  ASSERT_TRUE(graph.AddPose(PoseSpec::Of("l2", "L2").RelativeTo("l1", "L1"),
                            Quaterniond::Identity(), Vector3d(1, 0, 0)));
  auto h1 = graph.FindPoseEdge("l1", "base");
  auto h2 = graph.FindPoseEdge("l2", "l1");
  auto query = graph.CompilePose(PoseSpec::Of("l2").RelativeTo("base"));
  ASSERT_TRUE(h1 && h2 && query);
  const Quaterniond qa = Quaterniond::Identity();
  const Quaterniond qb(Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitZ()));
  const Vector3d pa(1, 0, 0), pb(0, 2, 0);
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    for (int i = 0; !stop.load(std::memory_order_relaxed); ++i) {
      (void)graph.SetPose(*h1, (i & 1) ? qb : qa, (i & 1) ? pb : pa);
      (void)graph.SetPose(*h2, (i & 2) ? qb : qa, (i & 2) ? pb : pa);
    }
  });
  // The four possible results X_base,l2 = X_1 * X_2.
  std::vector<B::PoseCoords> allowed;
  for (int i = 0; i < 4; ++i) {
    const B::PoseCoords X1{(i & 1) ? qb : qa, (i & 1) ? pb : pa};
    const B::PoseCoords X2{(i & 2) ? qb : qa, (i & 2) ? pb : pa};
    allowed.push_back(B::ComposeChain(X2, X1));
  }
  int bad = 0;
  auto cache = query->MakeCache();  // the memoized evaluation must be as untorn as the plain one
  for (int n = 0; n < 50000; ++n) {
    B::PoseCoords X;
    ASSERT_EQ((n & 1) ? query->Evaluate(X, cache) : query->Evaluate(X), ErrorCode::kOk);
    bool match = false;
    for (const B::PoseCoords& A : allowed) {
      match |= (X.translation - A.translation).norm() < 1e-12 &&
               X.rotation.angularDistance(A.rotation) < 1e-9;
    }
    bad += !match;
  }
  stop = true;
  writer.join();
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace semgraph::core
