// File: semgraph/topology/twist_forest.h
//
// TwistForest: the body-level twist graph TG(P) of one pose tree P (spec §3). Nodes are bodies
// (BodyIndex), edges are twist edges D -> {h}|H seen undirected (a twist inverts), identified
// by a TwistEdgeIndex the caller chooses (the scene topology passes the edge's slot); both are
// the strong indices of ids.h. Rule W3 makes TG(P) a forest, so between two bodies there is at
// most one twist path; this class stores that forest so the path is found by walking parent
// pointers, and so the two checks that guard it are cheap: Connected (W3, before adding an
// edge) and CanMerge (W4, before a pose edge joins two pose trees).
//
// Representation. Each tree of the forest is rooted at an arbitrary body. Per body (a
// FlatMap<Node> keyed by the body index's value): the parent body, the edge to it, the depth,
// the head of an intrusive doubly linked list of children (first_child, and next/prev sibling
// links in each child), and the number of bodies of its tree (meaningful at roots only); an
// absent link is an invalid index. Per edge (a FlatMap<TwistEdgeEnds> keyed by the edge
// index's value): its tail and head. The undirected adjacency of a body is its parent plus its
// children, so no per-body container is needed: every record is trivially copyable (the strong
// indices are plain 4-byte values) and the traversals below need no stack.
//
// Invariants (checked by CheckInvariants):
//  - ids: every stored body and edge index is valid (the invalid index, 0xFFFFFFFF, is also
//    FlatMap's free-slot key, so it could not be stored).
//  - forest: every edge joins a body to its parent; a non-root body has exactly one parent
//    edge, so num_edges() == num_bodies() - number of trees.
//  - depth(root) == 0 and depth(b) == depth(parent(b)) + 1 (hence parent pointers are acyclic).
//  - the children list of b holds exactly the bodies whose parent is b.
//  - a root records the number of bodies of its tree.
//  - no isolated body: a body is present iff it is an endpoint of some edge.
//
// Costs (n = bodies of the affected tree(s), d = depth of the bodies involved, k = steps):
//  - Contains, ContainsEdge, FindEdge, parent, parent_edge, depth: O(1).
//  - FindRoot O(d); Connected, PathLength O(d) (O(k) when connected); Path O(k + d).
//  - Link: O(d + size of the smaller of the two trees): the smaller tree is rerooted at its
//    endpoint and hung under the other endpoint, so over any sequence of links a body is
//    re-levelled O(log n) times.
//  - Unlink: O(d + size of the part below the edge), which is re-levelled; the part that stays
//    is untouched. Never allocates.
//  - CanMerge: O(m * (d + alpha)) with m = edges of the smaller forest; allocates a temporary
//    union-find over at most 2m bodies.
//  - Merge: links the edges of the smaller forest into the larger one (swapping first if
//    needed), each as a Link.
//  - Clear O(capacity); ForEachEdge O(capacity of the edge map).
//
// Thread safety: const methods may run concurrently; Contains, Connected, Path, PathLength,
// FindRoot and the accessors are noexcept, lock-free and allocation-free. Link, Unlink, Merge
// and Clear need one writer and may allocate. Readers on other threads may run Contains,
// ContainsEdge, parent, parent_edge, depth, FindRoot, Connected, PathLength and Path while the
// writer changes the forest (the one-shot twist queries under the scene topology's change
// counter, docs/realtime.md): the maps retire their old arrays (flat_map.h), the fields these
// read are Published atomics, and every walk is bounded by num_bodies() steps and treats a
// missing body as "not connected" instead of aborting. What such a reader gets is meaningful
// only under validation (the change counter even and unchanged around it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>

#include "semgraph/base/published.h"
#include "semgraph/topology/export.h"
#include "semgraph/topology/flat_map.h"
#include "semgraph/topology/ids.h"

namespace semgraph::topology {

/// One step of a twist path: cross twist edge `edge` from body `from` to body `to`. The step
/// follows the edge's direction iff `from` is the edge's tail (see TwistForest::FindEdge).
struct PathStep {
  TwistEdgeIndex edge;
  BodyIndex from;
  BodyIndex to;
  friend bool operator==(const PathStep&, const PathStep&) = default;
};

/// The endpoints of a twist edge D -> {h}|H: tail D (the moving body) and head H.
struct TwistEdgeEnds {
  BodyIndex tail;
  BodyIndex head;
  friend bool operator==(const TwistEdgeEnds&, const TwistEdgeEnds&) = default;
};

class SEMGRAPH_TOPOLOGY_EXPORT TwistForest {
 public:
  /// Path / PathLength result: the two bodies are not connected.
  static constexpr std::size_t kNoPath = std::numeric_limits<std::size_t>::max();
  /// Path result: connected, but the path has more steps than the output span holds.
  static constexpr std::size_t kPathTooLong = kNoPath - 1;

