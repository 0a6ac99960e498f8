// SceneGraph on seeded random scenes, on both backends (typed tests), checked against an
// independent ground truth.
//
// Method. A RigidBodyScene (tests/support/rigid_body_scene.h) holds K = 3..8 bodies with
// absolute poses and twists in a world frame W and 2..4 frames bolted to each body at fixed
// offsets. A naive Model (parent array, twist parents, existence flags; every rule of
// docs/rules.md §2-3 written out by walking the whole model) proposes only operations
// that the spec accepts, built from the world quantities: pose edges with random directions
// and parents, same-body (constant) and cross-body, some in non-edge form (quaternion
// backend), given as a quaternion (sometimes -q, sometimes off-unit within tolerance) or as a
// matrix; twist edges as screw twists or in another coordinate frame of the head's pose tree.
// Every add must be accepted; after each, CheckInvariants() must be empty and the graph's
// topology must equal the model's. Then hundreds of random queries of every kind (pose,
// position, orientation, twist, linear and angular velocity; by name and by semantics ids)
// are compared with values computed directly from the world, and queries the spec rejects
// (no_pose_path, no_twist_path, unknown_frame, and representation_constraint for the
// homogeneous backend) must fail with exactly that code. A second test removes and re-adds
// edges (grasps: a head re-hung under another parent), moves the bodies and feeds the new
// values through updates of existing edges, and checks the queries after every step.
//
// Seeds are fixed (kFirstSeed + i) and printed in every failure (SCOPED_TRACE).
//
// Monogram legend (indices are RigidBodyScene frames/bodies; "f<i>" / "B<k>" in the graph):
//   X_FE_R     pose of (e,[a])|C wrt (f,[b])|D expressed in [r]: value (O_BA_R, p_FE_R)
//   p_FE_R     position of point e wrt point f, in [r]
//   O_BA_R     orientation operator carrying [b] onto [a], in [r] (R_BA when r = b)
//   V_DCe_R   twist of body C wrt body D, reference point e, in [r]: (v_DCe_R, w_DC_R)
//   t -> h     a pose edge (tail t, head h); D ~> h a twist edge (body D, head frame h)
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <initializer_list>
#include <ostream>
#include <random>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "semgraph/base/error_code.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/rigid_body_scene.h"
#include "support/tolerance.h"
#include "support/world_scene.h"

namespace semgraph::semantics {
// Readable ErrorCode in gtest failure messages (found by ADL).
void PrintTo(ErrorCode code, std::ostream* os) { *os << ToString(code); }
}  // namespace semgraph::semantics

namespace semgraph::core {
namespace {

using semgraph::testing::Near;
using semgraph::testing::RigidBodyScene;
using semgraph::testing::UniformIndex;
using semgraph::testing::UnitDouble;

constexpr std::uint64_t kFirstSeed = 20130611;  // IROS 2013
constexpr int kSeeds = 12;
constexpr int kQueriesPerKind = 150;  // per seed, after the build
constexpr int kQueriesPerKindPerStep = 20;
constexpr int kChangeSteps = 16;
constexpr int kIllegalAttempts = 60;  // per seed, after the build
constexpr int kIllegalAttemptsPerStep = 10;
// Values are O(1..10) and paths at most ~30 edges: rounding stays far below this.
constexpr double kTol = 1e-9;

// ====================================================================== the naive model

/// The topology the spec predicts, on RigidBodyScene indices; every rule by brute force.
class Model {
 public:
  explicit Model(const RigidBodyScene& scene)
      : scene_(scene),
        parent_(static_cast<std::size_t>(scene.num_frames()), -1),
        twist_tail_(static_cast<std::size_t>(scene.num_frames()), -1),
        frame_exists_(static_cast<std::size_t>(scene.num_frames()), false),
        body_exists_(static_cast<std::size_t>(scene.num_bodies()), false) {}

  int parent(int f) const { return parent_[I(f)]; }
  int twist_tail(int f) const { return twist_tail_[I(f)]; }
  bool frame_exists(int f) const { return frame_exists_[I(f)]; }
  bool body_exists(int k) const { return body_exists_[I(k)]; }
  int Body(int f) const { return scene_.BodyOf(f); }

  void CreateBody(int k) { body_exists_[I(k)] = true; }
  void CreateFrame(int f) {
    frame_exists_[I(f)] = true;
    body_exists_[I(Body(f))] = true;
  }
  void LinkPose(int t, int h) {
    CreateFrame(t);
    CreateFrame(h);
    parent_[I(h)] = t;
  }
  void CutPose(int h) { parent_[I(h)] = -1; }
  void LinkTwist(int D, int h) {
    CreateFrame(h);
    CreateBody(D);
    twist_tail_[I(h)] = D;
  }
  void CutTwist(int h) { twist_tail_[I(h)] = -1; }

  int Root(int f) const {
    while (parent_[I(f)] >= 0) f = parent_[I(f)];
    return f;
  }
  bool Same(int x, int y) const { return Root(x) == Root(y); }
  std::vector<int> Tree(int x) const {
    std::vector<int> out;
    const int root = Root(x);
    for (int f = 0; f < scene_.num_frames(); ++f) {
      if (Root(f) == root) out.push_back(f);
    }
    return out;
  }
  std::vector<int> TreeFramesOn(int x, int body) const {
    std::vector<int> out;
    for (int f : Tree(x)) {
      if (Body(f) == body) out.push_back(f);
    }
    return out;
  }
  std::vector<int> Bodies(int x) const {
    std::vector<int> out;
    for (int f : Tree(x)) {
      if (std::find(out.begin(), out.end(), Body(f)) == out.end()) out.push_back(Body(f));
    }
    return out;
  }
  std::vector<std::pair<int, int>> PoseEdges() const {
    std::vector<std::pair<int, int>> out;
    for (int h = 0; h < scene_.num_frames(); ++h) {
      if (parent_[I(h)] >= 0) out.emplace_back(parent_[I(h)], h);
    }
    return out;
  }
  std::vector<std::pair<int, int>> TwistEdges() const {
    std::vector<std::pair<int, int>> out;
    for (int h = 0; h < scene_.num_frames(); ++h) {
      if (twist_tail_[I(h)] >= 0) out.emplace_back(twist_tail_[I(h)], h);
    }
    return out;
  }

