// File: semgraph/topology/scene_topology.h
//
// SceneTopology: everything of a scene graph that is not a number. Bodies and frames (nodes,
// named through one NameTable), the pose forest over frames, which pose tree each frame is in,
// and per pose tree its record: the multiset of bodies with frames in it (for P3) and its
// body-level twist graph TG(P) (for W3/W4). Twist edges D -> {h}|H are kept here too, with the
// semantics of their stored screw twist TwistCoord(h|H, D, [h]); their values live in
// core::EdgeValues, indexed by the same FrameIndex / TwistEdgeIndex.
//
// It checks nothing itself: callers run the rules of rules.h first (in the order of
// docs/rules.md) and only then mutate. Mutations keep every invariant below, or abort via
// SEMGRAPH_DEMAND when called against a rule (a programming error, never a user error).
// Allocation failure: every mutation makes all its allocations before its first change, so a
// std::bad_alloc leaves the topology unchanged (strong guarantee); the Reserve* calls let a
// caller that makes several mutations in a row (create nodes, then link them) allocate for all
// of them first. Reservations change capacities only (and may add an empty spare record).
//
// Invariants (CheckInvariants in scene_topology_debug.cc verifies them from scratch):
//  - every frame belongs to exactly one body; name -> frame and name -> body maps agree with
//    the nodes; names are unique among frames and among bodies.
//  - the pose forest is a forest (P1, P2); a tree record exactly for every tree with more than
//    one frame or with a twist edge, keyed by the tree's PoseForest::TreeKey.
//  - P3: in every pose tree the frames of one body are connected through same-body edges only
//    (a record's body count equals 1 + the same-body edges among that body's frames).
//  - W1: a frame has at most one twist edge into it; W2: no twist edge from a body to itself;
//    W3: every tree's TG(P) is a forest, and holds exactly the live twist edges whose head is
//    in that tree.
//
// Costs (n = frames, |T| = frames of an affected pose tree, b = bodies in a tree's body set):
//   CreateBody, CreateFrame            O(1) amortized (grow the node and name arrays)
//   LinkPose, new leaf frame           O(1) amortized (jump pointer, body count)
//   LinkPose, linking trees            O(log n) amortized (PoseForest::Link re-represents the
//                                      smaller tree) + O(min(b1, b2)) (body-set merge)
//                                      + O(twist edges of the smaller TG)
//   CutPose                            O(|T|) for the tree being split (plans both records)
//   RerootPose                         O(depth of v) (path reversal)
//   LinkTwist / UnlinkTwist            O(depth in TG) / O(size of the detached part of TG)
//   SameTree                           O(1), noexcept, no allocation
//   RecordOf, TreeHasBody              O(1) expected
//   SharedBody                         O(min(b1, b2))
// Thread safety: one writer thread makes every mutation, inside a change scope (BeginChange /
// EndChange, nestable: the outermost pair counts). Readers on other threads may run the const
// methods a query planner uses (names, FrameOfName, BodyOfName, body_of, the name ids, the
// forest's queries) concurrently with it: they never crash, loop or read freed memory (node
// arrays are RetiringArrays, fields are base::Published atomics, walks are bounded), but what
// they read is meaningful only if change_count() was even before and unchanged after (an
// optimistic read, docs/realtime.md "Topology changes while readers run"). So may the twist
// planner's reads: RecordOf (records never move; the index is checked), twist_edge(e).head and
// num_twist_edge_slots (twist edges grow by copy), and the TwistForest's queries (its maps
// retire old arrays, flat_map.h). TreeHasBody and the other twist-edge fields are the
// writer's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "semgraph/base/published.h"
#include "semgraph/base/retiring_array.h"
#include "semgraph/base/stable_array.h"
#include "semgraph/semantics/names.h"
#include "semgraph/semantics/relations.h"
#include "semgraph/topology/export.h"
#include "semgraph/topology/flat_map.h"
#include "semgraph/topology/ids.h"
#include "semgraph/topology/pose_forest.h"
#include "semgraph/topology/twist_forest.h"

namespace semgraph::topology {

using semantics::NameId;

/// A twist edge D -> {h}|H: its ends and the semantics TwistCoord(h|H, D, [h]) of its value.
/// Readers of other threads (the twist planner under validation) read only `head`, which is
/// therefore a Published atomic; the other fields are the writer thread's.
struct TwistEdge {
  BodyIndex tail;                    ///< D, the reference body
  base::Published<FrameIndex> head;  ///< {h}, a frame of the moving body H
  bool alive = false;
  semantics::TwistSemantics semantics;
};

/// A pose tree's record: its bodies (with frame counts) and its twist graph TG(P), whose edge
/// ids are TwistEdgeIndex values and node ids BodyIndex values.
struct TreeRecord {
  FlatMap<std::uint32_t> body_counts;
  TwistForest twists;
};

class SEMGRAPH_TOPOLOGY_EXPORT SceneTopology {
 public:
  SceneTopology() = default;
  SceneTopology(const SceneTopology&) = delete;
  SceneTopology& operator=(const SceneTopology&) = delete;
  SceneTopology(SceneTopology&&) = default;
  SceneTopology& operator=(SceneTopology&&) = default;

