// SceneGraph's real-time claims, proven by counting the global operator new
// (tests/support/alloc_counter.h) while the calls run in loops: every one-shot query kind
// (pose, position, orientation, twist, linear and angular velocity; accepted and rejected; by
// name and by semantics ids), compiled queries, and value updates of existing non-constant
// edges through handles (SetPose / SetTwist) allocate nothing (scene_graph.h: "Queries are
// noexcept, allocation-free"; "SetPose/SetTwist and CompiledX::Evaluate are noexcept,
// allocation-free"). Updates through AddPose / AddTwist are build-time calls and are only
// measured (see ValueUpdatesThroughAddPoseAndAddTwist...).
//
// Each case is first run once unarmed to check that it takes the intended path (its result
// code), then kRepetitions times armed.
//
// Legend:
//   {x}|X     frame x on body X;  t -> h pose edge;  D ~> {h} twist edge
//   X_FE_R    pose of (e,[a]) wrt (f,[b]) in [r];  p_FE_R position;  O_BA_R orientation
//   V_DCe_R  twist of C wrt D at point e in [r]
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "semgraph/base/error_code.h"
#include "semgraph/core/compiled_query.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/alloc_counter.h"
#include "support/rigid_body_scene.h"

namespace semgraph::semantics {
// Readable ErrorCode in gtest failure messages (found by ADL).
void PrintTo(ErrorCode code, std::ostream* os) { *os << ToString(code); }
}  // namespace semgraph::semantics