  /// TG of the pose trees of x and y (x == y: one tree), with one optional extra edge D–H:
  /// is it a forest (no cycle, no parallel edge)? Union-find over bodies.
  bool TwistGraphIsForest(int x, int y, int extra_D = -1, int extra_H = -1) const {
    std::vector<int> uf(static_cast<std::size_t>(scene_.num_bodies()));
    for (std::size_t i = 0; i < uf.size(); ++i) uf[i] = static_cast<int>(i);
    const auto find = [&](int k) {
      while (uf[I(k)] != k) k = uf[I(k)];
      return k;
    };
    const auto link = [&](int D, int H) {
      const int a = find(D), b = find(H);
      if (a == b) return false;
      uf[I(a)] = b;
      return true;
    };
    const int rx = Root(x), ry = Root(y);
    for (int h = 0; h < scene_.num_frames(); ++h) {
      const int r = Root(h);
      if (twist_tail_[I(h)] >= 0 && (r == rx || r == ry) && !link(twist_tail_[I(h)], Body(h))) {
        return false;
      }
    }
    return extra_D < 0 || link(extra_D, extra_H);
  }
  /// C and D joined by twist edges whose heads are in the pose tree of x.
  bool TwistConnected(int x, int C, int D) const {
    if (C == D) return true;
    return !TwistGraphIsForest(x, x, C, D);
  }

  /// Spec §2 (P1, P2, P3) and §3 (W4) for the pose edge t -> h.
  bool CanAddPose(int t, int h) const {
    if (t == h || parent_[I(h)] >= 0 || Same(t, h)) return false;
    const std::vector<int> bt = Bodies(t), bh = Bodies(h);
    for (int k : bt) {
      const bool shared = std::find(bh.begin(), bh.end(), k) != bh.end();
      const bool allowed = Body(t) == Body(h) && k == Body(t);
      if (shared && !allowed) return false;
    }
    return TwistGraphIsForest(t, h);
  }
  /// Spec §3 (W1, W2, W3) for the twist edge D ~> h.
  bool CanAddTwist(int D, int h) const {
    return twist_tail_[I(h)] < 0 && D != Body(h) && !TwistConnected(h, D, Body(h));
  }

 private:
  static std::size_t I(int i) { return static_cast<std::size_t>(i); }

  const RigidBodyScene& scene_;
  std::vector<int> parent_;
  std::vector<int> twist_tail_;
  std::vector<bool> frame_exists_;
  std::vector<bool> body_exists_;
};

// ====================================================================== the harness

/// What a test exercised (summed over seeds), so it can prove it checked something.
struct Tally {
  int pose = 0, position = 0, orientation = 0, twist = 0, linear = 0, angular = 0;
  int non_edge_form_queries = 0;  ///< pose values checked with e != a, f != b or r != b
  int no_pose_path = 0, no_twist_path = 0, representation = 0, unknown_frame = 0;
  int non_edge_adds = 0, converted_twists = 0, same_body_edges = 0, cross_body_edges = 0;
  int removals = 0, regrasps = 0, updates = 0, constant_no_ops = 0;
  int illegal_attempts = 0;
  int illegal_by_code[base::kNumErrorCodes] = {};  ///< rejections checked, by code
};

template <class B>
class Harness {
 public:
  static constexpr bool kHomogeneous = std::is_same_v<B, coord::HomogeneousBackend>;

  Harness(std::uint64_t seed, Tally& tally)
      : scene_(seed, 3 + static_cast<int>(seed % 6), 2, 4), model_(scene_), tally_(tally) {
    for (int k = 0; k < scene_.num_bodies(); ++k) frames_on_.emplace_back();
    for (int f = 0; f < scene_.num_frames(); ++f) frames_on_[I(scene_.BodyOf(f))].push_back(f);
  }

  SceneGraph<B>& graph() { return graph_; }
  const Model& model() const { return model_; }
  RigidBodyScene& scene() { return scene_; }
  std::mt19937_64& rng() { return scene_.rng(); }
  bool Chance(double p) { return UnitDouble(rng()) < p; }
  int Pick(const std::vector<int>& v) {
    return v[I(UniformIndex(rng(), static_cast<int>(v.size())))];
  }

  // ------------------------------------------------------------------ building

  /// Some bodies and frames exist before any edge names them (AddBody / AddFrame); the rest
  /// are created by the adds from the semantics.
  void PreCreateSomeNodes() {
    for (int k = 0; k < scene_.num_bodies(); ++k) {
      if (!Chance(0.4)) continue;
      ExpectAccepted(graph_.AddBody(scene_.body_name(k)), "AddBody " + scene_.body_name(k));
      model_.CreateBody(k);
    }
    for (int f = 0; f < scene_.num_frames(); ++f) {
      if (!Chance(0.3)) continue;
      const int k = scene_.BodyOf(f);
      if (!model_.body_exists(k)) {
        ExpectAccepted(graph_.AddBody(scene_.body_name(k)), "AddBody " + scene_.body_name(k));
        model_.CreateBody(k);
      }
      ExpectAccepted(graph_.AddFrame(scene_.frame_name(f), scene_.body_name(k)),
                     "AddFrame " + scene_.frame_name(f));
      model_.CreateFrame(f);
    }
  }