  // ---------------------------------------------------------------- names and nodes

  [[nodiscard]] const semantics::NameTable& names() const noexcept { return names_; }
  /// The table, for interning the names of an add (rolled back by the caller on rejection).
  [[nodiscard]] semantics::NameTable& mutable_names() noexcept { return names_; }

  [[nodiscard]] std::size_t num_frames() const noexcept { return frames_.size(); }
  [[nodiscard]] std::size_t num_bodies() const noexcept { return bodies_.size(); }
  [[nodiscard]] std::size_t num_pose_edges() const noexcept { return num_pose_edges_; }
  [[nodiscard]] std::size_t num_twist_edges() const noexcept { return num_twist_edges_; }

  /// The frame / body named `id` (invalid if the name is not one). O(1), noexcept.
  // Always inlined: the planner calls these per query field (they were inlined before their
  // loads became atomic, which made the compiler's size estimate exceed its budget).
  [[nodiscard, gnu::always_inline]] FrameIndex FrameOfName(NameId id) const noexcept {
    return id.is_valid() && id.value() < frame_of_name_.size()
               ? FrameIndex(frame_of_name_[id.value()].load())
               : FrameIndex();
  }
  [[nodiscard, gnu::always_inline]] BodyIndex BodyOfName(NameId id) const noexcept {
    return id.is_valid() && id.value() < body_of_name_.size()
               ? BodyIndex(body_of_name_[id.value()].load())
               : BodyIndex();
  }
  [[nodiscard]] FrameIndex FindFrame(std::string_view name) const noexcept {
    return FrameOfName(names_.Find(name));
  }
  [[nodiscard]] BodyIndex FindBody(std::string_view name) const noexcept {
    return BodyOfName(names_.Find(name));
  }
  [[nodiscard]] NameId frame_name_id(FrameIndex f) const noexcept {
    return frames_[f.value()].name;
  }
  [[nodiscard]] NameId body_name_id(BodyIndex b) const noexcept { return bodies_[b.value()].name; }
  [[nodiscard]] std::string_view frame_name(FrameIndex f) const noexcept {
    return names_.name(frame_name_id(f));
  }
  [[nodiscard]] std::string_view body_name(BodyIndex b) const noexcept {
    return names_.name(body_name_id(b));
  }
  [[nodiscard]] BodyIndex body_of(FrameIndex f) const noexcept { return frames_[f.value()].body; }

  /// The semantic primitives of a node: {f}, its body, a body.
  [[nodiscard]] semantics::Frame FrameSem(FrameIndex f) const noexcept {
    return semantics::Frame(frame_name_id(f));
  }
  [[nodiscard]] semantics::Body BodySem(BodyIndex b) const noexcept {
    return semantics::Body(body_name_id(b));
  }
  [[nodiscard, gnu::always_inline]] semantics::Body BodyOfSem(FrameIndex f) const noexcept {
    return BodySem(body_of(f));
  }

  /// Reserves room for `frames` frames and `bodies` bodies in total (nodes, forest, tree sets,
  /// name maps and names), so that a build of known size does not reallocate.
  void Reserve(std::size_t frames, std::size_t bodies);

  /// Room for `bodies` new bodies and `frames` new frames, whose names are interned already, so
  /// that the CreateBody / CreateFrame calls that follow do not allocate. Changes nothing else.
  /// O(1) when the room is there already (the common case: a build reserves, then creates):
  /// the room left is counted, so the check is three comparisons.
  void ReserveNodes(std::size_t bodies, std::size_t frames) {
    if (frames <= frame_room_ && bodies <= body_room_ && names_.size() <= name_map_room_) return;
    GrowNodes(bodies, frames);
  }
  /// New nodes. The name must be interned and not yet name a node of that kind.
  BodyIndex CreateBody(NameId name);
  FrameIndex CreateFrame(NameId name, BodyIndex body);

  // ---------------------------------------------------------------- change counter

