#include "semgraph/topology/pose_forest.h"

#include <algorithm>
#include <bit>
#include <utility>

#include "semgraph/base/demand.h"

namespace semgraph::topology {

void PoseForest::Reserve(std::size_t n) {
  // Geometric growth, so that reserving one more node at a time stays O(1) amortized.
  const std::size_t capacity = nodes_.capacity();
  if (n <= capacity) return;
  // reserve() only changes capacity, so a bad_alloc leaves the forest as it was.
  nodes_.reserve(std::max(n, 2 * capacity));
}

FrameIndex PoseForest::AddNode() {
  const std::size_t n = size();
  // kNone must stay free to mean "no node".
  SEMGRAPH_DEMAND(n < kNone);
  if (nodes_.capacity() == n) Reserve(std::max<std::size_t>(8, 2 * n));
  const auto v = static_cast<std::uint32_t>(n);
  // A one-node tree: its own rep root, semantic root, of size 1.
  nodes_.push_back(Node{kNone, kNone, kNone, kNone, v, 0, 1, v});
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
  if (nodes_[p].rep_depth == 0) return p;
  const std::uint32_t j = nodes_[p].rep_jump;
  if (nodes_[j].rep_depth != 0 && nodes_[p].rep_depth - nodes_[j].rep_depth ==
                                      nodes_[j].rep_depth - nodes_[nodes_[j].rep_jump].rep_depth) {
    return nodes_[j].rep_jump;
  }
  return p;
}

std::uint32_t PoseForest::Represent(std::uint32_t x, std::uint32_t above) noexcept {
  // Depth-first over the undirected tree, the neighbours of v in the order parent(v), then its
  // children; the rep parent (just set) is skipped, and serves as the way back, so no stack.
  const auto next = [this](std::uint32_t v, std::uint32_t u) {  // the neighbour of v after u
    return u == nodes_[v].parent ? nodes_[v].first_child.load() : nodes_[u].next_sibling.load();
  };
  const auto skip = [this, &next](std::uint32_t v, std::uint32_t u) {  // past rep_parent(v)
    return u != kNone && u == nodes_[v].rep_parent ? next(v, u) : u;
  };
  const auto first = [this, &skip](std::uint32_t v) {
    return skip(v, nodes_[v].parent != kNone ? nodes_[v].parent : nodes_[v].first_child);
  };
  std::uint32_t key;
  if (above == kNone) {
    key = x;
    nodes_[x].rep_parent = kNone;  // until the caller fills the tree slots: matches no neighbour
    nodes_[x].rep_depth = 0;
    nodes_[x].rep_jump = x;
  } else {
    key = nodes_[above].rep_root;
    nodes_[x].rep_parent = above;
    nodes_[x].rep_depth = nodes_[above].rep_depth + 1;
    nodes_[x].rep_jump = JumpForChildOf(above);
  }
  nodes_[x].rep_root = key;
  std::uint32_t count = 1;
  std::uint32_t v = x;
  std::uint32_t u = first(x);
  while (true) {
    if (u != kNone) {  // down to u
      nodes_[u].rep_parent = v;
      nodes_[u].rep_depth = nodes_[v].rep_depth + 1;
      nodes_[u].rep_jump = JumpForChildOf(v);
      nodes_[u].rep_root = key;
      ++count;
      v = u;
      u = first(v);
    } else {  // v done: back up to its rep parent, on to v's next sibling there
      if (v == x) break;
      const std::uint32_t w = nodes_[v].rep_parent;
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
  SEMGRAPH_DEMAND(nodes_[r].parent == kNone);                 // P1: root has no pose parent yet
  SEMGRAPH_DEMAND(nodes_[p].rep_root != nodes_[r].rep_root);  // P2: the edge would close a cycle
  const std::uint32_t key_p = nodes_[p].rep_root, key_r = nodes_[r].rep_root;
  const std::uint32_t size_p = nodes_[key_p].rep_jump, size_r = nodes_[key_r].rep_jump;
  const std::uint32_t semantic_root = nodes_[key_p].rep_parent;
  nodes_[r].parent = p;
  // Push r at the front of p's child list: O(1), no search.
  nodes_[r].prev_sibling = kNone;
  nodes_[r].next_sibling = nodes_[p].first_child;
  if (nodes_[p].first_child != kNone) nodes_[nodes_[p].first_child].prev_sibling = r;
  nodes_[p].first_child = r;
  // Small to large: the smaller tree is re-rooted at its end of the edge and hung under the
  // other end; the larger keeps its representation and its key.
  if (size_r <= size_p) {
    Represent(r, p);
    nodes_[key_p].rep_jump = size_p + size_r;
  } else {
    Represent(p, r);
    nodes_[key_r].rep_parent = semantic_root;
    nodes_[key_r].rep_jump = size_p + size_r;
  }
}

void PoseForest::Cut(FrameIndex child) {
  SEMGRAPH_DEMAND(child.value() < size());
  const std::uint32_t c = child.value();
  const std::uint32_t p = nodes_[c].parent;
  SEMGRAPH_DEMAND(p != kNone);
  const std::uint32_t key = nodes_[c].rep_root;
  const std::uint32_t total = nodes_[key].rep_jump;
  const std::uint32_t semantic_root = nodes_[key].rep_parent;
  // The edge is either c -> p or p -> c in the representation (a rep root's parent slot is
  // not an edge, hence the depth test).
  const bool c_below = nodes_[c].rep_depth != 0 && nodes_[c].rep_parent == p;
  // Unlink c from p's doubly linked child list in O(1).
  const std::uint32_t prev = nodes_[c].prev_sibling;
  const std::uint32_t next = nodes_[c].next_sibling;
  if (prev != kNone) {
    nodes_[prev].next_sibling = next;
  } else {
    nodes_[p].first_child = next;
  }
  if (next != kNone) nodes_[next].prev_sibling = prev;
  nodes_[c].parent = kNone;
  nodes_[c].prev_sibling = kNone;
  nodes_[c].next_sibling = kNone;
  // Re-represent the part that lost its way to the rep root: the rep subtree below the edge.
  if (c_below) {  // c's subtree: a new tree of its own, rooted at c both ways
    const std::uint32_t moved = Represent(c, kNone);
    nodes_[c].rep_parent = c;
    nodes_[c].rep_jump = moved;
    nodes_[key].rep_jump = total - moved;
  } else {  // the part above c (with the old semantic root) moves; c's part keeps the key
    const std::uint32_t moved = Represent(p, kNone);
    nodes_[p].rep_parent = semantic_root;
    nodes_[p].rep_jump = moved;
    nodes_[key].rep_parent = c;
    nodes_[key].rep_jump = total - moved;
  }
}

void PoseForest::Reroot(FrameIndex v) {
  SEMGRAPH_DEMAND(v.value() < size());
  const auto unlink = [this](std::uint32_t c) {  // c out of its parent's child list, O(1)
    const std::uint32_t p = nodes_[c].parent, prev = nodes_[c].prev_sibling,
                        next = nodes_[c].next_sibling;
    if (prev != kNone) {
      nodes_[prev].next_sibling = next;
    } else {
      nodes_[p].first_child = next;
    }
    if (next != kNone) nodes_[next].prev_sibling = prev;
    nodes_[c].prev_sibling = nodes_[c].next_sibling = kNone;
  };
  const auto push_child = [this](std::uint32_t p, std::uint32_t c) {
    nodes_[c].parent = p;
    nodes_[c].prev_sibling = kNone;
    nodes_[c].next_sibling = nodes_[p].first_child;
    if (nodes_[p].first_child != kNone) nodes_[nodes_[p].first_child].prev_sibling = c;
    nodes_[p].first_child = c;
  };
  // Walk up from v, turning each edge parent -> child into child -> parent.
  std::uint32_t child = v.value();
  std::uint32_t parent = nodes_[child].parent;
  if (parent == kNone) return;  // already the root
  unlink(child);
  nodes_[child].parent = kNone;
  while (parent != kNone) {
    const std::uint32_t grandparent = nodes_[parent].parent;
    if (grandparent != kNone) unlink(parent);
    push_child(child, parent);
    child = parent;
    parent = grandparent;
  }
  // Same undirected tree: the representation stands, only the semantic root moves.
  nodes_[nodes_[v.value()].rep_root].rep_parent = v.value();
}

std::uint32_t PoseForest::RepAncestorAtDepth(std::uint32_t v, std::uint32_t d) const noexcept {
  return RepAncestorAtDepth(nodes_.view(), v, d);
}

std::uint32_t PoseForest::RepAncestorAtDepth(Nodes nodes, std::uint32_t v,
                                             std::uint32_t d) noexcept {
  // Take the jump whenever it does not overshoot depth d, else one parent step. Jump depths
  // are skew-binary, so this takes O(log depth) steps. The bounds only matter to a reader
  // racing the writer (each step lowers the depth in a consistent forest).
  const auto n = static_cast<std::uint32_t>(nodes.size);
  const Node* node = nodes.data;
  for (std::uint32_t steps = 0; v < n && node[v].rep_depth > d; ++steps) {
    const std::uint32_t j = node[v].rep_jump;
    if (j >= n || steps == n) return kNone;
    v = node[j].rep_depth >= d ? j : node[v].rep_parent.load();
  }
  return v < n ? v : kNone;
}

std::uint32_t PoseForest::RepLca(std::uint32_t u, std::uint32_t v) const noexcept {
  const Nodes nodes = nodes_.view();
  const Node* node = nodes.data;
  if (node[u].rep_depth < node[v].rep_depth) std::swap(u, v);
  u = RepAncestorAtDepth(nodes, u, node[v].rep_depth);
  // u and v are now at equal depths, and a jump's target depth depends only on the depth, so
  // jump(u) and jump(v) are at equal depths too. Jump both while the targets differ (the common
  // ancestor is strictly above them), else step both to the parent: the same O(log n) search
  // as RepAncestorAtDepth, aimed at one below the common ancestor. Both are in one tree, so
  // they meet at the rep root at the latest (whose slots are never read: depth 0).
  const auto n = static_cast<std::uint32_t>(nodes.size);
  for (std::uint32_t steps = 0; u != v; ++steps) {
    if (u >= n || steps == n) return kNone;  // only under a concurrent change
    const std::uint32_t ju = node[u].rep_jump, jv = node[v].rep_jump;
    if (ju != jv) {
      u = ju;
      v = jv;
    } else {
      u = node[u].rep_parent;
      v = node[v].rep_parent;
    }
    if (v >= n) return kNone;
  }
  return u;
}

std::uint32_t PoseForest::depth(FrameIndex f) const noexcept {
  const std::uint32_t v = Checked(f);
  const std::uint32_t key = nodes_[v].rep_root;
  const std::uint32_t s = nodes_[key].rep_parent;
  if (s == key) return nodes_[v].rep_depth;
  const std::uint32_t m = RepLca(v, s);
  if (m == kNone) return 0;
  return nodes_[v].rep_depth + nodes_[s].rep_depth - 2 * nodes_[m].rep_depth;
}

FrameIndex PoseForest::AncestorAtDepth(FrameIndex f, std::uint32_t d) const noexcept {
  const std::uint32_t v = Checked(f);
  const std::uint32_t key = nodes_[v].rep_root;
  const std::uint32_t s = nodes_[key].rep_parent;
  if (s == key) {
    return d > nodes_[v].rep_depth ? FrameIndex() : FrameIndex(RepAncestorAtDepth(v, d));
  }
  // The semantic path s .. v climbs from s to m = lca_R(s, v), then descends to v.
  const std::uint32_t m = RepLca(v, s);
  if (m == kNone) return FrameIndex();
  const std::uint32_t up = nodes_[s].rep_depth - nodes_[m].rep_depth;
  const std::uint32_t down = nodes_[v].rep_depth - nodes_[m].rep_depth;
  if (d > up + down) return FrameIndex();
  if (d <= up) return FrameIndex(RepAncestorAtDepth(s, nodes_[s].rep_depth - d));
  return FrameIndex(RepAncestorAtDepth(v, nodes_[m].rep_depth + (d - up)));
}

bool PoseForest::IsAncestor(FrameIndex ancestor, FrameIndex descendant) const noexcept {
  const std::uint32_t a = Checked(ancestor);
  const std::uint32_t d = Checked(descendant);
  const std::uint32_t key = nodes_[d].rep_root;
  if (nodes_[a].rep_root != key) return false;
  if (nodes_[key].rep_parent == key) {
    return nodes_[a].rep_depth <= nodes_[d].rep_depth &&
           RepAncestorAtDepth(d, nodes_[a].rep_depth) == a;
  }
  return CommonAncestor(ancestor, descendant) == ancestor;
}

FrameIndex PoseForest::CommonAncestor(FrameIndex a, FrameIndex b) const noexcept {
  const std::uint32_t u = Checked(a);
  const std::uint32_t v = Checked(b);
  const std::uint32_t key = nodes_[u].rep_root;
  if (nodes_[v].rep_root != key) return FrameIndex();  // different trees
  const std::uint32_t x = RepLca(u, v);
  const std::uint32_t s = nodes_[key].rep_parent;
  if (s == key || x == kNone) return FrameIndex(x);
  // Two of the three rep LCAs coincide; the semantic one is the deepest.
  const std::uint32_t y = RepLca(u, s);
  const std::uint32_t z = RepLca(v, s);
  if (y == kNone || z == kNone) return FrameIndex();  // only under a concurrent change
  std::uint32_t best = nodes_[x].rep_depth >= nodes_[y].rep_depth ? x : y;
  if (nodes_[z].rep_depth > nodes_[best].rep_depth) best = z;
  return FrameIndex(best);
}

std::size_t PoseForest::ApproximateBytes() const noexcept {
  return nodes_.bytes();  // current and retired arrays
}

bool PoseForest::CheckInvariants() const {
  const std::size_t n = size();
  // Bounds first, so that the checks below may index freely.
  for (std::size_t v = 0; v < n; ++v) {
    if (nodes_[v].rep_parent >= n || nodes_[v].rep_root >= n ||
        (nodes_[v].parent != kNone && nodes_[v].parent >= n)) {
      return false;
    }
    if (nodes_[v].rep_depth != 0 && nodes_[v].rep_jump >= n) return false;
  }
  std::vector<std::uint32_t> count(n, 0);  // nodes per rep root
  std::size_t semantic_roots = 0, rep_roots = 0, non_roots = 0, listed_children = 0;
  for (std::uint32_t v = 0; v < n; ++v) {
    const std::uint32_t key = nodes_[v].rep_root;
    // Representation: a rep root is its own key, at depth 0, and nothing else is at depth 0.
    if (nodes_[key].rep_root != key || nodes_[key].rep_depth != 0 ||
        (nodes_[v].rep_depth == 0) != (key == v)) {
      return false;
    }
    ++count[key];
    if (key == v) {
      // Its tree slots: the semantic root is a semantic root of this tree.
      const std::uint32_t s = nodes_[v].rep_parent;
      if (nodes_[s].rep_root != v || nodes_[s].parent != kNone) return false;
      ++rep_roots;
    } else {
      const std::uint32_t q = nodes_[v].rep_parent;
      // depth = depth(rep parent) + 1 also rules out cycles: depths would have to increase all
      // the way round one (a wrap-around needs 2^32 nodes, more than an index can name).
      if (q == v || nodes_[v].rep_depth != nodes_[q].rep_depth + 1 || nodes_[q].rep_root != key)
        return false;
      // The parent's jump is checked in its own turn, so by induction every jump follows the
      // rule and is a rep ancestor; the rule itself is the skew-binary one (the O(log n)
      // bounds rely on it).
      if (nodes_[v].rep_jump != JumpForChildOf(q)) return false;
      if (nodes_[nodes_[v].rep_jump].rep_depth != SkewBinaryJumpDepth(nodes_[v].rep_depth))
        return false;
    }
    // Semantic: the one root of its tree, or an edge {v, parent(v)} that is a rep edge.
    const std::uint32_t p = nodes_[v].parent;
    if (p == kNone) {
      if (nodes_[key].rep_parent != v || nodes_[v].next_sibling != kNone ||
          nodes_[v].prev_sibling != kNone) {
        return false;
      }
      ++semantic_roots;
    } else {
      if (p == v || nodes_[p].parent == v) return false;  // a 2-cycle would use one rep edge twice
      const bool up = nodes_[v].rep_depth != 0 && nodes_[v].rep_parent == p;
      const bool down = nodes_[p].rep_depth != 0 && nodes_[p].rep_parent == v;
      if (!up && !down) return false;
      ++non_roots;
    }
    // v's child list: each entry names v as parent, back links match, and no loop (a node in
    // two places of one list would make it loop, caught by the length bound).
    std::uint32_t prev = kNone;
    std::size_t length = 0;
    for (std::uint32_t c = nodes_[v].first_child; c != kNone; c = nodes_[c].next_sibling) {
      if (c >= n || nodes_[c].parent != v || nodes_[c].prev_sibling != prev || ++length > n)
        return false;
      prev = c;
    }
    listed_children += length;
  }
  for (std::uint32_t v = 0; v < n; ++v) {
    if (nodes_[v].rep_root == v && nodes_[v].rep_jump != count[v]) return false;  // tree sizes
  }
  // Each semantic edge is a rep edge, and no two are the same one (no 2-cycles; the edge of v
  // is {v, parent(v)}); one semantic root per rep tree makes the counts equal, so the edge sets
  // are equal. A node is listed only under parent(node), at most once there; equal counts
  // mean every non-root is listed.
  return semantic_roots == rep_roots && non_roots == n - rep_roots && listed_children == non_roots;
}

}  // namespace semgraph::topology