namespace semgraph::core {
namespace {

using semgraph::testing::CountAllocations;
using semgraph::testing::RigidBodyScene;

constexpr int kRepetitions = 100;

template <class R>
ErrorCode CodeOf(const R& result) {
  return result ? ErrorCode::kOk : result.error().code;
}

/// Runs `run` (returning an ErrorCode) once unarmed, expecting `expected`, then kRepetitions
/// times with the counter armed, expecting no allocation.
template <class F>
void ExpectNoAllocation(const std::string& what, ErrorCode expected, F&& run) {
  EXPECT_EQ(run(), expected) << what << " took another path than intended";
  std::size_t allocations = 0;
  {
    CountAllocations counting;
    for (int i = 0; i < kRepetitions; ++i) {
      if (run() != expected) break;
    }
    allocations = counting.count();
  }
  EXPECT_EQ(allocations, 0u) << what << ": " << allocations << " allocations in " << kRepetitions
                             << " calls";
}

// ====================================================================== the §V scene

// Fig. 8, the spray-painting scene (pose edges solid, twist edges ~>), plus a lone frame:
//
//   {b}|B
//    +-- {c}|C                  B ~> {c}   camera mount: zero twist, given in [b]
//    |     +-- {o1}|O1          C ~> {o1}  measured in [c] (Listing 1), converted to [o1]
//    |           +-- {f1}|O1    constant (Listing 1)
//    +-- {e}|E                  B ~> {e}   joint velocities
//          +-- {o2}|O2          E ~> {o2}  rigid mount: zero twist
//   {l}|L   (alone)
template <class G>
void BuildSprayPainting(G& g) {
  const auto accept = [&](BuildResult r) { ASSERT_TRUE(r) << r.error().message; };
  const Eigen::Quaterniond q_CO1(Eigen::AngleAxisd(0.4, Eigen::Vector3d(0, 0, 1)));
  const Eigen::Quaterniond q_O1F1(Eigen::AngleAxisd(0.7853981633974483, Eigen::Vector3d::UnitZ()));
  const Eigen::Quaterniond q_BE(Eigen::AngleAxisd(-0.3, Eigen::Vector3d(1, 1, 0).normalized()));
  accept(g.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"), Eigen::Quaterniond::Identity(),
                   Eigen::Vector3d(0.5, 0, 1.2)));
  accept(g.AddPose(PoseSpec::Of("o1", "O1").RelativeTo("c", "C"), q_CO1,
                   Eigen::Vector3d(0.1, 0.3, 2.0)));
  accept(g.AddPose(PoseSpec::Of("f1", "O1").RelativeTo("o1", "O1"), q_O1F1,
                   Eigen::Vector3d(0.02, 0, 0.2)));
  accept(g.AddPose(PoseSpec::Of("e", "E").RelativeTo("b", "B"), q_BE,
                   Eigen::Vector3d(0.3, -0.2, 0.9)));
  accept(g.AddPose(PoseSpec::Of("o2", "O2").RelativeTo("e", "E"), Eigen::Quaterniond::Identity(),
                   Eigen::Vector3d(0, 0, 0.15)));
  accept(g.AddTwist(TwistSpec::Of("c", "C").RelativeTo("B").ExpressedIn("b"),
                    Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  accept(g.AddTwist(TwistSpec::Of("o1", "O1").RelativeTo("C").ExpressedIn("c"),
                    Eigen::Vector3d(0.2, 0.1, 0.1), Eigen::Vector3d(0.05, 0.1, 0.2)));
  accept(g.AddTwist(TwistSpec::Of("e", "E").RelativeTo("B").ExpressedIn("e"),
                    Eigen::Vector3d(0.0, 0.3, -0.1), Eigen::Vector3d(0.2, 0.0, 0.4)));
  accept(g.AddTwist(TwistSpec::Of("o2", "O2").RelativeTo("E").ExpressedIn("o2"),
                    Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  accept(g.AddBody("L"));
  accept(g.AddFrame("l", "L"));
}

template <class B>
class SceneGraphNoAllocation : public ::testing::Test {
 protected:
  static constexpr bool kHomogeneous = std::is_same_v<B, coord::HomogeneousBackend>;
  void SetUp() override { BuildSprayPainting(graph_); }
  semantics::Point P(std::string_view n) const { return semantics::Point(graph_.names().Find(n)); }
  semantics::OrientationFrame O(std::string_view n) const {
    return semantics::OrientationFrame(graph_.names().Find(n));
  }
  semantics::Body Bd(std::string_view n) const { return semantics::Body(graph_.names().Find(n)); }

  SceneGraph<B> graph_;
};

struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(SceneGraphNoAllocation, Backends, BackendName);

TYPED_TEST(SceneGraphNoAllocation, PoseQueriesByNameDoNotAllocate) {
  const auto& g = this->graph_;
  const ErrorCode free_form =
      this->kHomogeneous ? ErrorCode::kRepresentationConstraint : ErrorCode::kOk;
  // Listing 2: PoseCoord({f1}|O1, {o2}|O2, [o2]).
  const PoseSpec listing2 = PoseSpec::Of("f1", "O1").RelativeTo("o2", "O2");
  ExpectNoAllocation("GetPose(Listing 2)", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetPose(listing2)); });
  PoseSpec general =
      PoseSpec::Of("o1").RelativeTo("o2").AtPoint("f1").RelativeToPoint("o2").ExpressedIn("c");
  ExpectNoAllocation("GetPose((f1,[o1]), {o2}, [c])", free_form,
                     [&] { return CodeOf(g.GetPose(general)); });
  general = PoseSpec::Of("f1").RelativeTo("o2").RelativeToPoint("o2").ExpressedIn("b");
  ExpectNoAllocation("GetPose in [b]", free_form, [&] { return CodeOf(g.GetPose(general)); });
  const PoseSpec position = PoseSpec::Of("f1").RelativeTo("e").ExpressedIn("c");
  ExpectNoAllocation("GetPosition", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetPosition(position)); });
  const PoseSpec orientation = PoseSpec::Of("f1").RelativeTo("o2");
  ExpectNoAllocation("GetOrientation", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetOrientation(orientation)); });
  const PoseSpec orientation_in_c = PoseSpec::Of("f1").RelativeTo("o2").ExpressedIn("c");
  ExpectNoAllocation("GetOrientation in [c]", free_form,
                     [&] { return CodeOf(g.GetOrientation(orientation_in_c)); });
}

TYPED_TEST(SceneGraphNoAllocation, TwistQueriesByNameDoNotAllocate) {
  const auto& g = this->graph_;
  // Listing 2: TwistCoord(f1|O1, O2, [o2]), through B: O1 -C- B -E- O2.
  const TwistSpec listing2 = TwistSpec::Of("f1", "O1").RelativeTo("O2").ExpressedIn("o2");
  ExpectNoAllocation("GetTwist(Listing 2)", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetTwist(listing2)); });
  const TwistSpec at_other_point = TwistSpec::Of("e", "O1").RelativeTo("C").ExpressedIn("b");
  ExpectNoAllocation("GetTwist at a point of another body", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetTwist(at_other_point)); });
  ExpectNoAllocation("GetLinearVelocity", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetLinearVelocity(listing2)); });
  TwistSpec angular;
  angular.body = "O1";
  angular.ref_body = "E";
  angular.coordinate_frame = "c";
  ExpectNoAllocation("GetAngularVelocity", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetAngularVelocity(angular)); });
  const TwistSpec same_body = TwistSpec::Of("f1").RelativeTo("O1").ExpressedIn("b");
  ExpectNoAllocation("GetTwist of a body wrt itself", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetTwist(same_body)); });
}