  /// Even between changes, odd while one is in progress; every change scope adds 2. A reader
  /// reads it (acquire) before and after reading the topology: equal and even means it read
  /// one consistent topology (the writer's stores are release: a reader that saw any store of
  /// a change sees the odd count afterwards).
  [[nodiscard]] std::uint64_t change_count() const noexcept { return change_count_.load(); }
  /// Opens / closes a change (writer thread; nested scopes count as their outermost).
  void BeginChange() noexcept {
    if (change_depth_++ == 0) change_count_.store(change_count_.load() + 1);
  }
  void EndChange() noexcept {
    if (--change_depth_ == 0) change_count_.store(change_count_.load() + 1);
  }
  /// BeginChange for the scope of the object.
  class ChangeScope {
   public:
    explicit ChangeScope(SceneTopology& t) noexcept : t_(t) { t_.BeginChange(); }
    ~ChangeScope() { t_.EndChange(); }
    ChangeScope(const ChangeScope&) = delete;
    ChangeScope& operator=(const ChangeScope&) = delete;

   private:
    SceneTopology& t_;
  };

  // ---------------------------------------------------------------- pose forest

  [[nodiscard]] const PoseForest& forest() const noexcept { return forest_; }
  [[nodiscard]] FrameIndex pose_parent(FrameIndex f) const noexcept { return forest_.parent(f); }
  /// True when a and b are in one pose tree. O(1).
  [[nodiscard]] bool SameTree(FrameIndex a, FrameIndex b) const noexcept {
    return forest_.SameTree(a, b);
  }

  /// Room for LinkPose(tail, head), so that it does not allocate; an invalid index stands for
  /// a frame not created yet (a single-frame tree). A caller that creates nodes and then links
  /// them reserves first (with ReserveNodes), so that nothing changes unless all succeeds.
  void ReserveLinkPose(FrameIndex tail, FrameIndex head);
  /// Links the pose edge tail -> head (head a root of another tree; P1-P3 and W4 checked by
  /// the caller) and merges the two trees' records.
  void LinkPose(FrameIndex tail, FrameIndex head);
  /// LinkPose without its reservation, for a caller that called ReserveLinkPose for the same
  /// two trees (an invalid index there standing for the frame created since) and changed
  /// neither tree since: a build's add reserves once, before its first change.
  void LinkPoseReserved(FrameIndex tail, FrameIndex head);
  /// Removes the pose edge into `head`, splitting its tree; both parts get fresh records.
  void CutPose(FrameIndex head);
  /// Makes v the root of its pose tree by reversing the edges on its path to the root (the
  /// tree's frames, bodies and twist graph are unchanged, so its record stays). O(|T|).
  void RerootPose(FrameIndex v) { forest_.Reroot(v); }

  // ---------------------------------------------------------------- tree records

  /// The record of f's tree; nullptr for a single-frame tree without twist edges.
  [[nodiscard]] const TreeRecord* RecordOf(FrameIndex f) const noexcept;
  /// True when a frame of `body` is in f's tree. O(1) expected.
  [[nodiscard]] bool TreeHasBody(FrameIndex f, BodyIndex body) const noexcept;
  /// P3's question: a body with frames in the trees of both t and h, other than `allowed`
  /// (invalid if none). O(min(b_t, b_h)).
  [[nodiscard]] BodyIndex SharedBody(FrameIndex t, FrameIndex h, BodyIndex allowed) const noexcept;
  /// A frame of `body` in the tree of `tree_member` (invalid if none). O(frames of body).
  [[nodiscard]] FrameIndex SomeFrameOfBodyInTree(BodyIndex body,
                                                 FrameIndex tree_member) const noexcept;

  // ---------------------------------------------------------------- twist edges

  /// The twist edge into frame f (invalid if none).
  [[nodiscard]] TwistEdgeIndex twist_edge_of(FrameIndex f) const noexcept {
    return frames_[f.value()].twist_edge;
  }
  [[nodiscard]] const TwistEdge& twist_edge(TwistEdgeIndex e) const noexcept {
    return twist_edges_[e.value()];
  }
  /// Number of twist edge slots (live or free); values are kept per slot.
  [[nodiscard]] std::size_t num_twist_edge_slots() const noexcept { return twist_edges_.size(); }
  /// Room for LinkTwist(..., head, ...), so that it does not allocate; an invalid head stands
  /// for a frame not created yet.
  void ReserveLinkTwist(FrameIndex head);
  /// Adds the twist edge tail -> head (W1-W3 checked by the caller); returns its slot.
  TwistEdgeIndex LinkTwist(BodyIndex tail, FrameIndex head, const semantics::TwistSemantics& s);
  /// Removes a live twist edge from its tree's TG; its slot is reused later.
  void UnlinkTwist(TwistEdgeIndex e);

  // A joint is a pose edge and a twist edge made or removed together; these reserve for the
  // pair, so that a joint's add or removal is all or nothing under std::bad_alloc.