  std::vector<std::pair<int, int>> PoseCandidates() const {
    std::vector<std::pair<int, int>> out;
    for (int t = 0; t < scene_.num_frames(); ++t) {
      for (int h = 0; h < scene_.num_frames(); ++h) {
        if (model_.CanAddPose(t, h)) out.emplace_back(t, h);
      }
    }
    return out;
  }
  std::vector<std::pair<int, int>> TwistCandidates() const {
    std::vector<std::pair<int, int>> out;
    for (int D = 0; D < scene_.num_bodies(); ++D) {
      for (int h = 0; h < scene_.num_frames(); ++h) {
        if (model_.CanAddTwist(D, h)) out.emplace_back(D, h);
      }
    }
    return out;
  }

  /// Adds pose and twist edges proposed by the model until no pose edge can be added (a
  /// maximal forest: spanning where P3 allows) or, for a third of the scenes, half the frames
  /// are linked (several trees, frames never named), and the twist budget is spent.
  void BuildRandomScene() {
    PreCreateSomeNodes();
    int twist_budget = scene_.num_bodies() + 2;
    const int max_pose_edges = Chance(0.3) ? scene_.num_frames() / 2 : scene_.num_frames();
    for (;;) {
      const auto poses = static_cast<int>(model_.PoseEdges().size()) < max_pose_edges
                             ? PoseCandidates()
                             : std::vector<std::pair<int, int>>{};
      const auto twists = twist_budget > 0 ? TwistCandidates() : std::vector<std::pair<int, int>>{};
      if (poses.empty() && twists.empty()) break;
      if (!poses.empty() && (twists.empty() || Chance(0.75))) {
        AddPoseEdge(PickPreferringSameBody(poses), /*update_after_move=*/false);
      } else {
        const auto [D, h] = twists[I(UniformIndex(rng(), static_cast<int>(twists.size())))];
        AddTwistEdge(D, h, /*any_frame_of_tree=*/true);
        --twist_budget;
      }
    }
  }

  std::pair<int, int> PickPreferringSameBody(const std::vector<std::pair<int, int>>& candidates) {
    std::vector<std::pair<int, int>> same;
    for (const auto& c : candidates) {
      if (scene_.BodyOf(c.first) == scene_.BodyOf(c.second)) same.push_back(c);
    }
    const auto& from = !same.empty() && Chance(0.5) ? same : candidates;
    return from[I(UniformIndex(rng(), static_cast<int>(from.size())))];
  }

  /// Adds (or, when the edge exists, updates) the pose edge t -> h with the world's value,
  /// in edge form or, for the quaternion backend, sometimes as PoseCoord((e,[h])|H, (f,[t])|T,
  /// [r]). After a Move, [r] is restricted to frames of T in t's tree: the conversion then
  /// uses only constant same-body relations, never a cross-body edge that still holds the old
  /// value.
  void AddPoseEdge(std::pair<int, int> edge, bool update_after_move) {
    const auto [t, h] = edge;
    const int T = scene_.BodyOf(t), H = scene_.BodyOf(h);
    int e = h, f = t, r = t;
    if (!kHomogeneous && Chance(0.35)) {
      e = Pick(model_.TreeFramesOn(h, H));
      f = Pick(model_.TreeFramesOn(t, T));
      r = update_after_move ? Pick(model_.TreeFramesOn(t, T)) : Pick(model_.Tree(t));
    }
    PoseSpec spec = PoseSpec::Of(scene_.frame_name(h), BodyNameIfNeeded(h))
                        .RelativeTo(scene_.frame_name(t), BodyNameIfNeeded(t));
    spec.AtPoint(scene_.frame_name(e)).RelativeToPoint(scene_.frame_name(f));
    spec.ExpressedIn(scene_.frame_name(r));
    const Eigen::Matrix3d O_TH_R = scene_.OrientationOperator(h, t, r);
    const Eigen::Vector3d p_FE_R = scene_.Position(e, f, r);
    const std::string what = "AddPose " + scene_.frame_name(t) + " -> " + scene_.frame_name(h) +
                             " given at (" + scene_.frame_name(e) + ", " + scene_.frame_name(f) +
                             ", [" + scene_.frame_name(r) + "])";
    const bool exists = model_.parent(h) == t;
    const auto stored_before = exists ? graph_.pose_value(graph_.FindFrame(scene_.frame_name(h)))
                                      : typename B::PoseCoords{};
    BuildResult result = Chance(0.5) ? graph_.AddPose(spec, O_TH_R, p_FE_R)
                                     : graph_.AddPose(spec, JitteredQuaternion(O_TH_R), p_FE_R);
    ExpectAccepted(std::move(result), what);
    if (e != h || f != t || r != t) ++tally_.non_edge_adds;
    if (exists && T == H) {
      // P4: the same value again is a no-op that keeps the stored value bit for bit.
      const auto stored_after = graph_.pose_value(graph_.FindFrame(scene_.frame_name(h)));
      EXPECT_EQ(B::ToMatrix(B::RotationOf(stored_after)), B::ToMatrix(B::RotationOf(stored_before)))
          << what;
      EXPECT_EQ(B::TranslationOf(stored_after), B::TranslationOf(stored_before)) << what;
      ++tally_.constant_no_ops;
    } else if (exists) {
      ++tally_.updates;
    } else {
      ++(T == H ? tally_.same_body_edges : tally_.cross_body_edges);
    }
    model_.LinkPose(t, h);
    ExpectModelMatchesGraph(what);
  }

