// File: semgraph/topology/pose_forest.h
//
// PoseForest: the topology of the scene graph's pose forest over frames 0 .. n-1. A pose edge
// tail -> head makes the tail the parent of the head (spec §2: P1, a frame has at most one pose
// parent; P2, edges never close a cycle). The forest is dynamic: Link joins a tree under a node
// of another tree, Cut splits a subtree off, Reroot reverses the path to the root. Only topology
// lives here; no names, no values.
//
// Two rootings of one tree. What callers see is the *semantic* forest: parent, first_child,
// next_sibling, depth, Root, ... follow the pose edges. Ancestor queries run on a
// *representation* of the same undirected tree rooted at an arbitrary node of it, its "rep
// root" R, with depths and jump pointers relative to R. The two are tied by the classic
// identity: with semantic root s,
//   lca_s(a, b) = the deepest (from R) of lca_R(a, b), lca_R(a, s), lca_R(b, s),
// and semantic depth(v) = rd(v) + rd(s) - 2 rd(lca_R(v, s)) (rd = depth from R). When s == R
// (every tree built parents first) each query is a single rep query and costs what it did
// before the split.
//
// Why: linking a tree under a node of another must not recompute the depths of the tree that
// moves (building a chain from the leaf up was quadratic). Link re-represents the *smaller* of
// the two trees only, re-rooted at its end of the new edge and hung under the other end; the
// larger keeps its rep root. A node is re-represented only when its tree at least doubles, so
// at most log2(n) times over any sequence of links: Link is O(log n) amortized, whatever the
// order of the adds (a new leaf and a new root are both O(1)). With cuts in between (potential
// sum over nodes of log2(n / size of its tree): a link pays min(a, b) out of it, a cut into
// parts of a and b nodes puts back at most min(a, b) (log2 n + 1.45), within a log factor of the
// cut's own O(min(a, b)) at least). Reroot only turns the semantic edges round and moves the
// semantic root: the representation stays.
//
// Rep jump pointers are skew-binary ("Myers", E. W. Myers, "An applicative random-access
// stack", 1983): jump(R) = R; a rep child v of p gets
//   jump(v) = jump(jump(p))  if p != R, j = jump(p) != R and rd(p) - rd(j) == rd(j) - rd(jump(j)),
//   jump(v) = p              otherwise.
// The jump of a node depends on its rep depth only, so any rep ancestor depth is reached in
// O(log n) jump-or-parent steps, with one word per node (binary lifting needs O(log n) words;
// DFS intervals are renumbered globally by every link).
//
// Layout: structure of arrays, eight std::uint32_t per node (32 bytes). Semantic: parent,
// first_child, next_sibling, prev_sibling (children form a doubly linked sibling list, so Cut
// unlinks in O(1) and a subtree is walked without a stack). Representation: rep_parent,
// rep_depth, rep_jump, rep_root. A rep root's own rep_parent and rep_jump slots are free (it has
// no parent and jumps to itself), so they hold its tree's data: rep_parent[R] = the semantic
// root, rep_jump[R] = the number of nodes. rep_root makes Root, SameTree and TreeKey O(1), which
// is what lets SceneTopology drop its union-find (8 bytes per frame): the total stays 32.
//
// Invariants (checked from scratch by CheckInvariants, which tests call after every mutation):
//  - semantic: parent(v) is invalid (v is a semantic root) or another node; v is in the child
//    list of parent(v) exactly once, roots are in no child list; no 2-cycle parent(parent(v)) = v.
//  - rep: rep_root(v) is a rep root R (rep_root(R) = R, rep_depth(R) = 0, and rep_depth(v) = 0
//    only for rep roots); for v != R: rep_depth(v) = rep_depth(rep_parent(v)) + 1 (so no rep
//    cycles), rep_root(v) = rep_root(rep_parent(v)), rep_jump(v) follows the rule above and lands
//    at rep depth d - (smallest term of d's skew-binary decomposition into terms 2^k - 1).
//  - same tree: the undirected edges {v, parent(v)} are exactly the edges {v, rep_parent(v)},
//    one to one (so the semantic parent links form a forest too, oriented towards one node per
//    tree); rep_parent[R] is the one semantic root of R's tree, rep_jump[R] its node count.
//
// Costs (n = size(), amortized over any sequence of mutations):
//   AddNode                                  O(1) amortized (allocates when the arrays grow)
//   Link(parent, root)                       O(log n) amortized over links (re-represents the
//                                            smaller tree; each Cut adds O(its cost * log n))
//   Cut(child)                               O(size of the part that does not hold the rep root)
//   Reroot(v)                                O(depth(v)) (path reversal; no depth recomputed)
//   parent, is_root, first_child,
//   next_sibling, size, Root, SameTree,
//   TreeKey, TreeSize                        O(1)
//   depth, AncestorAtDepth, IsAncestor,
//   CommonAncestor                           O(log n), noexcept, no allocation (one rep query
//                                            when the tree's semantic root is its rep root,
//                                            depth then O(1); else up to three)
//   ForEachInSubtree(root, f)                O(size of root's subtree) calls of f, no allocation
//   CheckInvariants                          O(n), allocates O(n) scratch (tests only)
//
// Thread safety: one writer (AddNode, Reserve, Link, Cut, Reroot) and any number of readers of
// the const methods, which never crash or loop while the writer changes the forest: nodes live
// in a RetiringArray (grown by copy, old arrays kept), every field is a base::Published
// (atomic), and the walks (depth, AncestorAtDepth, IsAncestor, CommonAncestor) check each
// index they follow against size() and stop after size() steps, answering an invalid index (0
// depth) when the forest was inconsistent under them. Their answers are meaningful only when
// the reader validates that no change overlapped (SceneTopology's change counter;
// docs/realtime.md); without a concurrent writer they are exact.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "semgraph/base/published.h"
#include "semgraph/base/retiring_array.h"
#include "semgraph/topology/export.h"
#include "semgraph/topology/ids.h"