  /// Room for LinkPose(tail, head) followed by LinkTwist(..., head, ...) into the merged tree
  /// (invalid indices: frames not created yet). Changes capacities only.
  void ReserveLinkJoint(FrameIndex tail, FrameIndex head);
  /// Room for CutPose(head) followed by UnlinkTwist of the twist edge into head: CutPose makes
  /// all its allocations before its first change, so a caller that cuts first and then unlinks
  /// needs only UnlinkTwist's list growth reserved beforehand. Changes capacities only.
  void ReserveUnlinkAfterCut();

  // ---------------------------------------------------------------- iteration and checks

  /// f(tail, head) for every pose edge, by head frame index.
  template <class F>
  void ForEachPoseEdge(F&& f) const {
    for (std::uint32_t i = 0; i < frames_.size(); ++i) {
      const FrameIndex head(i);
      if (forest_.parent(head).is_valid()) f(forest_.parent(head), head);
    }
  }
  /// f(frame) for every frame of `body`, newest first.
  template <class F>
  void ForEachFrameOfBody(BodyIndex body, F&& f) const {
    for (std::uint32_t i = bodies_[body.value()].first_frame; i != kNone;
         i = frames_[i].next_in_body) {
      f(FrameIndex(i));
    }
  }
  /// f(tail body, head frame) for every live twist edge, by slot.
  template <class F>
  void ForEachTwistEdge(F&& f) const {
    for (std::size_t i = 0; i < twist_edges_.size(); ++i) {
      const TwistEdge& e = twist_edges_[i];
      if (e.alive) f(e.tail, e.head.load());
    }
  }
  /// Every invariant above, from scratch (slow; tests). Empty when all hold
  /// (scene_topology_debug.cc).
  [[nodiscard]] std::string CheckInvariants() const;
  /// Heap bytes, excluding the name strings and the name index.
  [[nodiscard]] std::size_t ApproximateBytesExcludingNames() const noexcept;

 private:
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  // Node fields are Published (atomic): readers of other threads may read them while the
  // writer changes them (see Thread safety).
  struct FrameNode {
    base::Published<NameId> name;
    base::Published<BodyIndex> body;
    base::Published<TwistEdgeIndex> twist_edge;
    base::Published<std::uint32_t> next_in_body = kNone;  // intrusive list of a body's frames
  };
  struct BodyNode {
    base::Published<NameId> name;
    base::Published<std::uint32_t> first_frame = kNone;
  };

  void GrowNameMaps();
  // ReserveNodes' growth: every node array to at least twice its size (O(1) amortized).
  void GrowNodes(std::size_t bodies, std::size_t frames);
  TreeRecord* MutableRecordOf(FrameIndex f) noexcept;
  TreeRecord& EnsureRecord(FrameIndex f);
  TreeRecord& NewRecord(std::uint32_t rep, FrameIndex f);
  void FreeRecord(std::uint32_t rep);
  void ReserveNewRecord(std::size_t bodies);
  void InstallTree(FrameIndex member, TreeRecord&& record) noexcept;

  semantics::NameTable names_;
  // NameId -> FrameIndex (kNone if not a frame) / BodyIndex. The node arrays and these maps
  // are RetiringArrays: grown by copy, old arrays kept, so a concurrent reader never reads
  // freed memory.
  base::RetiringArray<base::Published<std::uint32_t>> frame_of_name_;
  base::RetiringArray<base::Published<std::uint32_t>> body_of_name_;
  // How many frames / bodies can be created, and up to how many names the name maps hold,
  // without allocating (the capacities every array of that kind has at least).
  std::size_t frame_room_ = 0, body_room_ = 0, name_map_room_ = 0;
  base::RetiringArray<FrameNode> frames_;
  base::RetiringArray<BodyNode> bodies_;
  PoseForest forest_;
  // Read by the twist planner on reader threads (RecordOf): the map's values are Published and
  // records never move (a StableArray; a freed record is cleared and reused, never destroyed).
  FlatMap<base::Published<std::uint32_t>> record_of_rep_;  // PoseForest::TreeKey -> records_
  base::StableArray<TreeRecord, 3> records_;
  std::vector<std::uint32_t> free_records_;
  base::RetiringArray<TwistEdge> twist_edges_;  // grown by copy (twist_edge on reader threads)
  std::vector<std::uint32_t> free_twist_edges_;
  std::size_t num_pose_edges_ = 0;
  std::size_t num_twist_edges_ = 0;
  base::Published<std::uint64_t> change_count_ = 0;  // see change_count()
  std::uint32_t change_depth_ = 0;                   // open change scopes (writer only)
};

}  // namespace semgraph::topology