TYPED_TEST(SceneGraphNoAllocation, RejectedQueriesDoNotAllocate) {
  const auto& g = this->graph_;
  const std::string too_long(300, 'x');  // made before arming
  const PoseSpec empty_name = PoseSpec::Of("").RelativeTo("b");
  ExpectNoAllocation("invalid_name (empty)", ErrorCode::kInvalidName,
                     [&] { return CodeOf(g.GetPose(empty_name)); });
  const PoseSpec long_name = PoseSpec::Of(too_long).RelativeTo("b");
  ExpectNoAllocation("invalid_name (300 bytes)", ErrorCode::kInvalidName,
                     [&] { return CodeOf(g.GetPosition(long_name)); });
  const PoseSpec ghost = PoseSpec::Of("ghost").RelativeTo("b");
  ExpectNoAllocation("unknown_frame", ErrorCode::kUnknownFrame,
                     [&] { return CodeOf(g.GetPose(ghost)); });
  const TwistSpec nowhere = TwistSpec::Of("c").RelativeTo("Nowhere").ExpressedIn("c");
  ExpectNoAllocation("unknown_body", ErrorCode::kUnknownBody,
                     [&] { return CodeOf(g.GetTwist(nowhere)); });
  const PoseSpec mismatch = PoseSpec::Of("f1", "C").RelativeTo("b");
  ExpectNoAllocation("frame_body_mismatch", ErrorCode::kFrameBodyMismatch,
                     [&] { return CodeOf(g.GetOrientation(mismatch)); });
  const PoseSpec lone = PoseSpec::Of("l").RelativeTo("b");
  ExpectNoAllocation("no_pose_path", ErrorCode::kNoPosePath,
                     [&] { return CodeOf(g.GetPose(lone)); });
  const TwistSpec no_twist = TwistSpec::Of("l").RelativeTo("B").ExpressedIn("l");
  ExpectNoAllocation("no_twist_path", ErrorCode::kNoTwistPath,
                     [&] { return CodeOf(g.GetTwist(no_twist)); });
  if (this->kHomogeneous) {
    const PoseSpec in_c = PoseSpec::Of("f1").RelativeTo("o2").ExpressedIn("c");
    ExpectNoAllocation("representation_constraint", ErrorCode::kRepresentationConstraint,
                       [&] { return CodeOf(g.GetPose(in_c)); });
  }
}

TYPED_TEST(SceneGraphNoAllocation, QueriesBySemanticsIdsDoNotAllocate) {
  const auto& g = this->graph_;
  const semantics::PoseSemantics pose{this->P("f1"), this->O("f1"),  this->Bd("O1"), this->P("o2"),
                                      this->O("o2"), this->Bd("O2"), this->O("o2")};
  ExpectNoAllocation("GetPose(PoseSemantics)", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetPose(pose)); });
  const semantics::PositionSemantics position{this->P("f1"), this->Bd("O1"), this->P("e"),
                                              this->Bd("E"), this->O("c")};
  ExpectNoAllocation("GetPosition(PositionSemantics)", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetPosition(position)); });
  const semantics::OrientationSemantics orientation{this->O("f1"), this->Bd("O1"), this->O("b"),
                                                    this->Bd("B"), this->O("b")};
  ExpectNoAllocation("GetOrientation(OrientationSemantics)", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetOrientation(orientation)); });
  const semantics::TwistSemantics twist{this->P("f1"), this->Bd("O1"), this->Bd("O2"),
                                        this->O("o2")};
  ExpectNoAllocation("GetTwist(TwistSemantics)", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetTwist(twist)); });
  // Rejected: a frame in another tree, and an id that names no frame (a body's name).
  const semantics::PoseSemantics lone{this->P("l"), this->O("l"),  this->Bd("L"), this->P("b"),
                                      this->O("b"), this->Bd("B"), this->O("b")};
  ExpectNoAllocation("GetPose(PoseSemantics) no_pose_path", ErrorCode::kNoPosePath,
                     [&] { return CodeOf(g.GetPose(lone)); });
  const semantics::TwistSemantics not_a_frame{this->P("B"), this->Bd("B"), this->Bd("E"),
                                              this->O("b")};
  ExpectNoAllocation("GetTwist(TwistSemantics) unknown_frame", ErrorCode::kUnknownFrame,
                     [&] { return CodeOf(g.GetTwist(not_a_frame)); });
}