namespace semgraph::topology {

class SEMGRAPH_TOPOLOGY_EXPORT PoseForest {
 public:
  PoseForest() = default;

  /// Number of nodes (frames 0 .. size()-1).
  [[nodiscard]] std::size_t size() const noexcept { return nodes_.size(); }

  /// Reserves room for `n` nodes in total (growing at least twofold when it grows, so that
  /// reserving one more at a time is O(1) amortized): AddNode up to n nodes does not allocate.
  /// On std::bad_alloc the forest is unchanged.
  void Reserve(std::size_t n);

  /// Adds a new isolated root and returns its index (= the old size()). O(1) amortized.
  /// @pre size() < FrameIndex::kInvalid (aborts otherwise).
  FrameIndex AddNode();

  /// Makes `root` a child of `parent`. Re-represents the smaller of the two trees (its rep
  /// depths and jumps, relative to the larger tree's rep root): O(log n) amortized.
  /// @pre both are nodes of this forest, `root` is a root, and `parent` is not in root's tree
  ///      (aborts via SEMGRAPH_DEMAND otherwise; callers reject such edges earlier with a code).
  void Link(FrameIndex parent, FrameIndex root);

  /// Removes the edge parent(child) -> child; child's subtree becomes a tree of its own. The
  /// part without the rep root is re-represented: O(size of that part).
  /// @pre `child` is a node of this forest and has a parent (aborts otherwise).
  void Cut(FrameIndex child);
  /// Makes v the root of its tree by reversing the edges on the path from v to the old root
  /// (the parent of each node on it becomes its child). The tree keeps its nodes and its
  /// representation. O(depth(v)).
  void Reroot(FrameIndex v);

  // Cheap accessors. @pre f is a node of this forest (checked by assert in debug builds only).

  /// The parent of f, or an invalid index when f is a root.
  [[nodiscard]] FrameIndex parent(FrameIndex f) const noexcept {
    return FrameIndex(nodes_[Checked(f)].parent);
  }
  [[nodiscard]] bool is_root(FrameIndex f) const noexcept {
    return nodes_[Checked(f)].parent == kNone;
  }
  /// The first child of f, or an invalid index when f is a leaf. Children are in no
  /// particular order (the most recently linked comes first).
  [[nodiscard]] FrameIndex first_child(FrameIndex f) const noexcept {
    return FrameIndex(nodes_[Checked(f)].first_child);
  }
  /// The next child of parent(f), or an invalid index when f is the last one (or a root).
  [[nodiscard]] FrameIndex next_sibling(FrameIndex f) const noexcept {
    return FrameIndex(nodes_[Checked(f)].next_sibling);
  }

  /// The root of f's tree. O(1).
  [[nodiscard]] FrameIndex Root(FrameIndex f) const noexcept {
    return FrameIndex(nodes_[nodes_[Checked(f)].rep_root].rep_parent);
  }
  /// True when a and b are in the same tree. O(1).
  [[nodiscard]] bool SameTree(FrameIndex a, FrameIndex b) const noexcept {
    return nodes_[Checked(a)].rep_root == nodes_[Checked(b)].rep_root;
  }
  /// A node of f's tree that names the tree: equal for all its nodes, different between trees.
  /// A tree keeps its key until a Link or Cut changes it (a Link keeps the larger tree's key,
  /// a Cut keeps it for one of the two parts); Reroot keeps it. O(1).
  [[nodiscard]] FrameIndex TreeKey(FrameIndex f) const noexcept {
    return FrameIndex(nodes_[Checked(f)].rep_root);
  }
  /// The number of nodes of f's tree. O(1).
  [[nodiscard]] std::uint32_t TreeSize(FrameIndex f) const noexcept {
    return nodes_[nodes_[Checked(f)].rep_root].rep_jump;
  }

