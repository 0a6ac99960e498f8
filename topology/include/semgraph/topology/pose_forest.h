// File: semgraph/topology/pose_forest.h
//
// PoseForest: the topology of the scene graph's pose forest over frames 0 .. n-1. A pose edge
// tail -> head makes the tail the parent of the head (spec §2: P1, a frame has at most one pose
// parent; P2, edges never close a cycle). The forest is dynamic: Link joins a tree under a node
// of another tree, Cut splits a subtree off. Only topology lives here; no names, no values.
//
// Ancestor queries use one skew-binary ("Myers") jump pointer per node (E. W. Myers, "An
// applicative random-access stack", 1983): jump(root) = root; a new child v of p gets
//   jump(v) = jump(jump(p))  if p has a parent and depth(p) - depth(j) == depth(j) - depth(jump(j))
//             with j = jump(p),
//   jump(v) = p              otherwise.
// The jump of a node depends on its depth only, so any ancestor depth is reached in O(log n)
// jump-or-parent steps. Unlike binary lifting (O(log n) words per node) or DFS intervals (which
// a Link or Cut renumbers globally), this costs one word per node and a topology change only
// touches the tree that moves.
//
// Layout: structure of arrays, six std::uint32_t per node (24 bytes): parent, depth, jump,
// first_child, next_sibling, prev_sibling. Children form a doubly linked sibling list so Cut is
// O(1) before the subtree's depths are redone, and a subtree can be walked without a stack.
//
// Invariants (checked by CheckInvariants, which tests call after every mutation):
//  - parent(v) is invalid (v is a root) or another node; depth(root) = 0 and
//    depth(v) = depth(parent(v)) + 1, hence no cycles.
//  - v is in the child list of parent(v) exactly once; roots are in no child list.
//  - jump(root) = root; jump(v) is the ancestor of v given by the rule above, which puts it at
//    depth d - (smallest term of d's skew-binary decomposition into terms 2^k - 1), d = depth(v).
//
// Costs (n = size()):
//   AddNode                                  O(1) amortized (allocates when the arrays grow)
//   Link(parent, root)                       O(log n + size of root's tree)
//   Cut(child)                               O(size of child's subtree)
//   Reroot(v)                                O(size of v's tree)
//   parent, depth, is_root, first_child,
//   next_sibling, size                       O(1)
//   Root, AncestorAtDepth, IsAncestor,
//   CommonAncestor, SameTree                 O(log n), noexcept, no allocation
//   ForEachInSubtree(root, f)                O(size of root's subtree) calls of f, no allocation
//   CheckInvariants                          O(n log n), no allocation
//
// Thread safety: const methods may run concurrently (no mutable state, no locks, no lazy work);
// AddNode, Reserve, Link and Cut need exclusive access.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "semgraph/topology/export.h"
#include "semgraph/topology/ids.h"

namespace semgraph::topology {

class SEMGRAPH_TOPOLOGY_EXPORT PoseForest {
 public:
  PoseForest() = default;

  /// Number of nodes (frames 0 .. size()-1).
  [[nodiscard]] std::size_t size() const noexcept { return parent_.size(); }

  /// Reserves room for `n` nodes in total (growing at least twofold when it grows, so that
  /// reserving one more at a time is O(1) amortized): AddNode up to n nodes does not allocate.
  /// On std::bad_alloc the forest is unchanged.
  void Reserve(std::size_t n);

  /// Adds a new isolated root and returns its index (= the old size()). O(1) amortized.
  /// @pre size() < FrameIndex::kInvalid (aborts otherwise).
  FrameIndex AddNode();

  /// Makes `root` a child of `parent`, and recomputes the depth and jump pointer of every node of
  /// root's tree. Cost O(log n) for the precondition check plus O(size of root's tree).
  /// @pre both are nodes of this forest, `root` is a root, and `parent` is not in root's tree
  ///      (aborts via SEMGRAPH_DEMAND otherwise; callers reject such edges earlier with a code).
  void Link(FrameIndex parent, FrameIndex root);

  /// Removes the edge parent(child) -> child; child's subtree becomes a tree of its own with
  /// recomputed depths and jumps. Cost O(size of child's subtree).
  /// @pre `child` is a node of this forest and has a parent (aborts otherwise).
  void Cut(FrameIndex child);
  /// Makes v the root of its tree by reversing the edges on the path from v to the old root
  /// (the parent of each node on it becomes its child). The tree keeps its nodes; depths and
  /// jumps are recomputed. O(size of the tree).
  void Reroot(FrameIndex v);