TYPED_TEST(SceneGraphNoAllocation, UpdatesThroughHandlesAndCompiledQueriesDoNotAllocate) {
  auto& g = this->graph_;
  // Build time (allocates): handles of the two cross-body joints and two twist edges, and
  // compiled queries of every kind.
  auto X_CO1 = g.FindPoseEdge("o1", "c");
  auto X_BE = g.FindPoseEdge("e", "b");
  auto V_C_O1 = g.FindTwistEdge("o1", "C");
  auto V_B_E = g.FindTwistEdge("e", "B");
  ASSERT_TRUE(X_CO1 && X_BE && V_C_O1 && V_B_E);
  auto pose = g.CompilePose(PoseSpec::Of("f1", "O1").RelativeTo("o2", "O2"));
  auto position = g.CompilePosition(PoseSpec::Of("f1").RelativeTo("e").ExpressedIn("c"));
  auto orientation = g.CompileOrientation(PoseSpec::Of("f1").RelativeTo("o2"));
  auto twist = g.CompileTwist(TwistSpec::Of("f1", "O1").RelativeTo("O2").ExpressedIn("o2"));
  ASSERT_TRUE(pose && position && orientation && twist);
  std::vector<Eigen::Quaterniond> q(kRepetitions);
  std::vector<Eigen::Matrix3d> R(kRepetitions);
  for (int i = 0; i < kRepetitions; ++i) {
    q[static_cast<std::size_t>(i)] =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * i, Eigen::Vector3d::UnitZ()));
    R[static_cast<std::size_t>(i)] =
        Eigen::AngleAxisd(-0.02 * i, Eigen::Vector3d::UnitX()).toRotationMatrix();
  }
  // The control loop: new joint values, then the compiled queries.
  std::size_t allocations = 0;
  int failures = 0;
  typename TypeParam::PoseCoords X;
  typename TypeParam::Rotation M;
  Eigen::Vector3d p, v, w;
  {
    CountAllocations counting;
    for (int i = 0; i < kRepetitions; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const Eigen::Vector3d p_k(0.001 * i, 0.3, 2.0);
      failures += g.SetPose(*X_CO1, q[k], p_k) != ErrorCode::kOk;
      failures += g.SetPose(*X_BE, R[k], p_k) != ErrorCode::kOk;
      failures += g.SetTwist(*V_C_O1, p_k, Eigen::Vector3d(0.1, 0.0, 0.01 * i)) != ErrorCode::kOk;
      failures += g.SetTwist(*V_B_E, -p_k, Eigen::Vector3d(0.0, 0.2, 0.0)) != ErrorCode::kOk;
      failures += pose->Evaluate(X) != ErrorCode::kOk;
      failures += position->Evaluate(p) != ErrorCode::kOk;
      failures += orientation->Evaluate(M) != ErrorCode::kOk;
      failures += twist->Evaluate(v, w) != ErrorCode::kOk;
    }
    allocations = counting.count();
  }
  EXPECT_EQ(failures, 0);
  EXPECT_EQ(allocations, 0u) << "SetPose/SetTwist/Evaluate loop: " << allocations << " allocations";
  // The updates reached the graph: the one-shot query sees the last joint value.
  auto p_CO1 = g.GetPosition(PoseSpec::Of("o1").RelativeTo("c"));
  ASSERT_TRUE(p_CO1);
  EXPECT_NEAR(p_CO1->value.x(), 0.001 * (kRepetitions - 1), 1e-12);
  // One-shot queries interleaved with handle updates allocate nothing either.
  ExpectNoAllocation("SetPose + GetPose", ErrorCode::kOk, [&] {
    const ErrorCode set = g.SetPose(*X_BE, q[3], Eigen::Vector3d(0.3, -0.2, 0.9));
    return set != ErrorCode::kOk ? set : CodeOf(g.GetPose(PoseSpec::Of("o2").RelativeTo("c")));
  });
  // A refused update's detail (update_error.h) costs no allocation either.
  UpdateError why;
  ExpectNoAllocation("SetPose refused, with its detail", ErrorCode::kInvalidNumber,
                     [&] { return g.SetPose(*X_BE, q[3], Eigen::Vector3d(0, 2e12, 0), &why); });
  ExpectNoAllocation("SetTwist refused, with its detail", ErrorCode::kInvalidNumber, [&] {
    return g.SetTwist(*V_B_E, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, std::nan("")), &why);
  });
  // The unchecked fast path allocates nothing either, and stores exactly what it is given.
  const Eigen::Quaterniond q_unit = q[2].normalized();
  ExpectNoAllocation("SetPoseUnchecked", ErrorCode::kOk, [&] {
    return g.SetPoseUnchecked(*X_BE, q_unit, Eigen::Vector3d(0.5, 0.25, -1));
  });
  auto X_BE_now = g.GetPose(PoseSpec::Of("e").RelativeTo("b"));
  ASSERT_TRUE(X_BE_now);
  EXPECT_LT(
      (TypeParam::ToMatrix(TypeParam::RotationOf(X_BE_now->value)) - q_unit.toRotationMatrix())
          .norm(),
      1e-12);
  EXPECT_LT((TypeParam::TranslationOf(X_BE_now->value) - Eigen::Vector3d(0.5, 0.25, -1)).norm(),
            1e-15);
}