  TwistForest() noexcept = default;

  // ---- Accessors: O(1), noexcept, allocation-free. -----------------------------------------

  [[nodiscard]] bool Contains(BodyIndex body) const noexcept {
    return nodes_.Contains(body.value());
  }
  [[nodiscard]] bool ContainsEdge(TwistEdgeIndex edge) const noexcept {
    return edges_.Contains(edge.value());
  }
  /// The endpoints of `edge`, or nullptr when absent. Invalidated by any mutation.
  [[nodiscard]] const TwistEdgeEnds* FindEdge(TwistEdgeIndex edge) const noexcept {
    return edges_.Find(edge.value());
  }
  [[nodiscard]] std::size_t num_bodies() const noexcept { return nodes_.size(); }
  [[nodiscard]] std::size_t num_edges() const noexcept { return edges_.size(); }
  [[nodiscard]] bool empty() const noexcept { return edges_.empty(); }
  /// Parent of `body` in its rooted tree; invalid for a root or an absent body. Which body is
  /// the root is an internal choice (Link reroots), exposed for tests, diagnostics and the
  /// twist-path planner (query_plan.h).
  [[nodiscard]] BodyIndex parent(BodyIndex body) const noexcept;
  /// Edge from `body` to its parent; invalid for a root or an absent body.
  [[nodiscard]] TwistEdgeIndex parent_edge(BodyIndex body) const noexcept;
  /// Depth of `body` in its rooted tree; 0 for a root or an absent body.
  [[nodiscard]] std::uint32_t depth(BodyIndex body) const noexcept;

  // ---- Queries: noexcept, allocation-free. --------------------------------------------------

  /// Root of the tree holding `body`; `body` itself when absent. O(depth).
  [[nodiscard]] BodyIndex FindRoot(BodyIndex body) const noexcept;

  /// True iff a twist path joins `u` and `v`. u == v is always connected; an absent body is
  /// connected only to itself. O(depth(u) + depth(v)).
  [[nodiscard]] bool Connected(BodyIndex u, BodyIndex v) const noexcept;

  /// Writes the unique path from `u` to `v` into `out`, in order from u to v, and returns its
  /// number of steps (0 when u == v). Returns kNoPath when not connected and kPathTooLong when
  /// `out` is shorter than the path; in both cases nothing is written. Never writes past the
  /// path length. O(steps + depth).
  [[nodiscard]] std::size_t Path(BodyIndex u, BodyIndex v, std::span<PathStep> out) const noexcept;

  /// Number of steps of the path from `u` to `v`, or kNoPath. O(steps + depth).
  [[nodiscard]] std::size_t PathLength(BodyIndex u, BodyIndex v) const noexcept;

  /// True iff the union of this forest and `other` (same body index = same node) is still a
  /// forest: no cycle, no parallel edges, and no edge index in both. Implements spec W4. Neither
  /// forest changes. Allocates a temporary union-find; O(m * (depth + alpha)), m = edges of the
  /// smaller forest.
  [[nodiscard]] bool CanMerge(const TwistForest& other) const;

  // ---- Mutations: exclusive access; may allocate; invalidate FindEdge pointers. -------------

  /// Room for one more Link (two bodies, one edge), so that it does not allocate.
  void ReserveLink();
  /// Room for Merge(other) (in whichever of the two keeps its storage), so that it does not
  /// allocate. Changes neither forest's contents.
  void ReserveMerge(TwistForest& other);
  /// Room for `bodies` more bodies and `edges` more edges than this forest holds, so that
  /// Links and Merges adding no more than that into this storage do not allocate.
  void ReserveMore(std::size_t bodies, std::size_t edges);

  /// Adds twist edge `edge` = tail -> head, creating the bodies as needed. Strong guarantee:
  /// when an allocation fails (std::bad_alloc) the forest is unchanged.
  /// @pre edge, tail, head valid; tail != head; `edge` absent; !Connected(tail, head).
  /// Preconditions are checked (SEMGRAPH_DEMAND aborts) before anything changes.
  /// O(depth + size of the smaller of the two trees), which is the one rerooted.
  void Link(TwistEdgeIndex edge, BodyIndex tail, BodyIndex head);

