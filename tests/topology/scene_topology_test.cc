// SceneTopology (topology/scene_topology.h) on its own, no numbers: nodes and names, the tree
// records (bodies per pose tree, for P3; the twist graph TG per tree, for W3/W4) through every
// mutation (link, cut, reroot, twist link and unlink), the iteration helpers, and the aborts
// when a mutation is called against a rule. Expected records are written out by hand for each
// small scene; CheckInvariants (which recounts everything from scratch) is run after each
// mutation as a second, independent check.
#include "semgraph/topology/scene_topology.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "topology/scene_builder.h"

namespace semgraph::topology {
namespace {

using testing::SceneBuilder;

// The bodies with frames in f's tree, by name, and their frame counts.
std::set<std::pair<std::string, std::uint32_t>> BodiesOfTree(const SceneTopology& t, FrameIndex f) {
  std::set<std::pair<std::string, std::uint32_t>> out;
  const TreeRecord* rec = t.RecordOf(f);
  if (rec == nullptr) {
    out.insert({std::string(t.body_name(t.body_of(f))), 1});
    return out;
  }
  rec->body_counts.ForEach([&](std::uint32_t body, std::uint32_t count) {
    out.insert({std::string(t.body_name(BodyIndex(body))), count});
  });
  return out;
}

// The twist edges of f's TG as (tail body, head body) names.
std::set<std::pair<std::string, std::string>> TwistGraphOfTree(const SceneTopology& t,
                                                               FrameIndex f) {
  std::set<std::pair<std::string, std::string>> out;
  const TreeRecord* rec = t.RecordOf(f);
  if (rec == nullptr) return out;
  rec->twists.ForEachEdge([&](TwistEdgeIndex, BodyIndex from, BodyIndex to) {
    out.insert({std::string(t.body_name(from)), std::string(t.body_name(to))});
  });
  return out;
}

TEST(SceneTopology, NodesAreNamedInSeparateFrameAndBodyNamespaces) {
  SceneBuilder s;
  const BodyIndex W = s.Body("W");
  const FrameIndex w = s.Frame("w", "W"), w2 = s.Frame("w2", "W");
  const FrameIndex x = s.Frame("x", "x");  // a frame and a body may share a name
  EXPECT_EQ(s.t.num_frames(), 3u);
  EXPECT_EQ(s.t.num_bodies(), 2u);
  EXPECT_EQ(s.t.FindFrame("w"), w);
  EXPECT_EQ(s.t.FindBody("W"), W);
  EXPECT_FALSE(s.t.FindFrame("W").is_valid());
  EXPECT_FALSE(s.t.FindBody("w").is_valid());
  EXPECT_FALSE(s.t.FindFrame("nowhere").is_valid());
  EXPECT_EQ(s.t.FindFrame("x"), x);
  EXPECT_EQ(s.t.body_name(s.t.body_of(x)), "x");
  EXPECT_EQ(s.t.frame_name(w2), "w2");
  EXPECT_EQ(s.t.body_of(w2), W);
  EXPECT_EQ(s.t.FrameSem(w).id(), s.t.frame_name_id(w));
  EXPECT_EQ(s.t.BodyOfSem(w2), s.t.BodySem(W));
  // A body's frames, newest first.
  std::vector<FrameIndex> frames;
  s.t.ForEachFrameOfBody(W, [&](FrameIndex f) { frames.push_back(f); });
  EXPECT_EQ(frames, (std::vector<FrameIndex>{w2, w}));
  // New frames are single-frame trees without a record.
  EXPECT_EQ(s.t.RecordOf(w), nullptr);
  EXPECT_FALSE(s.t.SameTree(w, w2));
  EXPECT_TRUE(s.t.TreeHasBody(w, W));
  EXPECT_FALSE(s.t.TreeHasBody(w, s.t.body_of(x)));
  EXPECT_EQ(s.t.CheckInvariants(), "");
}

TEST(SceneTopology, LinkPoseMergesTheBodiesOfTwoTrees) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A"), a2 = s.Frame("a2", "A");
  const FrameIndex b = s.Frame("b", "B");
  s.Pose(w, a);
  EXPECT_EQ(s.t.num_pose_edges(), 1u);
  EXPECT_EQ(BodiesOfTree(s.t, w),
            (std::set<std::pair<std::string, std::uint32_t>>{{"A", 1}, {"W", 1}}));
  s.Pose(a, a2);  // a constant edge: A counts two frames
  s.Pose(b, w);   // a tree linked under a new root
  EXPECT_EQ(s.t.CheckInvariants(), "");
  EXPECT_EQ(BodiesOfTree(s.t, a2),
            (std::set<std::pair<std::string, std::uint32_t>>{{"A", 2}, {"B", 1}, {"W", 1}}));
  EXPECT_EQ(s.t.RecordOf(a), s.t.RecordOf(b));
  EXPECT_EQ(s.t.pose_parent(w), b);
  EXPECT_FALSE(s.t.pose_parent(b).is_valid());
  EXPECT_EQ(s.t.SomeFrameOfBodyInTree(s.Body("W"), a2), w);
  const FrameIndex some_a = s.t.SomeFrameOfBodyInTree(s.Body("A"), b);
  EXPECT_TRUE(some_a == a || some_a == a2);
  // SharedBody: P3's question between trees.
  const FrameIndex v = s.Frame("v", "V"), w3 = s.Frame("w3", "W");
  s.Pose(v, w3);
  EXPECT_EQ(s.t.SharedBody(a, v, BodyIndex()), s.Body("W"));
  EXPECT_FALSE(s.t.SharedBody(a, v, s.Body("W")).is_valid());  // the allowed body
  EXPECT_FALSE(s.t.SomeFrameOfBodyInTree(s.Body("V"), a).is_valid());
  // Every pose edge, by head.
  std::vector<std::pair<FrameIndex, FrameIndex>> edges;
  s.t.ForEachPoseEdge([&](FrameIndex tail, FrameIndex head) { edges.emplace_back(tail, head); });
  EXPECT_EQ(edges,
            (std::vector<std::pair<FrameIndex, FrameIndex>>{{b, w}, {w, a}, {a, a2}, {v, w3}}));
  EXPECT_EQ(s.t.num_pose_edges(), 4u);
}

TEST(SceneTopology, CutPoseSplitsTheBodiesAndTheTwistGraph) {
  SceneBuilder s;
  // w|W -> a|A -> b|B -> b2|B, a -> c|C; twists W -> {a}, A -> {b}, A -> {c}.
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A"), b = s.Frame("b", "B");
  const FrameIndex b2 = s.Frame("b2", "B"), c = s.Frame("c", "C");
  s.Pose(w, a);
  s.Pose(a, b);
  s.Pose(b, b2);
  s.Pose(a, c);
  s.Twist(s.Body("W"), a);
  s.Twist(s.Body("A"), b);
  s.Twist(s.Body("A"), c);
  EXPECT_EQ(TwistGraphOfTree(s.t, w),
            (std::set<std::pair<std::string, std::string>>{{"W", "A"}, {"A", "B"}, {"A", "C"}}));
  // Cut a -> b: {b, b2} with the twist edge into b; the rest keeps the others.
  s.t.CutPose(b);
  EXPECT_EQ(s.t.CheckInvariants(), "");
  EXPECT_FALSE(s.t.SameTree(a, b));
  EXPECT_EQ(s.t.num_pose_edges(), 3u);
  EXPECT_EQ(BodiesOfTree(s.t, b), (std::set<std::pair<std::string, std::uint32_t>>{{"B", 2}}));
  EXPECT_EQ(BodiesOfTree(s.t, w),
            (std::set<std::pair<std::string, std::uint32_t>>{{"A", 1}, {"C", 1}, {"W", 1}}));
  EXPECT_EQ(TwistGraphOfTree(s.t, b), (std::set<std::pair<std::string, std::string>>{{"A", "B"}}));
  EXPECT_EQ(TwistGraphOfTree(s.t, w),
            (std::set<std::pair<std::string, std::string>>{{"W", "A"}, {"A", "C"}}));
  EXPECT_FALSE(s.t.TreeHasBody(w, s.Body("B")));
  EXPECT_TRUE(s.t.TreeHasBody(b2, s.Body("B")));
  // Cut a -> c: c alone keeps a record for its twist edge; w -> a has W -> {a} left.
  s.t.CutPose(c);
  EXPECT_EQ(s.t.CheckInvariants(), "");
  ASSERT_NE(s.t.RecordOf(c), nullptr);
  EXPECT_EQ(TwistGraphOfTree(s.t, c), (std::set<std::pair<std::string, std::string>>{{"A", "C"}}));
  // Cut w -> a: w alone, no twist edge into it: no record.
  s.t.CutPose(a);
  EXPECT_EQ(s.t.CheckInvariants(), "");
  EXPECT_EQ(s.t.RecordOf(w), nullptr);
  EXPECT_EQ(TwistGraphOfTree(s.t, a), (std::set<std::pair<std::string, std::string>>{{"W", "A"}}));
  EXPECT_EQ(s.t.num_pose_edges(), 1u);
  // Linking back merges the twist graphs again.
  s.Pose(a, c);
  EXPECT_EQ(TwistGraphOfTree(s.t, c),
            (std::set<std::pair<std::string, std::string>>{{"W", "A"}, {"A", "C"}}));
  EXPECT_EQ(s.t.CheckInvariants(), "");
}

TEST(SceneTopology, RerootReversesEdgesAndKeepsTheRecord) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A"), b = s.Frame("b", "B");
  s.Pose(w, a);
  s.Pose(a, b);
  s.Twist(s.Body("W"), a);
  const TreeRecord* before = s.t.RecordOf(w);
  s.t.RerootPose(b);
  EXPECT_EQ(s.t.CheckInvariants(), "");
  EXPECT_FALSE(s.t.pose_parent(b).is_valid());
  EXPECT_EQ(s.t.pose_parent(a), b);
  EXPECT_EQ(s.t.pose_parent(w), a);
  EXPECT_EQ(s.t.RecordOf(w), before);
  EXPECT_EQ(BodiesOfTree(s.t, b),
            (std::set<std::pair<std::string, std::uint32_t>>{{"A", 1}, {"B", 1}, {"W", 1}}));
  EXPECT_EQ(TwistGraphOfTree(s.t, b), (std::set<std::pair<std::string, std::string>>{{"W", "A"}}));
  // The twist edge stays on its head frame.
  EXPECT_EQ(s.t.twist_edge(s.t.twist_edge_of(a)).head, a);
}