  /// Adds (or updates) the twist edge D ~> h with the world's screw twist at h, given in [h]
  /// or, sometimes, in another frame [r] of h's pose tree (converted by the graph).
  void AddTwistEdge(int D, int h, bool any_frame_of_tree) {
    const int H = scene_.BodyOf(h);
    int r = h;
    if (any_frame_of_tree && model_.frame_exists(h) && Chance(0.5)) r = Pick(model_.Tree(h));
    const TwistSpec spec = TwistSpec::Of(scene_.frame_name(h), BodyNameIfNeeded(h))
                               .RelativeTo(scene_.body_name(D))
                               .ExpressedIn(scene_.frame_name(r));
    const std::string what = "AddTwist " + scene_.body_name(D) + " ~> " + scene_.frame_name(h) +
                             " in [" + scene_.frame_name(r) + "]";
    const bool exists = model_.twist_tail(h) == D;
    ExpectAccepted(
        graph_.AddTwist(spec, scene_.LinearVelocity(h, H, D, r), scene_.AngularVelocity(H, D, r)),
        what);
    if (r != h) ++tally_.converted_twists;
    if (exists) ++tally_.updates;
    model_.LinkTwist(D, h);
    ExpectModelMatchesGraph(what);
  }

  /// n attempts at edges the model forbids, each with the code the spec's order predicts; the
  /// graph must be left exactly as it was (Dump) and the message must name the head frame.
  /// This checks the graph's incremental bookkeeping (union-find, body counts, TG forests,
  /// rebuilt after removals) against the model's brute force in the rejecting direction.
  void AttemptIllegalEdges(int n) {
    for (int i = 0; i < n; ++i) {
      if (Chance(0.6)) {
        const int t = RandomFrame(), h = RandomFrame();
        if (model_.parent(h) == t || model_.CanAddPose(t, h)) continue;  // updates, legal adds
        ErrorCode expected = ErrorCode::kTwistMergeConflict;             // the last rule left
        if (t == h) {
          expected = ErrorCode::kSelfEdge;
        } else if (model_.parent(h) >= 0) {
          expected = ErrorCode::kMultiplePoseParents;
        } else if (model_.Same(t, h)) {
          expected = ErrorCode::kPoseCycle;
        } else if (!BodySetsAllow(t, h)) {
          expected = ErrorCode::kDuplicatePosePath;
        }
        const std::string before = Dump(graph_);
        const auto result = graph_.AddPose(
            PoseSpec::Of(Name(h), BodyNameIfNeeded(h)).RelativeTo(Name(t), BodyNameIfNeeded(t)),
            scene_.Rotation(t, h), scene_.Position(h, t, t));
        const std::string what = "illegal AddPose " + Name(t) + " -> " + Name(h);
        ExpectRejected(result, expected, "{" + Name(h) + "}", before, what);
      } else {
        const int D = RandomBody(), h = RandomFrame();
        if (model_.twist_tail(h) == D || model_.CanAddTwist(D, h)) continue;
        ErrorCode expected = ErrorCode::kDuplicateTwistPath;
        if (D == scene_.BodyOf(h)) {
          expected = ErrorCode::kTwistSameBody;
        } else if (model_.twist_tail(h) >= 0) {
          expected = ErrorCode::kMultipleTwistParents;
        }
        const std::string before = Dump(graph_);
        const int H = scene_.BodyOf(h);
        const auto result =
            graph_.AddTwist(TwistSpec::Of(Name(h), BodyNameIfNeeded(h))
                                .RelativeTo(scene_.body_name(D))
                                .ExpressedIn(Name(h)),
                            scene_.LinearVelocity(h, H, D, h), scene_.AngularVelocity(H, D, h));
        const std::string what = "illegal AddTwist " + scene_.body_name(D) + " ~> " + Name(h);
        ExpectRejected(result, expected, "twist of " + Name(h), before, what);
      }
      ++tally_.illegal_attempts;
    }
  }

  /// P3 alone (the model's CanAddPose also checks P1, P2 and W4).
  bool BodySetsAllow(int t, int h) const {
    const std::vector<int> bt = model_.Bodies(t), bh = model_.Bodies(h);
    for (int k : bt) {
      const bool shared = std::find(bh.begin(), bh.end(), k) != bh.end();
      if (shared && !(scene_.BodyOf(t) == scene_.BodyOf(h) && k == scene_.BodyOf(t))) return false;
    }
    return true;
  }

  void ExpectRejected(const BuildResult& result, ErrorCode expected, const std::string& names_head,
                      const std::string& before, const std::string& what) {
    if (result) {
      ADD_FAILURE() << what << " accepted; expected " << base::ToString(expected);
      return;
    }
    EXPECT_EQ(result.error().code, expected) << what << ": " << result.error().message;
    ++tally_.illegal_by_code[static_cast<int>(expected)];
    EXPECT_NE(result.error().message.find(names_head), std::string::npos)
        << what << ": " << result.error().message;
    EXPECT_EQ(Dump(graph_), before) << what << " changed the graph";
  }

  void RemovePoseEdge(int t, int h) {
    const std::string what = "RemovePose " + scene_.frame_name(t) + " -> " + scene_.frame_name(h);
    ExpectAccepted(graph_.RemovePose(scene_.frame_name(h), scene_.frame_name(t)), what);
    model_.CutPose(h);
    ++tally_.removals;
    ExpectModelMatchesGraph(what);
  }

  void RemoveTwistEdge(int D, int h) {
    const std::string what = "RemoveTwist " + scene_.body_name(D) + " ~> " + scene_.frame_name(h);
    ExpectAccepted(graph_.RemoveTwist(scene_.frame_name(h), scene_.body_name(D)), what);
    model_.CutTwist(h);
    ++tally_.removals;
    ExpectModelMatchesGraph(what);
  }