  // Cheap accessors. @pre f is a node of this forest (checked by assert in debug builds only).

  /// The parent of f, or an invalid index when f is a root.
  [[nodiscard]] FrameIndex parent(FrameIndex f) const noexcept {
    return FrameIndex(parent_[Checked(f)]);
  }
  /// The number of edges between f and its root.
  [[nodiscard]] std::uint32_t depth(FrameIndex f) const noexcept { return depth_[Checked(f)]; }
  [[nodiscard]] bool is_root(FrameIndex f) const noexcept { return parent_[Checked(f)] == kNone; }
  /// The first child of f, or an invalid index when f is a leaf. Children are in no
  /// particular order (the most recently linked comes first).
  [[nodiscard]] FrameIndex first_child(FrameIndex f) const noexcept {
    return FrameIndex(first_child_[Checked(f)]);
  }
  /// The next child of parent(f), or an invalid index when f is the last one (or a root).
  [[nodiscard]] FrameIndex next_sibling(FrameIndex f) const noexcept {
    return FrameIndex(next_sibling_[Checked(f)]);
  }

  // Queries. @pre every argument is a node of this forest (debug assert only). All are
  // O(log n), noexcept, allocation-free and read-only.

  /// The root of f's tree.
  [[nodiscard]] FrameIndex Root(FrameIndex f) const noexcept;

  /// The ancestor of f at depth d (f itself when d == depth(f)), or an invalid index when
  /// d > depth(f).
  [[nodiscard]] FrameIndex AncestorAtDepth(FrameIndex f, std::uint32_t d) const noexcept;

  /// True when `ancestor` lies on the path from `descendant` to its root. A node is its own
  /// ancestor.
  [[nodiscard]] bool IsAncestor(FrameIndex ancestor, FrameIndex descendant) const noexcept;

  /// The youngest (deepest) common ancestor of a and b, or an invalid index when they are in
  /// different trees. CommonAncestor(a, a) == a.
  [[nodiscard]] FrameIndex CommonAncestor(FrameIndex a, FrameIndex b) const noexcept;

  /// True when a and b are in the same tree (have the same root).
  [[nodiscard]] bool SameTree(FrameIndex a, FrameIndex b) const noexcept;

  /// Calls f(FrameIndex) once for every node of the subtree rooted at `root` (root included),
  /// in preorder: a node is visited before its children. Iterative, constant extra space: it
  /// walks the child/sibling/parent links instead of keeping a stack, so a 10^6-deep chain is
  /// fine. `f` must not Link or Cut while the walk runs. O(size of the subtree).
  template <class F>
  void ForEachInSubtree(FrameIndex root, F&& f) const {
    const std::uint32_t top = Checked(root);
    std::uint32_t v = top;
    while (true) {
      f(FrameIndex(v));
      if (first_child_[v] != kNone) {
        v = first_child_[v];
        continue;
      }
      // No child: climb until a node with a next sibling, but never above `top` (whose own
      // siblings are outside the subtree).
      while (v != top && next_sibling_[v] == kNone) v = parent_[v];
      if (v == top) return;
      v = next_sibling_[v];
    }
  }

  /// Bytes held by the node arrays (their capacity), for memory budgets.
  [[nodiscard]] std::size_t ApproximateBytes() const noexcept;

  /// Full check of every invariant listed at the top of this file, O(n log n). For tests and
  /// fuzzers; no query relies on it being called.
  [[nodiscard]] bool CheckInvariants() const;

 private:
  static constexpr std::uint32_t kNone = FrameIndex::kInvalid;

  std::uint32_t Checked(FrameIndex f) const noexcept {
    assert(f.value() < parent_.size());
    return f.value();
  }
  // The jump pointer a new child of p gets (the skew-binary rule above).
  std::uint32_t JumpForChildOf(std::uint32_t p) const noexcept;
  // Sets depth and jump of `top` from its parent (or as a root) and of all its descendants,
  // parents before children.
  void RecomputeSubtree(std::uint32_t top) noexcept;

  std::vector<std::uint32_t> parent_;
  std::vector<std::uint32_t> depth_;
  std::vector<std::uint32_t> jump_;
  std::vector<std::uint32_t> first_child_;
  std::vector<std::uint32_t> next_sibling_;
  std::vector<std::uint32_t> prev_sibling_;
};

}  // namespace semgraph::topology