// Reserve(frames, bodies) makes a build of known size reallocate none of the graph's arrays:
// building the same 2,000-frame chain allocates far less often after Reserve than without it.
TYPED_TEST(SceneGraphNoAllocation, ReserveAvoidsRegrowingWhileBuilding) {
  constexpr int kFrames = 2000;
  std::vector<std::string> frames, bodies;
  for (int i = 0; i <= kFrames; ++i) {
    frames.push_back("f" + std::to_string(i));
    bodies.push_back("B" + std::to_string(i));
  }
  const auto build = [&](bool reserve) {
    SceneGraph<TypeParam> g;
    std::size_t allocations = 0;
    {
      CountAllocations counting;
      if (reserve) g.Reserve(kFrames + 1, kFrames + 1);
      for (int i = 1; i <= kFrames; ++i) {
        auto r =
            g.AddPose(PoseSpec::Of(frames[i], bodies[i]).RelativeTo(frames[i - 1], bodies[i - 1]),
                      Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0));
        if (!r) ADD_FAILURE() << r.error().message;
      }
      allocations = counting.count();
    }
    auto X = g.GetPosition(PoseSpec::Of(frames[kFrames]).RelativeTo(frames[0]));
    EXPECT_TRUE(X && std::abs(X->value.x() - kFrames) < 1e-9);
    return allocations;
  };
  const std::size_t grown = build(false), reserved = build(true);
  // Without Reserve every array doubles about log2(2000) = 11 times; with it, only the name
  // arena's blocks and the tree record's body map (which Reserve does not size) allocate.
  EXPECT_LT(reserved * 2, grown) << "reserved " << reserved << ", grown " << grown;
  std::printf("allocations building %d frames: %zu grown, %zu after Reserve\n", kFrames, grown,
              reserved);
}

TYPED_TEST(SceneGraphNoAllocation, ValueUpdatesThroughAddPoseAndAddTwistAreMeasured) {
  auto& g = this->graph_;
  const PoseSpec joint = PoseSpec::Of("e", "E").RelativeTo("b", "B");
  const TwistSpec joint_velocity = TwistSpec::Of("e", "E").RelativeTo("B").ExpressedIn("e");
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()));
  std::size_t allocations = 0;
  int failures = 0;
  {
    CountAllocations counting;
    for (int i = 0; i < kRepetitions; ++i) {
      failures += !g.AddPose(joint, q, Eigen::Vector3d(0.3, -0.2, 0.001 * i));
      failures +=
          !g.AddTwist(joint_velocity, Eigen::Vector3d(0.0, 0.01 * i, 0.0), Eigen::Vector3d::Zero());
    }
    allocations = counting.count();
  }
  EXPECT_EQ(failures, 0);
  EXPECT_EQ(g.num_pose_edges(), 5u);
  EXPECT_EQ(g.num_twist_edges(), 4u);
  // TODO(semgraph): AddPose/AddTwist on an existing edge format their `what` message string up
  // front, so every update allocates. The allocation-free update path is the handle API,
  // SceneGraph::FindPoseEdge/SetPose and FindTwistEdge/SetTwist (covered above); when AddPose
  // and AddTwist build the message only on rejection, turn this measurement into an assertion.
  if (allocations > 0) {
    GTEST_SKIP() << "AddPose/AddTwist value updates allocate (" << allocations << " allocations in "
                 << 2 * kRepetitions << " calls: the message string is built up front); "
                 << "control loops must use FindPoseEdge/SetPose and FindTwistEdge/SetTwist";
  }
  EXPECT_EQ(allocations, 0u);
}

// ====================================================================== a longer random chain