  // ------------------------------------------------------------------ checks of the graph

  void ExpectAccepted(BuildResult result, const std::string& what) {
    ASSERT_TRUE(result) << what << " rejected: " << result.error().message;
    const std::string broken = CheckInvariants(graph_);
    EXPECT_TRUE(broken.empty()) << "after " << what << ":\n" << broken;
  }

  /// Nodes, pose parents and twist parents of the graph equal the model's.
  void ExpectModelMatchesGraph(const std::string& what) {
    std::size_t pose_edges = 0, twist_edges = 0;
    for (int f = 0; f < scene_.num_frames(); ++f) {
      const FrameIndex g = graph_.FindFrame(scene_.frame_name(f));
      ASSERT_EQ(g.is_valid(), model_.frame_exists(f)) << what << ": frame " << scene_.frame_name(f);
      if (!g.is_valid()) continue;
      EXPECT_EQ(graph_.body_name(graph_.body_of(g)), scene_.body_name(scene_.BodyOf(f))) << what;
      const int p = model_.parent(f);
      const FrameIndex gp = graph_.pose_parent(g);
      EXPECT_EQ(gp.is_valid() ? std::string(graph_.frame_name(gp)) : std::string("none"),
                p >= 0 ? scene_.frame_name(p) : std::string("none"))
          << what << ": pose parent of " << scene_.frame_name(f);
      const int D = model_.twist_tail(f);
      const BodyIndex gD = graph_.twist_parent(g);
      EXPECT_EQ(gD.is_valid() ? std::string(graph_.body_name(gD)) : std::string("none"),
                D >= 0 ? scene_.body_name(D) : std::string("none"))
          << what << ": twist parent of " << scene_.frame_name(f);
      pose_edges += p >= 0 ? 1 : 0;
      twist_edges += D >= 0 ? 1 : 0;
    }
    for (int k = 0; k < scene_.num_bodies(); ++k) {
      EXPECT_EQ(graph_.FindBody(scene_.body_name(k)).is_valid(), model_.body_exists(k))
          << what << ": body " << scene_.body_name(k);
    }
    EXPECT_EQ(graph_.num_pose_edges(), pose_edges) << what;
    EXPECT_EQ(graph_.num_twist_edges(), twist_edges) << what;
  }

  // ------------------------------------------------------------------ queries

  /// n random queries of each kind, each compared with the world or with the predicted code.
  void CheckRandomQueries(int n) {
    for (int i = 0; i < n; ++i) {
      CheckPoseQuery();
      CheckPositionQuery();
      CheckOrientationQuery();
      CheckTwistQuery();
      CheckAngularVelocityQuery();
    }
  }

  /// The spec's outcome for a pose / position / orientation query (bodies always right).
  ErrorCode PredictPoseLike(std::initializer_list<int> frames_in_order,
                            std::initializer_list<std::pair<int, int>> same_tree_pairs,
                            bool representable) const {
    for (int x : frames_in_order) {
      if (!model_.frame_exists(x)) return ErrorCode::kUnknownFrame;
    }
    for (const auto& [x, y] : same_tree_pairs) {
      if (!model_.Same(x, y)) return ErrorCode::kNoPosePath;
    }
    return representable ? ErrorCode::kOk : ErrorCode::kRepresentationConstraint;
  }

  /// Uniform random frames and bodies of the scene (existing in the graph or not).
  int RandomFrameOn(int body) { return Pick(frames_on_[I(body)]); }
  int RandomBody() { return UniformIndex(rng(), scene_.num_bodies()); }
  int RandomFrame() { return UniformIndex(rng(), scene_.num_frames()); }
  /// A random frame of `body`, in 80% of the cases from the pose tree of x (so paths exist).
  int RandomFrameOnNear(int body, int x) {
    const std::vector<int> near = model_.TreeFramesOn(x, body);
    return !near.empty() && Chance(0.8) ? Pick(near) : RandomFrameOn(body);
  }
  /// A random frame, in 80% of the cases from the pose tree of x.
  int RandomFrameNear(int x) { return Chance(0.8) ? Pick(model_.Tree(x)) : RandomFrame(); }

  /// Bodies of a frame argument: given (and right) or omitted (taken from the frame).
  std::string_view MaybeBody(int frame) {
    return Chance(0.5) ? std::string_view(scene_.body_name(scene_.BodyOf(frame)))
                       : std::string_view();
  }
  std::string_view BodyNameIfNeeded(int frame) {
    return !model_.frame_exists(frame) || Chance(0.5)
               ? std::string_view(scene_.body_name(scene_.BodyOf(frame)))
               : std::string_view();
  }

  const std::string& Name(int f) const { return scene_.frame_name(f); }