TEST(SceneTopology, TwistEdgesLinkUnlinkAndReuseTheirSlots) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A"), b = s.Frame("b", "B");
  s.Pose(w, a);
  const BodyIndex W = s.Body("W"), A = s.Body("A");
  const TwistEdgeIndex e0 = s.Twist(W, a);
  EXPECT_EQ(s.t.num_twist_edges(), 1u);
  EXPECT_EQ(s.t.twist_edge_of(a), e0);
  EXPECT_FALSE(s.t.twist_edge_of(w).is_valid());
  const TwistEdge& te = s.t.twist_edge(e0);
  EXPECT_TRUE(te.alive);
  EXPECT_EQ(te.tail, W);
  EXPECT_EQ(te.head, a);
  // Its semantics: TwistCoord(a|A, W, [a]), a screw twist.
  EXPECT_EQ(te.semantics.body, s.t.BodySem(A));
  EXPECT_EQ(te.semantics.ref_body, s.t.BodySem(W));
  EXPECT_TRUE(te.semantics.is_screw_twist());
  // A twist edge into a single-frame tree gives it a record; unlinking it drops the record.
  const TwistEdgeIndex e1 = s.Twist(A, b);
  ASSERT_NE(s.t.RecordOf(b), nullptr);
  EXPECT_EQ(s.t.CheckInvariants(), "");
  std::vector<std::pair<BodyIndex, FrameIndex>> live;
  s.t.ForEachTwistEdge([&](BodyIndex tail, FrameIndex head) { live.emplace_back(tail, head); });
  EXPECT_EQ(live, (std::vector<std::pair<BodyIndex, FrameIndex>>{{W, a}, {A, b}}));
  s.t.UnlinkTwist(e1);
  EXPECT_EQ(s.t.RecordOf(b), nullptr);
  EXPECT_FALSE(s.t.twist_edge_of(b).is_valid());
  EXPECT_EQ(s.t.num_twist_edges(), 1u);
  EXPECT_EQ(s.t.CheckInvariants(), "");
  // Unlinking the edge of a bigger tree keeps its record (it has two frames).
  s.t.UnlinkTwist(e0);
  EXPECT_NE(s.t.RecordOf(a), nullptr);
  EXPECT_TRUE(TwistGraphOfTree(s.t, a).empty());
  // Freed slots are reused: no new slot for the next edges.
  const std::size_t slots = s.t.num_twist_edge_slots();
  const TwistEdgeIndex e2 = s.Twist(W, a);
  const TwistEdgeIndex e3 = s.Twist(W, b);
  EXPECT_EQ(s.t.num_twist_edge_slots(), slots);
  EXPECT_EQ((std::set<TwistEdgeIndex>{e2, e3}), (std::set<TwistEdgeIndex>{e0, e1}));
  EXPECT_EQ(s.t.CheckInvariants(), "");
}