  // Queries. @pre every argument is a node of this forest (debug assert only). All are
  // O(log n), noexcept, allocation-free and read-only.

  /// The number of edges between f and its root. O(1) when the tree's root is its rep root
  /// (trees built parents first), else O(log n).
  [[nodiscard]] std::uint32_t depth(FrameIndex f) const noexcept;

  /// The ancestor of f at depth d (f itself when d == depth(f)), or an invalid index when
  /// d > depth(f).
  [[nodiscard]] FrameIndex AncestorAtDepth(FrameIndex f, std::uint32_t d) const noexcept;

  /// True when `ancestor` lies on the path from `descendant` to its root. A node is its own
  /// ancestor.
  [[nodiscard]] bool IsAncestor(FrameIndex ancestor, FrameIndex descendant) const noexcept;

  /// The youngest (deepest) common ancestor of a and b, or an invalid index when they are in
  /// different trees. CommonAncestor(a, a) == a.
  [[nodiscard]] FrameIndex CommonAncestor(FrameIndex a, FrameIndex b) const noexcept;

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
      if (nodes_[v].first_child != kNone) {
        v = nodes_[v].first_child;
        continue;
      }
      // No child: climb until a node with a next sibling, but never above `top` (whose own
      // siblings are outside the subtree).
      while (v != top && nodes_[v].next_sibling == kNone) v = nodes_[v].parent;
      if (v == top) return;
      v = nodes_[v].next_sibling;
    }
  }

  /// Statistic: the number of node representations (rep depth and jump) computed by Link and
  /// Cut since construction. Link keeps it within n log2(n) over any sequence of links of n
  /// nodes; tests assert that bound, benchmarks may report it.
  [[nodiscard]] std::uint64_t rerepresented_nodes() const noexcept { return rerepresented_; }

  /// Bytes held by the node arrays (their capacity), for memory budgets.
  [[nodiscard]] std::size_t ApproximateBytes() const noexcept;

  /// Full check of every invariant listed at the top of this file, O(n). For tests and
  /// fuzzers; no query relies on it being called.
  [[nodiscard]] bool CheckInvariants() const;

 private:
  static constexpr std::uint32_t kNone = FrameIndex::kInvalid;

  std::uint32_t Checked(FrameIndex f) const noexcept {
    assert(f.value() < nodes_.size());
    return f.value();
  }
  // The rep jump pointer a new rep child of p gets (the skew-binary rule above).
  std::uint32_t JumpForChildOf(std::uint32_t p) const noexcept;
  // Rep queries: the rep ancestor of v at rep depth d <= rep_depth(v), and the rep LCA of two
  // nodes of one tree; kNone when a concurrent change left an index out of range or a walk
  // longer than the node count (see Thread safety).
  std::uint32_t RepAncestorAtDepth(std::uint32_t v, std::uint32_t d) const noexcept;
  std::uint32_t RepLca(std::uint32_t u, std::uint32_t v) const noexcept;
  // Re-represents the component of x (the semantic edges as they are, without the edge to
  // `above`): rooted at x, x hung under `above` (kNone: x becomes a rep root, whose two tree
  // slots the caller fills). Parents before children, without a stack. Returns the node count.
  std::uint32_t Represent(std::uint32_t x, std::uint32_t above) noexcept;

  // A node's fields side by side (32 bytes, two nodes per cache line): a link, a cut and a
  // query read several fields of one node, so each node costs one cache miss, not eight.
  struct Node {
    // Semantic forest.
    base::Published<std::uint32_t> parent, first_child, next_sibling, prev_sibling;
    // Representation. At a rep root R: rep_parent = semantic root, rep_jump = tree size.
    base::Published<std::uint32_t> rep_parent, rep_depth, rep_jump, rep_root;
  };
  using Nodes = base::RetiringArray<Node>::View;
  // RepAncestorAtDepth over one load of the node array (the walks' inner loop).
  static std::uint32_t RepAncestorAtDepth(Nodes nodes, std::uint32_t v, std::uint32_t d) noexcept;
  [[nodiscard]] std::uint32_t size32() const noexcept {
    return static_cast<std::uint32_t>(nodes_.size());
  }
  base::RetiringArray<Node> nodes_;
  std::uint64_t rerepresented_ = 0;
};

}  // namespace semgraph::topology