  void CheckPoseQuery() {
    // Shapes: point = orientation frame or not, ref point = ref orientation frame or not,
    // [r] = [b], [a] or any frame; the homogeneous backend gets the edge form half the time.
    const int C = RandomBody(), D = RandomBody();
    const int b = RandomFrameOn(D);
    const int a = RandomFrameOnNear(C, b);
    int e = Chance(0.4) ? a : RandomFrameOnNear(C, a);
    int f = Chance(0.4) ? b : RandomFrameOnNear(D, b);
    const double u = UnitDouble(rng());
    int r = u < 0.35 ? b : u < 0.5 ? a : RandomFrameNear(b);
    if (kHomogeneous && Chance(0.5)) {
      e = a;
      f = b;
      r = b;
    }
    const bool edge_form = e == a && f == b && r == b;
    const ErrorCode expected = PredictPoseLike({e, a, f, b, r}, {{a, b}, {e, a}, {f, b}, {r, b}},
                                               !kHomogeneous || edge_form);
    PoseSpec spec;
    spec.point = Name(e);
    spec.orientation = Name(a);
    spec.body = MaybeBody(a);
    spec.ref_point = Name(f);
    spec.ref_orientation = Name(b);
    spec.ref_body = MaybeBody(b);
    spec.coordinate_frame = Name(r);
    const std::string what = "GetPose(PoseCoord((" + Name(e) + ",[" + Name(a) + "])|" +
                             scene_.body_name(C) + ", (" + Name(f) + ",[" + Name(b) + "])|" +
                             scene_.body_name(D) + ", [" + Name(r) + "]))";
    const auto X_FE_R =
        Chance(0.25) ? graph_.GetPose(PoseSemanticsOf(e, a, f, b, r)) : graph_.GetPose(spec);
    if (!CheckOutcome(X_FE_R, expected, what)) return;
    const Eigen::Matrix3d O_BA_R = B::ToMatrix(B::RotationOf(X_FE_R->value));
    EXPECT_TRUE(Near(O_BA_R, scene_.OrientationOperator(a, b, r), kTol)) << what;
    EXPECT_TRUE(Near(B::TranslationOf(X_FE_R->value), scene_.Position(e, f, r), kTol)) << what;
    EXPECT_TRUE(X_FE_R->semantics == PoseSemanticsOf(e, a, f, b, r)) << what << ": semantics";
    ++tally_.pose;
    if (!edge_form) ++tally_.non_edge_form_queries;
  }

  void CheckPositionQuery() {
    const int C = RandomBody(), D = RandomBody();
    const int f = RandomFrameOn(D);
    const int e = RandomFrameOnNear(C, f);
    const int r = Chance(0.4) ? f : RandomFrameNear(f);
    const ErrorCode expected = PredictPoseLike({e, f, r}, {{e, f}, {r, f}}, true);
    PoseSpec spec;
    spec.point = Name(e);
    spec.body = MaybeBody(e);
    spec.ref_point = Name(f);
    spec.ref_body = MaybeBody(f);
    spec.coordinate_frame = Name(r);
    const std::string what = "GetPosition(PositionCoord(" + Name(e) + "|" + scene_.body_name(C) +
                             ", " + Name(f) + "|" + scene_.body_name(D) + ", [" + Name(r) + "]))";
    const auto p_FE_R = Chance(0.25)
                            ? graph_.GetPosition(semantics::PositionSemantics{
                                  Point(e), BodyOfFrame(e), Point(f), BodyOfFrame(f), Axes(r)})
                            : graph_.GetPosition(spec);
    if (!CheckOutcome(p_FE_R, expected, what)) return;
    EXPECT_TRUE(Near(p_FE_R->value, scene_.Position(e, f, r), kTol)) << what;
    ++tally_.position;
  }

  void CheckOrientationQuery() {
    const int C = RandomBody(), D = RandomBody();
    const int b = RandomFrameOn(D);
    const int a = RandomFrameOnNear(C, b);
    int r = Chance(0.4) ? b : RandomFrameNear(b);
    if (kHomogeneous && Chance(0.5)) r = b;
    const ErrorCode expected =
        PredictPoseLike({a, b, r}, {{a, b}, {r, b}}, !kHomogeneous || r == b);
    PoseSpec spec;
    spec.orientation = Name(a);
    spec.body = MaybeBody(a);
    spec.ref_orientation = Name(b);
    spec.ref_body = MaybeBody(b);
    spec.coordinate_frame = Name(r);
    const std::string what = "GetOrientation(OrientationCoord([" + Name(a) + "]|" +
                             scene_.body_name(C) + ", [" + Name(b) + "]|" + scene_.body_name(D) +
                             ", [" + Name(r) + "]))";
    const auto O_BA_R = Chance(0.25)
                            ? graph_.GetOrientation(semantics::OrientationSemantics{
                                  Axes(a), BodyOfFrame(a), Axes(b), BodyOfFrame(b), Axes(r)})
                            : graph_.GetOrientation(spec);
    if (!CheckOutcome(O_BA_R, expected, what)) return;
    EXPECT_TRUE(Near(B::ToMatrix(O_BA_R->value), scene_.OrientationOperator(a, b, r), kTol))
        << what;
    ++tally_.orientation;
  }

  /// Twist and linear velocity: point e (any frame), bodies C, D (any), [r] near e.
  void CheckTwistQuery() {
    const int e = RandomFrame();
    const int C = Chance(0.3) ? scene_.BodyOf(e) : RandomBody();
    const int D = RandomBody();
    const int r = Chance(0.3) ? e : RandomFrameNear(e);
    ErrorCode expected = ErrorCode::kOk;
    if (!model_.frame_exists(e) || !model_.frame_exists(r)) {
      expected = ErrorCode::kUnknownFrame;
    } else if (!model_.body_exists(C) || !model_.body_exists(D)) {
      expected = ErrorCode::kUnknownBody;
    } else if (!model_.Same(e, r)) {
      expected = ErrorCode::kNoPosePath;
    } else if (!model_.TwistConnected(e, C, D)) {
      expected = ErrorCode::kNoTwistPath;
    }
    const bool default_body = C == scene_.BodyOf(e) && Chance(0.5);
    const TwistSpec spec =
        TwistSpec::Of(Name(e), default_body ? std::string_view() : scene_.body_name(C))
            .RelativeTo(scene_.body_name(D))
            .ExpressedIn(Name(r));
    const std::string what = "GetTwist(TwistCoord(" + Name(e) + "|" + scene_.body_name(C) + ", " +
                             scene_.body_name(D) + ", [" + Name(r) + "]))";
    const Eigen::Vector3d v_DCe_R = scene_.LinearVelocity(e, C, D, r);
    const Eigen::Vector3d w_DC_R = scene_.AngularVelocity(C, D, r);
    if (Chance(0.5)) {
      const auto V_DCe_R =
          Chance(0.3)
              ? graph_.GetTwist(semantics::TwistSemantics{Point(e), BodyId(C), BodyId(D), Axes(r)})
              : graph_.GetTwist(spec);
      if (!CheckOutcome(V_DCe_R, expected, what)) return;
      EXPECT_TRUE(Near(V_DCe_R->linear, v_DCe_R, kTol)) << what << ": linear";
      EXPECT_TRUE(Near(V_DCe_R->angular, w_DC_R, kTol)) << what << ": angular";
      EXPECT_TRUE(V_DCe_R->semantics ==
                  (semantics::TwistSemantics{Point(e), BodyId(C), BodyId(D), Axes(r)}))
          << what << ": semantics";
      ++tally_.twist;
    } else {
      const auto v = graph_.GetLinearVelocity(spec);
      if (!CheckOutcome(v, expected, "linear velocity of " + what)) return;
      EXPECT_TRUE(Near(v->value, v_DCe_R, kTol)) << "linear velocity of " << what;
      ++tally_.linear;
    }
  }