// RigidBodyScene(seed, 6 bodies, 2..3 frames each), linked as a chain of first frames with the
// other frames of each body hung under its first frame:
//
//   {first of B0}
//    +-- {other frames of B0}       (constant)
//    +-- {first of B1}              B0 ~> {first of B1}
//          +-- {other frames of B1}
//          +-- {first of B2}        B1 ~> {first of B2}
//                +-- ...
template <class G>
void BuildChain(G& g, const RigidBodyScene& scene) {
  int previous_first = -1;  // first frame of the previous body
  int first = -1;           // first frame of the current body (frames of a body are consecutive)
  for (int f = 0; f < scene.num_frames(); ++f) {
    const int k = scene.BodyOf(f);
    const bool starts_body = f == 0 || scene.BodyOf(f - 1) != k;
    if (starts_body) {
      previous_first = first;
      first = f;
    }
    if (f == 0) {
      ASSERT_TRUE(g.AddBody(scene.body_name(k)));
      ASSERT_TRUE(g.AddFrame(scene.frame_name(f), scene.body_name(k)));
      continue;
    }
    const int tail = starts_body ? previous_first : first;
    const auto r =
        g.AddPose(PoseSpec::Of(scene.frame_name(f), scene.body_name(k))
                      .RelativeTo(scene.frame_name(tail), scene.body_name(scene.BodyOf(tail))),
                  Eigen::Matrix3d(scene.Rotation(tail, f)), scene.Position(f, tail, tail));
    ASSERT_TRUE(r) << r.error().message;
    if (starts_body) {
      const int D = scene.BodyOf(tail);
      const auto tw = g.AddTwist(TwistSpec::Of(scene.frame_name(f), scene.body_name(k))
                                     .RelativeTo(scene.body_name(D))
                                     .ExpressedIn(scene.frame_name(f)),
                                 scene.LinearVelocity(f, k, D, f), scene.AngularVelocity(k, D, f));
      ASSERT_TRUE(tw) << tw.error().message;
    }
  }
}

TYPED_TEST(SceneGraphNoAllocation, EveryQueryKindOnALongerChainDoesNotAllocate) {
  constexpr std::uint64_t kSeed = 424242;
  SCOPED_TRACE("seed " + std::to_string(kSeed));
  RigidBodyScene scene(kSeed, 6, 2, 3);
  SceneGraph<TypeParam> g;
  BuildChain(g, scene);
  ASSERT_TRUE(CheckInvariants(g).empty()) << CheckInvariants(g);
  ASSERT_EQ(g.num_pose_edges(), static_cast<std::size_t>(scene.num_frames() - 1));
  // Every (a, b) pair, with r = b (all backends) and r = a (quaternion: a value; homogeneous:
  // representation_constraint for poses and orientations); every twist between bodies.
  std::size_t allocations = 0;
  int ok = 0, rejected = 0;
  std::vector<std::string> names;
  for (int f = 0; f < scene.num_frames(); ++f) names.push_back(scene.frame_name(f));
  {
    CountAllocations counting;
    for (int a = 0; a < scene.num_frames(); ++a) {
      for (int b = 0; b < scene.num_frames(); ++b) {
        const std::string_view A = names[static_cast<std::size_t>(a)],
                               Bn = names[static_cast<std::size_t>(b)];
        for (std::string_view r : {Bn, A}) {
          const PoseSpec s = PoseSpec::Of(A).RelativeTo(Bn).ExpressedIn(r);
          for (ErrorCode c :
               {CodeOf(g.GetPose(s)), CodeOf(g.GetPosition(s)), CodeOf(g.GetOrientation(s))}) {
            ++(c == ErrorCode::kOk ? ok : rejected);
          }
          const TwistSpec t =
              TwistSpec::Of(A).RelativeTo(scene.body_name(scene.BodyOf(b))).ExpressedIn(r);
          for (ErrorCode c : {CodeOf(g.GetTwist(t)), CodeOf(g.GetLinearVelocity(t))}) {
            ++(c == ErrorCode::kOk ? ok : rejected);
          }
        }
      }
    }
    allocations = counting.count();
  }
  EXPECT_EQ(allocations, 0u) << allocations << " allocations in " << ok + rejected << " queries";
  EXPECT_GT(ok, 0);
  if constexpr (std::is_same_v<TypeParam, coord::HomogeneousBackend>) {
    EXPECT_GT(rejected, 0);
  } else {
    EXPECT_EQ(rejected, 0);
  }
}

}  // namespace
}  // namespace semgraph::core