  /// Removes `edge`; the part that hung below it becomes a tree of its own, and a body left
  /// without edges leaves the forest. @pre ContainsEdge(edge) (checked).
  /// O(depth + size of the part below the edge).
  void Unlink(TwistEdgeIndex edge);

  /// Moves every edge of `other` into this forest; `other` is left empty. The surviving
  /// storage is that of the larger forest, and the smaller one's edges are linked into it.
  /// Allocates (ReserveMerge) before it changes anything: on std::bad_alloc both are unchanged.
  /// @pre CanMerge(other), &other != this (checked edge by edge through Link's checks, which
  /// abort on violation, possibly after some edges were moved).
  void Merge(TwistForest&& other);

  /// This forest becomes `other` (left valid), without allocating: FlatMap::AssignOrAdopt on
  /// both maps (copied into this forest's arrays when they have room, else taken over).
  void AssignOrAdopt(TwistForest&& other) noexcept {
    nodes_.AssignOrAdopt(std::move(other.nodes_));
    edges_.AssignOrAdopt(std::move(other.edges_));
  }

  /// Removes all bodies and edges; keeps the memory.
  void Clear() noexcept {
    nodes_.Clear();
    edges_.Clear();
  }

  /// Calls f(TwistEdgeIndex edge, BodyIndex tail, BodyIndex head) for every edge, in
  /// unspecified order.
  template <class F>
  void ForEachEdge(F f) const {
    edges_.ForEach([&f](std::uint32_t edge, const TwistEdgeEnds& ends) {
      f(TwistEdgeIndex(edge), ends.tail, ends.head);
    });
  }

  /// Full structural check of the invariants above; O(n) plus temporaries. For tests and
  /// fuzzers, never called by the library.
  [[nodiscard]] bool CheckInvariants() const;

  /// Heap bytes owned plus the object itself.
  [[nodiscard]] std::size_t ApproximateBytes() const noexcept {
    return sizeof(*this) - sizeof(nodes_) - sizeof(edges_) + nodes_.ApproximateBytes() +
           edges_.ApproximateBytes();
  }

 private:
  // Links are invalid when absent (a root's parent, a last child's next_sibling, ...).
  // The fields readers of other threads walk (parent, parent_edge, depth) are Published
  // atomics (see Thread safety above); the rest are the writer's.
  struct Node {
    base::Published<BodyIndex> parent;
    base::Published<TwistEdgeIndex> parent_edge;
    base::Published<std::uint32_t> depth = 0;
    BodyIndex first_child;
    BodyIndex next_sibling;
    BodyIndex prev_sibling;
    std::uint32_t tree_size = 1;  // bodies in the tree; meaningful at roots only
  };

  // The record of `body`, or nullptr when absent.
  [[nodiscard]] const Node* FindNode(BodyIndex body) const noexcept {
    return nodes_.Find(body.value());
  }
  // Present-body lookups for internal use (the body is known to be present).
  [[nodiscard]] const Node& NodeAt(BodyIndex body) const noexcept;
  [[nodiscard]] Node& NodeAt(BodyIndex body) noexcept;

  // Walks u and v up to their lowest common ancestor; on success stores the number of steps
  // from each side. False when they are in different trees. Both must be present.
  bool Meet(BodyIndex u, BodyIndex v, std::size_t* up_u, std::size_t* up_v) const noexcept;
  // One step of Meet's walk: to the parent, within the step budget; false when the budget is
  // spent or the parent is missing (only under a concurrent writer).
  bool Up(BodyIndex& body, const Node*& node, std::size_t& steps,
          std::size_t& budget) const noexcept;

  void AttachChild(BodyIndex parent, BodyIndex child) noexcept;
  void DetachChild(BodyIndex parent, BodyIndex child) noexcept;
  // Makes `body` the root of its tree by reversing the parent links on its path to the root.
  // Depths are left stale (the caller re-levels the whole tree).
  void Reroot(BodyIndex body) noexcept;
  // Sets depth(top) = top_depth and re-levels its subtree; returns the subtree's body count.
  std::size_t Relevel(BodyIndex top, std::uint32_t top_depth) noexcept;

  FlatMap<Node> nodes_;
  FlatMap<TwistEdgeEnds> edges_;
};

}  // namespace semgraph::topology