  void CheckAngularVelocityQuery() {
    const int C = RandomBody(), D = RandomBody();
    const int r = RandomFrame();
    ErrorCode expected = ErrorCode::kOk;
    if (!model_.frame_exists(r)) {
      expected = ErrorCode::kUnknownFrame;
    } else if (!model_.body_exists(C) || !model_.body_exists(D)) {
      expected = ErrorCode::kUnknownBody;
    } else if (!model_.TwistConnected(r, C, D)) {
      expected = ErrorCode::kNoTwistPath;
    }
    TwistSpec spec;
    spec.body = scene_.body_name(C);
    spec.ref_body = scene_.body_name(D);
    spec.coordinate_frame = Name(r);
    const std::string what = "GetAngularVelocity(AngularVelocityCoord(" + scene_.body_name(C) +
                             ", " + scene_.body_name(D) + ", [" + Name(r) + "]))";
    const auto w_DC_R = graph_.GetAngularVelocity(spec);
    if (!CheckOutcome(w_DC_R, expected, what)) return;
    EXPECT_TRUE(Near(w_DC_R->value, scene_.AngularVelocity(C, D, r), kTol)) << what;
    ++tally_.angular;
  }

  /// True when a value is there to be checked; otherwise checks the error code.
  template <class Result>
  bool CheckOutcome(const Result& result, ErrorCode expected, const std::string& what) {
    if (expected == ErrorCode::kOk) {
      EXPECT_TRUE(result) << what << " failed: " << base::ToString(result.error().code) << ": "
                          << graph_.Describe(result.error());
      return static_cast<bool>(result);
    }
    if (result) {
      ADD_FAILURE() << what << " succeeded; expected " << base::ToString(expected);
      return false;
    }
    EXPECT_EQ(result.error().code, expected) << what << ": " << graph_.Describe(result.error());
    switch (expected) {
      case ErrorCode::kNoPosePath:
        ++tally_.no_pose_path;
        break;
      case ErrorCode::kNoTwistPath:
        ++tally_.no_twist_path;
        break;
      case ErrorCode::kRepresentationConstraint:
        ++tally_.representation;
        break;
      case ErrorCode::kUnknownFrame:
        ++tally_.unknown_frame;
        break;
      default:
        break;
    }
    return false;
  }

  // Semantics ids of this graph's names (invalid ids for names it never saw).
  semantics::Point Point(int f) const { return semantics::Point(graph_.names().Find(Name(f))); }
  semantics::OrientationFrame Axes(int f) const {
    return semantics::OrientationFrame(graph_.names().Find(Name(f)));
  }
  semantics::Body BodyId(int k) const {
    return semantics::Body(graph_.names().Find(scene_.body_name(k)));
  }
  semantics::Body BodyOfFrame(int f) const { return BodyId(scene_.BodyOf(f)); }
  semantics::PoseSemantics PoseSemanticsOf(int e, int a, int f, int b, int r) const {
    return {Point(e), Axes(a), BodyOfFrame(a), Point(f), Axes(b), BodyOfFrame(b), Axes(r)};
  }

  // ------------------------------------------------------------------ values

  /// The rotation as a quaternion: sometimes -q (the same rotation), sometimes scaled off
  /// unit norm within the spec's 1e-6 (normalized by the graph).
  Eigen::Quaterniond JitteredQuaternion(const Eigen::Matrix3d& R) {
    Eigen::Quaterniond q(R);
    if (Chance(0.3)) q.coeffs() = -q.coeffs();
    if (Chance(0.3)) q.coeffs() *= 1.0 + 5e-7;
    return q;
  }

 private:
  static std::size_t I(int i) { return static_cast<std::size_t>(i); }