TEST(SceneTopology, ReservationsLetLinksRunWithoutGrowing) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A");
  s.t.ReserveLinkPose(w, a);
  s.t.LinkPoseReserved(w, a);
  EXPECT_TRUE(s.t.SameTree(w, a));
  EXPECT_EQ(BodiesOfTree(s.t, a),
            (std::set<std::pair<std::string, std::uint32_t>>{{"A", 1}, {"W", 1}}));
  EXPECT_EQ(s.t.CheckInvariants(), "");
}

// ---------------------------------------------------------------- mutations against a rule abort

TEST(SceneTopologyDeathTest, MutationsCalledAgainstARuleAbort) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A"), x = s.Frame("x", "X");
  s.Pose(w, a);
  const BodyIndex W = s.Body("W"), A = s.Body("A");
  s.Twist(W, a);
  const semantics::TwistSemantics sem{s.t.FrameSem(a).origin(), s.t.BodySem(A), s.t.BodySem(A),
                                      s.t.FrameSem(a).axes()};
  EXPECT_DEATH(s.t.LinkTwist(A, a, sem), "internal check failed");  // W2: from its own body
  EXPECT_DEATH(s.t.LinkTwist(s.Body("X"), a, sem), "internal check failed");  // W1: a second parent
  EXPECT_DEATH(s.t.CutPose(w), "internal check failed");                      // w has no parent
  EXPECT_DEATH(s.t.CreateFrame(s.t.frame_name_id(w), W), "internal check failed");  // name taken
  EXPECT_DEATH(s.t.CreateBody(s.t.body_name_id(W)), "internal check failed");
  (void)x;
}

}  // namespace
}  // namespace semgraph::topology
