#include "semgraph/topology/pose_forest.h"

#include <algorithm>
#include <bit>
#include <utility>

#include "semgraph/base/demand.h"

namespace semgraph::topology {

void PoseForest::Reserve(std::size_t n) {
  // Geometric growth, so that reserving one more node at a time stays O(1) amortized.
  const std::size_t capacity =
      std::min({parent_.capacity(), depth_.capacity(), jump_.capacity(), first_child_.capacity(),
                next_sibling_.capacity(), prev_sibling_.capacity()});
  if (n <= capacity) return;
  n = std::max(n, 2 * capacity);
  // reserve() only changes capacity, so a bad_alloc part way leaves the forest as it was.
  parent_.reserve(n);
  depth_.reserve(n);
  jump_.reserve(n);
  first_child_.reserve(n);
  next_sibling_.reserve(n);
  prev_sibling_.reserve(n);
}

FrameIndex PoseForest::AddNode() {
  const std::size_t n = size();
  // kNone must stay free to mean "no node".
  SEMGRAPH_DEMAND(n < kNone);
  // Grow all six arrays up front, so that the push_backs below cannot throw and a failed
  // allocation cannot leave the arrays with different lengths.
  const std::size_t capacity =
      std::min({parent_.capacity(), depth_.capacity(), jump_.capacity(), first_child_.capacity(),
                next_sibling_.capacity(), prev_sibling_.capacity()});
  if (capacity == n) Reserve(std::max<std::size_t>(8, 2 * n));
  const auto v = static_cast<std::uint32_t>(n);
  parent_.push_back(kNone);
  depth_.push_back(0);
  jump_.push_back(v);  // a root jumps to itself
  first_child_.push_back(kNone);
  next_sibling_.push_back(kNone);
  prev_sibling_.push_back(kNone);
  return FrameIndex(v);
}

namespace {

// Independent closed form of the rule, for CheckInvariants: the jump from depth d >= 1 lands
// at d minus the smallest term of d's greedy decomposition into terms 2^k - 1 (the canonical
// skew-binary representation). O(log d).
std::uint32_t SkewBinaryJumpDepth(std::uint32_t d) noexcept {
  std::uint64_t rest = d;
  std::uint64_t term = 0;
  while (rest > 0) {
    term = (std::uint64_t{1} << (std::bit_width(rest + 1) - 1)) - 1;  // largest 2^k - 1 <= rest
    rest -= term;
  }
  return static_cast<std::uint32_t>(d - term);
}

}  // namespace

std::uint32_t PoseForest::JumpForChildOf(std::uint32_t p) const noexcept {
  // Skew-binary rule: when the two jumps above p span equal depths, a child of p can skip both
  // (their sum plus one is the next skew-binary term); otherwise it starts a new jump of one.
  const std::uint32_t j = jump_[p];
  if (parent_[p] != kNone && depth_[p] - depth_[j] == depth_[j] - depth_[jump_[j]]) {
    return jump_[j];
  }
  return p;
}

void PoseForest::RecomputeSubtree(std::uint32_t top) noexcept {
  // Preorder visits a parent before its children, so each node reads final parent values.
  ForEachInSubtree(FrameIndex(top), [this](FrameIndex f) {
    const std::uint32_t v = f.value();
    const std::uint32_t p = parent_[v];
    if (p == kNone) {
      depth_[v] = 0;
      jump_[v] = v;
    } else {
      depth_[v] = depth_[p] + 1;
      jump_[v] = JumpForChildOf(p);
    }
  });
}

void PoseForest::Link(FrameIndex parent, FrameIndex root) {
  SEMGRAPH_DEMAND(parent.value() < size() && root.value() < size());
  const std::uint32_t p = parent.value();
  const std::uint32_t r = root.value();
  SEMGRAPH_DEMAND(parent_[r] == kNone);  // P1: root has no pose parent yet
  SEMGRAPH_DEMAND(Root(parent) != root);  // P2: the edge would close a cycle
  parent_[r] = p;
  // Push r at the front of p's child list: O(1), no search.
  prev_sibling_[r] = kNone;
  next_sibling_[r] = first_child_[p];
  if (first_child_[p] != kNone) prev_sibling_[first_child_[p]] = r;
  first_child_[p] = r;
  RecomputeSubtree(r);
}

void PoseForest::Cut(FrameIndex child) {
  SEMGRAPH_DEMAND(child.value() < size());
  const std::uint32_t c = child.value();
  const std::uint32_t p = parent_[c];
  SEMGRAPH_DEMAND(p != kNone);
  // Unlink c from p's doubly linked child list in O(1).
  const std::uint32_t prev = prev_sibling_[c];
  const std::uint32_t next = next_sibling_[c];
  if (prev != kNone) {
    next_sibling_[prev] = next;
  } else {
    first_child_[p] = next;
  }
  if (next != kNone) prev_sibling_[next] = prev;
  parent_[c] = kNone;
  prev_sibling_[c] = kNone;
  next_sibling_[c] = kNone;
  RecomputeSubtree(c);
}

void PoseForest::Reroot(FrameIndex v) {
  SEMGRAPH_DEMAND(v.value() < size());
  const auto unlink = [this](std::uint32_t c) {  // c out of its parent's child list, O(1)
    const std::uint32_t p = parent_[c], prev = prev_sibling_[c], next = next_sibling_[c];
    if (prev != kNone) {
      next_sibling_[prev] = next;
    } else {
      first_child_[p] = next;
    }
    if (next != kNone) prev_sibling_[next] = prev;
    prev_sibling_[c] = next_sibling_[c] = kNone;
  };
  const auto push_child = [this](std::uint32_t p, std::uint32_t c) {
    parent_[c] = p;
    prev_sibling_[c] = kNone;
    next_sibling_[c] = first_child_[p];
    if (first_child_[p] != kNone) prev_sibling_[first_child_[p]] = c;
    first_child_[p] = c;
  };
  // Walk up from v, turning each edge parent -> child into child -> parent.
  std::uint32_t child = v.value();
  std::uint32_t parent = parent_[child];
  if (parent == kNone) return;  // already the root
  unlink(child);
  parent_[child] = kNone;
  while (parent != kNone) {
    const std::uint32_t grandparent = parent_[parent];
    if (grandparent != kNone) unlink(parent);
    push_child(child, parent);
    child = parent;
    parent = grandparent;
  }
  RecomputeSubtree(v.value());
}

FrameIndex PoseForest::AncestorAtDepth(FrameIndex f, std::uint32_t d) const noexcept {
  std::uint32_t v = Checked(f);
  if (d > depth_[v]) return FrameIndex();
  // Take the jump whenever it does not overshoot depth d, else one parent step. Jump depths
  // are skew-binary, so this takes O(log depth) steps.
  while (depth_[v] > d) {
    const std::uint32_t j = jump_[v];
    v = depth_[j] >= d ? j : parent_[v];
  }
  return FrameIndex(v);
}

FrameIndex PoseForest::Root(FrameIndex f) const noexcept { return AncestorAtDepth(f, 0); }

bool PoseForest::IsAncestor(FrameIndex ancestor, FrameIndex descendant) const noexcept {
  const std::uint32_t d = depth_[Checked(ancestor)];
  return d <= depth_[Checked(descendant)] && AncestorAtDepth(descendant, d) == ancestor;
}

FrameIndex PoseForest::CommonAncestor(FrameIndex a, FrameIndex b) const noexcept {
  std::uint32_t u = Checked(a);
  std::uint32_t v = Checked(b);
  if (depth_[u] < depth_[v]) std::swap(u, v);
  u = AncestorAtDepth(FrameIndex(u), depth_[v]).value();
  // u and v are now at equal depths, and a jump's target depth depends only on the depth, so
  // jump(u) and jump(v) are at equal depths too. Jump both while the targets differ (the common
  // ancestor is strictly above them), else step both to the parent: the same O(log n) search
  // as AncestorAtDepth, aimed at one below the common ancestor.
  while (u != v) {
    if (parent_[u] == kNone) return FrameIndex();  // two different roots: different trees
    if (jump_[u] != jump_[v]) {
      u = jump_[u];
      v = jump_[v];
    } else {
      u = parent_[u];
      v = parent_[v];
    }
  }
  return FrameIndex(u);
}

bool PoseForest::SameTree(FrameIndex a, FrameIndex b) const noexcept {
  return Root(a) == Root(b);
}

std::size_t PoseForest::ApproximateBytes() const noexcept {
  return sizeof(std::uint32_t) *
         (parent_.capacity() + depth_.capacity() + jump_.capacity() + first_child_.capacity() +
          next_sibling_.capacity() + prev_sibling_.capacity());
}

bool PoseForest::CheckInvariants() const {
  const std::size_t n = size();
  if (depth_.size() != n || jump_.size() != n || first_child_.size() != n ||
      next_sibling_.size() != n || prev_sibling_.size() != n) {
    return false;
  }
  // Bounds first, so that the checks below may index freely.
  for (std::size_t v = 0; v < n; ++v) {
    if (jump_[v] >= n || (parent_[v] != kNone && parent_[v] >= n)) return false;
  }
  std::size_t non_roots = 0;
  std::size_t listed_children = 0;
  for (std::uint32_t v = 0; v < n; ++v) {
    const std::uint32_t p = parent_[v];
    if (p == kNone) {
      // A root: depth 0, jumps to itself, in no child list.
      if (depth_[v] != 0 || jump_[v] != v || next_sibling_[v] != kNone ||
          prev_sibling_[v] != kNone) {
        return false;
      }
    } else {
      // depth = depth(parent) + 1 also rules out cycles: depths would have to increase all
      // the way round one (a wrap-around needs 2^32 nodes, more than an index can name).
      if (p == v || depth_[v] != depth_[p] + 1) return false;
      // The parent's jump is checked in its own turn, so by induction every jump follows the
      // rule and is an ancestor.
      if (jump_[v] != JumpForChildOf(p)) return false;
      // ... and the rule itself is the skew-binary one, which the O(log n) bounds rely on.
      if (depth_[jump_[v]] != SkewBinaryJumpDepth(depth_[v])) return false;
      ++non_roots;
    }
    // v's child list: each entry names v as parent, back links match, and no loop (a node in
    // two places of one list would make it loop, caught by the length bound).
    std::uint32_t prev = kNone;
    std::size_t length = 0;
    for (std::uint32_t c = first_child_[v]; c != kNone; c = next_sibling_[c]) {
      if (c >= n || parent_[c] != v || prev_sibling_[c] != prev || ++length > n) return false;
      prev = c;
    }
    listed_children += length;
  }
  // A node is listed only under parent(node), at most once there; equal counts mean every
  // non-root is listed.
  return listed_children == non_roots;
}

}  // namespace semgraph::topology
