#include "semgraph/topology/pose_forest.h"

#include <algorithm>
#include <bit>
#include <utility>

#include "semgraph/base/demand.h"

namespace semgraph::topology {

void PoseForest::Reserve(std::size_t n) {
  // Geometric growth, so that reserving one more node at a time stays O(1) amortized.
  const std::size_t capacity =
      std::min({parent_.capacity(), first_child_.capacity(), next_sibling_.capacity(),
                prev_sibling_.capacity(), rep_parent_.capacity(), rep_depth_.capacity(),
                rep_jump_.capacity(), rep_root_.capacity()});
  if (n <= capacity) return;
  n = std::max(n, 2 * capacity);
  // reserve() only changes capacity, so a bad_alloc part way leaves the forest as it was.
  parent_.reserve(n);
  first_child_.reserve(n);
  next_sibling_.reserve(n);
  prev_sibling_.reserve(n);
  rep_parent_.reserve(n);
  rep_depth_.reserve(n);
  rep_jump_.reserve(n);
  rep_root_.reserve(n);
}

FrameIndex PoseForest::AddNode() {
  const std::size_t n = size();
  // kNone must stay free to mean "no node".
  SEMGRAPH_DEMAND(n < kNone);
  // Grow all arrays up front, so that the push_backs below cannot throw and a failed
  // allocation cannot leave the arrays with different lengths.
  const std::size_t capacity =
      std::min({parent_.capacity(), first_child_.capacity(), next_sibling_.capacity(),
                prev_sibling_.capacity(), rep_parent_.capacity(), rep_depth_.capacity(),
                rep_jump_.capacity(), rep_root_.capacity()});
  if (capacity == n) Reserve(std::max<std::size_t>(8, 2 * n));
  const auto v = static_cast<std::uint32_t>(n);
  parent_.push_back(kNone);
  first_child_.push_back(kNone);
  next_sibling_.push_back(kNone);
  prev_sibling_.push_back(kNone);
  // A one-node tree: its own rep root, semantic root, of size 1.
  rep_parent_.push_back(v);
  rep_depth_.push_back(0);
  rep_jump_.push_back(1);
  rep_root_.push_back(v);
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
  // A rep root's jump slot holds its tree size, so it is never read as a jump: jump(R) = R
  // spans depth 0, never equal to the positive span above it.
  if (rep_depth_[p] == 0) return p;
  const std::uint32_t j = rep_jump_[p];
  if (rep_depth_[j] != 0 &&
      rep_depth_[p] - rep_depth_[j] == rep_depth_[j] - rep_depth_[rep_jump_[j]]) {
    return rep_jump_[j];
  }
  return p;
}

std::uint32_t PoseForest::Represent(std::uint32_t x, std::uint32_t above) noexcept {
  // Depth-first over the undirected tree, the neighbours of v in the order parent(v), then its
  // children; the rep parent (just set) is skipped, and serves as the way back, so no stack.
  const auto next = [this](std::uint32_t v, std::uint32_t u) {  // the neighbour of v after u
    return u == parent_[v] ? first_child_[v] : next_sibling_[u];
  };
  const auto skip = [this, &next](std::uint32_t v, std::uint32_t u) {  // past rep_parent(v)
    return u != kNone && u == rep_parent_[v] ? next(v, u) : u;
  };
  const auto first = [this, &skip](std::uint32_t v) {
    return skip(v, parent_[v] != kNone ? parent_[v] : first_child_[v]);
  };
  std::uint32_t key;
  if (above == kNone) {
    key = x;
    rep_parent_[x] = kNone;  // until the caller fills the tree slots: matches no neighbour
    rep_depth_[x] = 0;
    rep_jump_[x] = x;
  } else {
    key = rep_root_[above];
    rep_parent_[x] = above;
    rep_depth_[x] = rep_depth_[above] + 1;
    rep_jump_[x] = JumpForChildOf(above);
  }
  rep_root_[x] = key;
  std::uint32_t count = 1;
  std::uint32_t v = x;
  std::uint32_t u = first(x);
  while (true) {
    if (u != kNone) {  // down to u
      rep_parent_[u] = v;
      rep_depth_[u] = rep_depth_[v] + 1;
      rep_jump_[u] = JumpForChildOf(v);
      rep_root_[u] = key;
      ++count;
      v = u;
      u = first(v);
    } else {  // v done: back up to its rep parent, on to v's next sibling there
      if (v == x) break;
      const std::uint32_t w = rep_parent_[v];
      u = skip(w, next(w, v));
      v = w;
    }
  }
  rerepresented_ += count;
  return count;
}

void PoseForest::Link(FrameIndex parent, FrameIndex root) {
  SEMGRAPH_DEMAND(parent.value() < size() && root.value() < size());
  const std::uint32_t p = parent.value();
  const std::uint32_t r = root.value();
  SEMGRAPH_DEMAND(parent_[r] == kNone);              // P1: root has no pose parent yet
  SEMGRAPH_DEMAND(rep_root_[p] != rep_root_[r]);     // P2: the edge would close a cycle
  const std::uint32_t key_p = rep_root_[p], key_r = rep_root_[r];
  const std::uint32_t size_p = rep_jump_[key_p], size_r = rep_jump_[key_r];
  const std::uint32_t semantic_root = rep_parent_[key_p];
  parent_[r] = p;
  // Push r at the front of p's child list: O(1), no search.
  prev_sibling_[r] = kNone;
  next_sibling_[r] = first_child_[p];
  if (first_child_[p] != kNone) prev_sibling_[first_child_[p]] = r;
  first_child_[p] = r;
  // Small to large: the smaller tree is re-rooted at its end of the edge and hung under the
  // other end; the larger keeps its representation and its key.
  if (size_r <= size_p) {
    Represent(r, p);
    rep_jump_[key_p] = size_p + size_r;
  } else {
    Represent(p, r);
    rep_parent_[key_r] = semantic_root;
    rep_jump_[key_r] = size_p + size_r;
  }
}

void PoseForest::Cut(FrameIndex child) {
  SEMGRAPH_DEMAND(child.value() < size());
  const std::uint32_t c = child.value();
  const std::uint32_t p = parent_[c];
  SEMGRAPH_DEMAND(p != kNone);
  const std::uint32_t key = rep_root_[c];
  const std::uint32_t total = rep_jump_[key];
  const std::uint32_t semantic_root = rep_parent_[key];
  // The edge is either c -> p or p -> c in the representation (a rep root's parent slot is
  // not an edge, hence the depth test).
  const bool c_below = rep_depth_[c] != 0 && rep_parent_[c] == p;
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
  // Re-represent the part that lost its way to the rep root: the rep subtree below the edge.
  if (c_below) {  // c's subtree: a new tree of its own, rooted at c both ways
    const std::uint32_t moved = Represent(c, kNone);
    rep_parent_[c] = c;
    rep_jump_[c] = moved;
    rep_jump_[key] = total - moved;
  } else {  // the part above c (with the old semantic root) moves; c's part keeps the key
    const std::uint32_t moved = Represent(p, kNone);
    rep_parent_[p] = semantic_root;
    rep_jump_[p] = moved;
    rep_parent_[key] = c;
    rep_jump_[key] = total - moved;
  }
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
  // Same undirected tree: the representation stands, only the semantic root moves.
  rep_parent_[rep_root_[v.value()]] = v.value();
}

std::uint32_t PoseForest::RepAncestorAtDepth(std::uint32_t v, std::uint32_t d) const noexcept {
  // Take the jump whenever it does not overshoot depth d, else one parent step. Jump depths
  // are skew-binary, so this takes O(log depth) steps.
  while (rep_depth_[v] > d) {
    const std::uint32_t j = rep_jump_[v];
    v = rep_depth_[j] >= d ? j : rep_parent_[v];
  }
  return v;
}

std::uint32_t PoseForest::RepLca(std::uint32_t u, std::uint32_t v) const noexcept {
  if (rep_depth_[u] < rep_depth_[v]) std::swap(u, v);
  u = RepAncestorAtDepth(u, rep_depth_[v]);
  // u and v are now at equal depths, and a jump's target depth depends only on the depth, so
  // jump(u) and jump(v) are at equal depths too. Jump both while the targets differ (the common
  // ancestor is strictly above them), else step both to the parent: the same O(log n) search
  // as RepAncestorAtDepth, aimed at one below the common ancestor. Both are in one tree, so
  // they meet at the rep root at the latest (whose slots are never read: depth 0).
  while (u != v) {
    if (rep_jump_[u] != rep_jump_[v]) {
      u = rep_jump_[u];
      v = rep_jump_[v];
    } else {
      u = rep_parent_[u];
      v = rep_parent_[v];
    }
  }
  return u;
}

std::uint32_t PoseForest::depth(FrameIndex f) const noexcept {
  const std::uint32_t v = Checked(f);
  const std::uint32_t key = rep_root_[v];
  const std::uint32_t s = rep_parent_[key];
  if (s == key) return rep_depth_[v];
  return rep_depth_[v] + rep_depth_[s] - 2 * rep_depth_[RepLca(v, s)];
}

FrameIndex PoseForest::AncestorAtDepth(FrameIndex f, std::uint32_t d) const noexcept {
  const std::uint32_t v = Checked(f);
  const std::uint32_t key = rep_root_[v];
  const std::uint32_t s = rep_parent_[key];
  if (s == key) {
    return d > rep_depth_[v] ? FrameIndex() : FrameIndex(RepAncestorAtDepth(v, d));
  }
  // The semantic path s .. v climbs from s to m = lca_R(s, v), then descends to v.
  const std::uint32_t m = RepLca(v, s);
  const std::uint32_t up = rep_depth_[s] - rep_depth_[m];
  const std::uint32_t down = rep_depth_[v] - rep_depth_[m];
  if (d > up + down) return FrameIndex();
  if (d <= up) return FrameIndex(RepAncestorAtDepth(s, rep_depth_[s] - d));
  return FrameIndex(RepAncestorAtDepth(v, rep_depth_[m] + (d - up)));
}

bool PoseForest::IsAncestor(FrameIndex ancestor, FrameIndex descendant) const noexcept {
  const std::uint32_t a = Checked(ancestor);
  const std::uint32_t d = Checked(descendant);
  const std::uint32_t key = rep_root_[d];
  if (rep_root_[a] != key) return false;
  if (rep_parent_[key] == key) {
    return rep_depth_[a] <= rep_depth_[d] && RepAncestorAtDepth(d, rep_depth_[a]) == a;
  }
  return CommonAncestor(ancestor, descendant) == ancestor;
}

FrameIndex PoseForest::CommonAncestor(FrameIndex a, FrameIndex b) const noexcept {
  const std::uint32_t u = Checked(a);
  const std::uint32_t v = Checked(b);
  const std::uint32_t key = rep_root_[u];
  if (rep_root_[v] != key) return FrameIndex();  // different trees
  const std::uint32_t x = RepLca(u, v);
  const std::uint32_t s = rep_parent_[key];
  if (s == key) return FrameIndex(x);
  // Two of the three rep LCAs coincide; the semantic one is the deepest.
  const std::uint32_t y = RepLca(u, s);
  const std::uint32_t z = RepLca(v, s);
  std::uint32_t best = rep_depth_[x] >= rep_depth_[y] ? x : y;
  if (rep_depth_[z] > rep_depth_[best]) best = z;
  return FrameIndex(best);
}

std::size_t PoseForest::ApproximateBytes() const noexcept {
  return sizeof(std::uint32_t) *
         (parent_.capacity() + first_child_.capacity() + next_sibling_.capacity() +
          prev_sibling_.capacity() + rep_parent_.capacity() + rep_depth_.capacity() +
          rep_jump_.capacity() + rep_root_.capacity());
}

bool PoseForest::CheckInvariants() const {
  const std::size_t n = size();
  if (first_child_.size() != n || next_sibling_.size() != n || prev_sibling_.size() != n ||
      rep_parent_.size() != n || rep_depth_.size() != n || rep_jump_.size() != n ||
      rep_root_.size() != n) {
    return false;
  }
  // Bounds first, so that the checks below may index freely.
  for (std::size_t v = 0; v < n; ++v) {
    if (rep_parent_[v] >= n || rep_root_[v] >= n || (parent_[v] != kNone && parent_[v] >= n)) {
      return false;
    }
    if (rep_depth_[v] != 0 && rep_jump_[v] >= n) return false;
  }
  std::vector<std::uint32_t> count(n, 0);  // nodes per rep root
  std::size_t semantic_roots = 0, rep_roots = 0, non_roots = 0, listed_children = 0;
  for (std::uint32_t v = 0; v < n; ++v) {
    const std::uint32_t key = rep_root_[v];
    // Representation: a rep root is its own key, at depth 0, and nothing else is at depth 0.
    if (rep_root_[key] != key || rep_depth_[key] != 0 || (rep_depth_[v] == 0) != (key == v)) {
      return false;
    }
    ++count[key];
    if (key == v) {
      // Its tree slots: the semantic root is a semantic root of this tree.
      const std::uint32_t s = rep_parent_[v];
      if (rep_root_[s] != v || parent_[s] != kNone) return false;
      ++rep_roots;
    } else {
      const std::uint32_t q = rep_parent_[v];
      // depth = depth(rep parent) + 1 also rules out cycles: depths would have to increase all
      // the way round one (a wrap-around needs 2^32 nodes, more than an index can name).
      if (q == v || rep_depth_[v] != rep_depth_[q] + 1 || rep_root_[q] != key) return false;
      // The parent's jump is checked in its own turn, so by induction every jump follows the
      // rule and is a rep ancestor; the rule itself is the skew-binary one (the O(log n)
      // bounds rely on it).
      if (rep_jump_[v] != JumpForChildOf(q)) return false;
      if (rep_depth_[rep_jump_[v]] != SkewBinaryJumpDepth(rep_depth_[v])) return false;
    }
    // Semantic: the one root of its tree, or an edge {v, parent(v)} that is a rep edge.
    const std::uint32_t p = parent_[v];
    if (p == kNone) {
      if (rep_parent_[key] != v || next_sibling_[v] != kNone || prev_sibling_[v] != kNone) {
        return false;
      }
      ++semantic_roots;
    } else {
      if (p == v || parent_[p] == v) return false;  // a 2-cycle would use one rep edge twice
      const bool up = rep_depth_[v] != 0 && rep_parent_[v] == p;
      const bool down = rep_depth_[p] != 0 && rep_parent_[p] == v;
      if (!up && !down) return false;
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
  for (std::uint32_t v = 0; v < n; ++v) {
    if (rep_root_[v] == v && rep_jump_[v] != count[v]) return false;  // tree sizes
  }
  // Each semantic edge is a rep edge, and no two are the same one (no 2-cycles; the edge of v
  // is {v, parent(v)}); one semantic root per rep tree makes the counts equal, so the edge sets
  // are equal. A node is listed only under parent(node), at most once there; equal counts
  // mean every non-root is listed.
  return semantic_roots == rep_roots && non_roots == n - rep_roots && listed_children == non_roots;
}

}  // namespace semgraph::topology
