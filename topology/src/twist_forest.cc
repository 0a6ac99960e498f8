#include "semgraph/topology/twist_forest.h"

#include <utility>

namespace semgraph::topology {

// ---- Accessors --------------------------------------------------------------------------------

std::uint32_t TwistForest::parent(std::uint32_t body) const noexcept {
  const Node* node = nodes_.Find(body);
  return node != nullptr ? node->parent : kNone;
}

std::uint32_t TwistForest::parent_edge(std::uint32_t body) const noexcept {
  const Node* node = nodes_.Find(body);
  return node != nullptr ? node->parent_edge : kNone;
}

std::uint32_t TwistForest::depth(std::uint32_t body) const noexcept {
  const Node* node = nodes_.Find(body);
  return node != nullptr ? node->depth : 0;
}

const TwistForest::Node& TwistForest::NodeAt(std::uint32_t body) const noexcept {
  const Node* node = nodes_.Find(body);
  SEMGRAPH_DEMAND(node != nullptr);  // an internal link points at a missing body
  return *node;
}

TwistForest::Node& TwistForest::NodeAt(std::uint32_t body) noexcept {
  return const_cast<Node&>(std::as_const(*this).NodeAt(body));
}

// ---- Queries ----------------------------------------------------------------------------------

std::uint32_t TwistForest::FindRoot(std::uint32_t body) const noexcept {
  const Node* node = nodes_.Find(body);
  if (node == nullptr) return body;
  while (node->parent != kNone) {
    body = node->parent;
    node = &NodeAt(body);
  }
  return body;
}

bool TwistForest::Meet(std::uint32_t u, std::uint32_t v, std::size_t* up_u,
                       std::size_t* up_v) const noexcept {
  const Node* a = &NodeAt(u);
  const Node* b = &NodeAt(v);
  std::size_t steps_u = 0;
  std::size_t steps_v = 0;
  // Equalize depths first, so the lockstep walk below meets exactly at the common ancestor.
  while (a->depth > b->depth) {
    u = a->parent;
    a = &NodeAt(u);
    ++steps_u;
  }
  while (b->depth > a->depth) {
    v = b->parent;
    b = &NodeAt(v);
    ++steps_v;
  }
  while (u != v) {
    if (a->parent == kNone) return false;  // two different roots
    u = a->parent;
    a = &NodeAt(u);
    v = b->parent;
    b = &NodeAt(v);
    ++steps_u;
    ++steps_v;
  }
  *up_u = steps_u;
  *up_v = steps_v;
  return true;
}

bool TwistForest::Connected(std::uint32_t u, std::uint32_t v) const noexcept {
  return PathLength(u, v) != kNoPath;
}

std::size_t TwistForest::PathLength(std::uint32_t u, std::uint32_t v) const noexcept {
  if (u == v) return 0;
  if (!nodes_.Contains(u) || !nodes_.Contains(v)) return kNoPath;
  std::size_t up_u = 0;
  std::size_t up_v = 0;
  return Meet(u, v, &up_u, &up_v) ? up_u + up_v : kNoPath;
}

std::size_t TwistForest::Path(std::uint32_t u, std::uint32_t v,
                              std::span<PathStep> out) const noexcept {
  if (u == v) return 0;
  if (!nodes_.Contains(u) || !nodes_.Contains(v)) return kNoPath;
  std::size_t up_u = 0;
  std::size_t up_v = 0;
  if (!Meet(u, v, &up_u, &up_v)) return kNoPath;
  const std::size_t length = up_u + up_v;
  if (length > out.size()) return kPathTooLong;
  // u's side climbs towards the common ancestor: steps in path order.
  for (std::size_t i = 0; i < up_u; ++i) {
    const Node& node = NodeAt(u);
    out[i] = PathStep{node.parent_edge, u, node.parent};
    u = node.parent;
  }
  // v's side also climbs, but the path descends it: fill from the end, steps reversed.
  for (std::size_t i = 0; i < up_v; ++i) {
    const Node& node = NodeAt(v);
    out[length - 1 - i] = PathStep{node.parent_edge, node.parent, v};
    v = node.parent;
  }
  return length;
}

bool TwistForest::CanMerge(const TwistForest& other) const {
  if (&other == this) return empty();  // every edge would be parallel to itself
  // Add the smaller forest's edges, one at a time, to the larger one. The larger forest's
  // connectivity is read through FindRoot (read-only); the edges added so far are tracked in a
  // union-find over component keys: the larger forest's root of a body, or the body itself
  // when the larger forest lacks it (a body id is then never also a root id there).
  const bool this_larger = num_edges() >= other.num_edges();
  const TwistForest& large = this_larger ? *this : other;
  const TwistForest& small = this_larger ? other : *this;
  if (small.empty()) return true;

  struct Set {
    std::uint32_t parent;
    std::uint32_t size;
  };
  FlatMap<Set> sets;
  sets.Reserve(2 * small.num_edges());
  // Reserved for every key we can insert (two per edge), so pointers into `sets` stay valid.
  auto find = [&sets](std::uint32_t key) {
    Set* set = &sets.FindOrInsert(key, Set{key, 1});
    // Path halving keeps the trees shallow.
    while (set->parent != key) {
      Set* up = sets.Find(set->parent);
      set->parent = up->parent;
      key = up->parent;
      set = sets.Find(key);
    }
    return key;
  };

  bool forest = true;
  small.ForEachEdge([&](std::uint32_t edge, std::uint32_t tail, std::uint32_t head) {
    if (!forest) return;
    if (large.ContainsEdge(edge)) {
      forest = false;
      return;
    }
    const std::uint32_t a = find(large.FindRoot(tail));
    const std::uint32_t b = find(large.FindRoot(head));
    if (a == b) {  // tail and head are already joined: a cycle, or a parallel edge
      forest = false;
      return;
    }
    // Union by size: the smaller set hangs under the larger one's representative.
    const bool a_keeps = sets.Find(a)->size >= sets.Find(b)->size;
    Set* keep = sets.Find(a_keeps ? a : b);
    Set* join = sets.Find(a_keeps ? b : a);
    join->parent = a_keeps ? a : b;
    keep->size += join->size;
  });
  return forest;
}

// ---- Mutations --------------------------------------------------------------------------------

void TwistForest::AttachChild(std::uint32_t parent, std::uint32_t child) noexcept {
  Node& p = NodeAt(parent);
  Node& c = NodeAt(child);
  c.prev_sibling = kNone;
  c.next_sibling = p.first_child;
  if (p.first_child != kNone) NodeAt(p.first_child).prev_sibling = child;
  p.first_child = child;
}

void TwistForest::DetachChild(std::uint32_t parent, std::uint32_t child) noexcept {
  Node& c = NodeAt(child);
  if (c.prev_sibling != kNone) {
    NodeAt(c.prev_sibling).next_sibling = c.next_sibling;
  } else {
    NodeAt(parent).first_child = c.next_sibling;
  }
  if (c.next_sibling != kNone) NodeAt(c.next_sibling).prev_sibling = c.prev_sibling;
  c.prev_sibling = kNone;
  c.next_sibling = kNone;
}

void TwistForest::Reroot(std::uint32_t body) noexcept {
  Node& top = NodeAt(body);
  if (top.parent == kNone) return;
  const std::uint32_t tree_size = NodeAt(FindRoot(body)).tree_size;
  std::uint32_t up = top.parent;
  std::uint32_t edge = top.parent_edge;
  DetachChild(up, body);
  top.parent = kNone;
  top.parent_edge = kNone;
  top.tree_size = tree_size;
  // Reverse the path body -> root one edge at a time. Each body is unhooked from its old
  // parent before it is hooked under its old child, so its sibling links are never shared.
  std::uint32_t below = body;
  while (up != kNone) {
    Node& node = NodeAt(up);
    const std::uint32_t next_up = node.parent;
    const std::uint32_t next_edge = node.parent_edge;
    if (next_up != kNone) DetachChild(next_up, up);
    node.parent = below;
    node.parent_edge = edge;
    AttachChild(below, up);
    below = up;
    up = next_up;
    edge = next_edge;
  }
}

std::size_t TwistForest::Relevel(std::uint32_t top, std::uint32_t top_depth) noexcept {
  // Stackless preorder walk over first_child / next_sibling / parent links.
  NodeAt(top).depth = top_depth;
  std::size_t count = 0;
  std::uint32_t body = top;
  while (true) {
    ++count;
    const Node& node = NodeAt(body);
    if (node.first_child != kNone) {
      NodeAt(node.first_child).depth = node.depth + 1;
      body = node.first_child;
      continue;
    }
    while (body != top && NodeAt(body).next_sibling == kNone) body = NodeAt(body).parent;
    if (body == top) return count;
    const Node& done = NodeAt(body);
    NodeAt(done.next_sibling).depth = done.depth;
    body = done.next_sibling;
  }
}

void TwistForest::Link(std::uint32_t edge, std::uint32_t tail, std::uint32_t head) {
  SEMGRAPH_DEMAND(edge != kNone && tail != kNone && head != kNone);
  SEMGRAPH_DEMAND(tail != head);
  SEMGRAPH_DEMAND(!edges_.Contains(edge));
  // An absent body is its own (virtual) root, never equal to a present body's root.
  const std::uint32_t tail_root = FindRoot(tail);
  const std::uint32_t head_root = FindRoot(head);
  SEMGRAPH_DEMAND(tail_root != head_root);

  // All insertions first: they may rehash, so no Node reference is held across them. Both
  // maps are grown before either changes, so an allocation failure changes nothing.
  ReserveLink();
  nodes_.FindOrInsert(tail, Node{});
  nodes_.FindOrInsert(head, Node{});
  edges_.Insert(edge, TwistEdgeEnds{tail, head});

  // Hang the smaller tree under the other endpoint: only the smaller tree is rerooted and
  // re-levelled (ties hang the tail's tree).
  const bool tail_hangs = NodeAt(tail_root).tree_size <= NodeAt(head_root).tree_size;
  const std::uint32_t lower = tail_hangs ? tail : head;
  const std::uint32_t upper = tail_hangs ? head : tail;
  const std::uint32_t upper_root = tail_hangs ? head_root : tail_root;
  const std::uint32_t moved = NodeAt(tail_hangs ? tail_root : head_root).tree_size;

  Reroot(lower);
  Node& node = NodeAt(lower);
  node.parent = upper;
  node.parent_edge = edge;
  AttachChild(upper, lower);
  NodeAt(upper_root).tree_size += moved;
  Relevel(lower, NodeAt(upper).depth + 1);
}

void TwistForest::Unlink(std::uint32_t edge) {
  const TwistEdgeEnds* ends = edges_.Find(edge);
  SEMGRAPH_DEMAND(ends != nullptr);
  // The endpoint whose parent link is this edge is the one below it.
  const bool tail_below = NodeAt(ends->tail).parent_edge == edge;
  const std::uint32_t below = tail_below ? ends->tail : ends->head;
  const std::uint32_t above = tail_below ? ends->head : ends->tail;
  SEMGRAPH_DEMAND(NodeAt(below).parent == above && NodeAt(below).parent_edge == edge);

  DetachChild(above, below);
  Node& node = NodeAt(below);
  node.parent = kNone;
  node.parent_edge = kNone;
  const std::uint32_t root = FindRoot(above);
  const auto moved = static_cast<std::uint32_t>(Relevel(below, 0));
  NodeAt(below).tree_size = moved;
  NodeAt(root).tree_size -= moved;
  const bool root_alone = NodeAt(root).tree_size == 1;

  // Erasures last: backward shift moves entries, invalidating Node references.
  edges_.Erase(edge);
  if (moved == 1) nodes_.Erase(below);
  if (root_alone) nodes_.Erase(root);
}

void TwistForest::ReserveLink() {
  nodes_.Reserve(nodes_.size() + 2);
  edges_.Reserve(edges_.size() + 1);
}

void TwistForest::ReserveMore(std::size_t bodies, std::size_t edges) {
  nodes_.Reserve(nodes_.size() + bodies);
  edges_.Reserve(edges_.size() + edges);
}

void TwistForest::ReserveMerge(TwistForest& other) {
  // With one side empty, Merge links nothing (at most it swaps): nothing to reserve.
  if (&other == this || empty() || other.empty()) return;
  // Merge keeps the storage of the forest with more edges and links the other's edges into it.
  TwistForest& survivor = other.num_edges() > num_edges() ? other : *this;
  survivor.nodes_.Reserve(nodes_.size() + other.nodes_.size() + 2);
  survivor.edges_.Reserve(edges_.size() + other.edges_.size());
}

void TwistForest::Merge(TwistForest&& other) {
  SEMGRAPH_DEMAND(&other != this || empty());
  if (&other == this) return;
  // Room for every edge first (strong guarantee: the Links below then never allocate).
  ReserveMerge(other);
  // Link the smaller set of edges into the larger structure; which object ends up owning the
  // storage does not matter, the result is the same forest.
  if (other.num_edges() > num_edges()) std::swap(*this, other);
  other.ForEachEdge([this](std::uint32_t edge, std::uint32_t tail, std::uint32_t head) {
    Link(edge, tail, head);
  });
  other.Clear();
}

// ---- Checks -----------------------------------------------------------------------------------

bool TwistForest::CheckInvariants() const {
  bool ok = true;
  auto expect = [&ok](bool condition) { ok = ok && condition; };
  std::size_t roots = 0;
  std::size_t listed_children = 0;
  std::size_t bodies_in_trees = 0;
  const std::size_t n = nodes_.size();

  nodes_.ForEach([&](std::uint32_t body, const Node& node) {
    if (!ok) return;
    expect(body != kNone);
    // Children list: doubly linked, each child points back, bounded length (no cycle).
    std::uint32_t prev = kNone;
    std::size_t length = 0;
    for (std::uint32_t c = node.first_child; c != kNone && ok && length <= n;) {
      const Node* child = nodes_.Find(c);
      expect(child != nullptr);
      if (child == nullptr) break;
      expect(child->parent == body && child->prev_sibling == prev);
      ++length;
      prev = c;
      c = child->next_sibling;
    }
    expect(length <= n);
    listed_children += length;

    if (node.parent == kNone) {
      ++roots;
      expect(node.parent_edge == kNone && node.depth == 0);
      expect(node.next_sibling == kNone && node.prev_sibling == kNone);
      expect(node.first_child != kNone);  // no isolated body
      bodies_in_trees += node.tree_size;
      // The recorded size is the size of the tree hanging from this root.
      // Links were not all validated yet (ForEach order), so look up defensively.
      std::size_t count = 0;
      std::uint32_t b = body;
      const Node* at = &node;
      while (count <= n) {
        ++count;
        if (at->first_child != kNone) {
          b = at->first_child;
        } else {
          while (b != body && at != nullptr && at->next_sibling == kNone) {
            b = at->parent;
            at = nodes_.Find(b);
          }
          if (b == body || at == nullptr) break;
          b = at->next_sibling;
        }
        at = nodes_.Find(b);
        if (at == nullptr) break;
      }
      expect(at != nullptr && count == node.tree_size);
      return;
    }
    const Node* up = nodes_.Find(node.parent);
    const TwistEdgeEnds* ends = edges_.Find(node.parent_edge);
    expect(up != nullptr && ends != nullptr);
    if (!ok) return;
    expect(node.depth == up->depth + 1);
    expect((ends->tail == body && ends->head == node.parent) ||
           (ends->head == body && ends->tail == node.parent));
  });
  if (!ok) return false;
  // Every non-root is listed exactly once under its parent, and every edge is the parent edge
  // of exactly one body (edges map onto non-roots, injectively by the tail/head check above).
  expect(listed_children == n - roots);
  expect(edges_.size() == n - roots);
  expect(bodies_in_trees == n);
  edges_.ForEach([&](std::uint32_t edge, const TwistEdgeEnds& ends) {
    const Node* tail = nodes_.Find(ends.tail);
    const Node* head = nodes_.Find(ends.head);
    expect(edge != kNone && ends.tail != ends.head && tail != nullptr && head != nullptr);
    if (tail == nullptr || head == nullptr) return;
    expect((tail->parent_edge == edge && tail->parent == ends.head) ||
           (head->parent_edge == edge && head->parent == ends.tail));
  });
  return ok;
}

}  // namespace semgraph::topology