  RigidBodyScene scene_;
  Model model_;
  SceneGraph<B> graph_;
  std::vector<std::vector<int>> frames_on_;
  Tally& tally_;
};

// ====================================================================== the tests

/// Every rule the illegal attempts can break was broken at least once.
void ExpectEveryIllegalKindSeen(const Tally& tally) {
  for (ErrorCode code :
       {ErrorCode::kSelfEdge, ErrorCode::kMultiplePoseParents, ErrorCode::kPoseCycle,
        ErrorCode::kDuplicatePosePath, ErrorCode::kTwistMergeConflict, ErrorCode::kTwistSameBody,
        ErrorCode::kMultipleTwistParents, ErrorCode::kDuplicateTwistPath}) {
    EXPECT_GT(tally.illegal_by_code[static_cast<int>(code)], 0) << base::ToString(code);
  }
}

template <class B>
class SceneGraphRandom : public ::testing::Test {};

struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(SceneGraphRandom, Backends, BackendName);

TYPED_TEST(SceneGraphRandom, QueriesOnRandomScenesMatchTheWorld) {
  using B = TypeParam;
  Tally tally;
  for (int i = 0; i < kSeeds; ++i) {
    const std::uint64_t seed = kFirstSeed + static_cast<std::uint64_t>(i);
    SCOPED_TRACE("seed " + std::to_string(seed) + " (RigidBodyScene, backend " + B::kName + ")");
    Harness<B> h(seed, tally);
    h.BuildRandomScene();
    if (::testing::Test::HasFatalFailure()) return;
    h.CheckRandomQueries(kQueriesPerKind);
    h.AttemptIllegalEdges(kIllegalAttempts);
  }
  // The test exercised what it is for.
  EXPECT_GT(tally.pose, 100);
  EXPECT_GT(tally.position, 100);
  EXPECT_GT(tally.orientation, 100);
  EXPECT_GT(tally.twist, 50);
  EXPECT_GT(tally.linear, 50);
  EXPECT_GT(tally.angular, 50);
  EXPECT_GT(tally.illegal_attempts, 100);
  ExpectEveryIllegalKindSeen(tally);
  EXPECT_GT(tally.same_body_edges, 0);
  EXPECT_GT(tally.cross_body_edges, 0);
  EXPECT_GT(tally.converted_twists, 0);
  EXPECT_GT(tally.no_twist_path, 0);
  EXPECT_GT(tally.unknown_frame, 0);
  if constexpr (std::is_same_v<B, coord::HomogeneousBackend>) {
    EXPECT_GT(tally.representation, 0);
    EXPECT_EQ(tally.non_edge_adds, 0);
  } else {
    EXPECT_EQ(tally.representation, 0);
    EXPECT_GT(tally.non_edge_adds, 0);
    EXPECT_GT(tally.non_edge_form_queries, 100);
  }
}

TYPED_TEST(SceneGraphRandom, QueriesStayCorrectThroughRemovalsReAddsAndMotion) {
  using B = TypeParam;
  Tally tally;
  for (int i = 0; i < kSeeds; ++i) {
    const std::uint64_t seed = kFirstSeed + 1000 + static_cast<std::uint64_t>(i);
    SCOPED_TRACE("seed " + std::to_string(seed) + " (RigidBodyScene, backend " + B::kName + ")");
    Harness<B> h(seed, tally);
    h.BuildRandomScene();
    if (::testing::Test::HasFatalFailure()) return;
    for (int step = 0; step < kChangeSteps; ++step) {
      SCOPED_TRACE("step " + std::to_string(step));
      const double u = UnitDouble(h.rng());
      const auto pose_edges = h.model().PoseEdges();
      const auto twist_edges = h.model().TwistEdges();
      if (u < 0.45 && !pose_edges.empty()) {
        // Remove a pose edge, query the split trees, then re-hang the head under another
        // parent when the rules allow (a grasp), else add any legal edge.
        const auto [t, head] = pose_edges[static_cast<std::size_t>(
            UniformIndex(h.rng(), static_cast<int>(pose_edges.size())))];
        h.RemovePoseEdge(t, head);
        h.CheckRandomQueries(kQueriesPerKindPerStep);
        auto candidates = h.PoseCandidates();
        std::vector<std::pair<int, int>> regrasps;
        for (const auto& c : candidates) {
          if (c.second == head && c.first != t) regrasps.push_back(c);
        }
        if (!regrasps.empty() && h.Chance(0.7)) {
          h.AddPoseEdge(regrasps[static_cast<std::size_t>(
                            UniformIndex(h.rng(), static_cast<int>(regrasps.size())))],
                        false);
          ++tally.regrasps;
        } else if (!candidates.empty()) {
          h.AddPoseEdge(h.PickPreferringSameBody(candidates), false);
        }
      } else if (u < 0.7 && !twist_edges.empty()) {
        const auto [D, head] = twist_edges[static_cast<std::size_t>(
            UniformIndex(h.rng(), static_cast<int>(twist_edges.size())))];
        h.RemoveTwistEdge(D, head);
        h.CheckRandomQueries(kQueriesPerKindPerStep);
        const auto candidates = h.TwistCandidates();
        if (!candidates.empty()) {
          const auto [D2, head2] = candidates[static_cast<std::size_t>(
              UniformIndex(h.rng(), static_cast<int>(candidates.size())))];
          h.AddTwistEdge(D2, head2, true);
        }
      } else {
        // The bodies move: every cross-body edge gets its new value (an update: topology
        // unchanged), every same-body edge is set again to its unchanged value (a no-op), and
        // then every twist edge gets its new value.
        h.scene().Move();
        for (const auto& edge : h.model().PoseEdges())
          h.AddPoseEdge(edge, /*update_after_move=*/true);
        for (const auto& [D, head] : h.model().TwistEdges()) h.AddTwistEdge(D, head, true);
      }
      if (::testing::Test::HasFatalFailure()) return;
      h.CheckRandomQueries(kQueriesPerKindPerStep);
      h.AttemptIllegalEdges(kIllegalAttemptsPerStep);
    }
  }
  EXPECT_GT(tally.illegal_attempts, 100);
  ExpectEveryIllegalKindSeen(tally);
  EXPECT_GT(tally.removals, 0);
  EXPECT_GT(tally.regrasps, 0);
  EXPECT_GT(tally.updates, 0);
  EXPECT_GT(tally.constant_no_ops, 0);
  EXPECT_GT(tally.pose, 100);
  EXPECT_GT(tally.twist, 50);
}

}  // namespace
}  // namespace semgraph::core
