#include "semgraph/topology/twist_forest.h"

#include <utility>

namespace semgraph::topology {

// ---- Accessors --------------------------------------------------------------------------------

BodyIndex TwistForest::parent(BodyIndex body) const noexcept {
  const Node* node = FindNode(body);
  return node != nullptr ? node->parent.load() : BodyIndex();
}

TwistEdgeIndex TwistForest::parent_edge(BodyIndex body) const noexcept {
  const Node* node = FindNode(body);
  return node != nullptr ? node->parent_edge.load() : TwistEdgeIndex();
}

std::uint32_t TwistForest::depth(BodyIndex body) const noexcept {
  const Node* node = FindNode(body);
  return node != nullptr ? node->depth.load() : 0;
}

const TwistForest::Node& TwistForest::NodeAt(BodyIndex body) const noexcept {
  const Node* node = FindNode(body);
  SEMGRAPH_DEMAND(node != nullptr);  // an internal link points at a missing body
  return *node;
}

TwistForest::Node& TwistForest::NodeAt(BodyIndex body) noexcept {
  return const_cast<Node&>(std::as_const(*this).NodeAt(body));
}

// ---- Queries ----------------------------------------------------------------------------------

BodyIndex TwistForest::FindRoot(BodyIndex body) const noexcept {
  const Node* node = FindNode(body);
  // Bounded (a concurrent writer may show a reader a cycle): a root is at most num_bodies()
  // steps up in a consistent forest.
  for (std::size_t steps = num_bodies(); node != nullptr && steps > 0; --steps) {
    const BodyIndex up = node->parent;
    if (!up.is_valid()) break;
    body = up;
    node = FindNode(body);
  }
  return body;
}

// A walk that a concurrent writer can only make fail, not run away or abort: each step looks
// the parent up (a missing one ends the walk) and at most num_bodies() steps are taken.
bool TwistForest::Meet(BodyIndex u, BodyIndex v, std::size_t* up_u,
                       std::size_t* up_v) const noexcept {
  const Node* a = FindNode(u);
  const Node* b = FindNode(v);
  std::size_t steps_u = 0;
  std::size_t steps_v = 0;
  std::size_t budget = 2 * num_bodies();
  if (a == nullptr || b == nullptr) return false;
  // Equalize depths first, so the lockstep walk below meets exactly at the common ancestor.
  while (a->depth > b->depth) {
    if (!Up(u, a, steps_u, budget)) return false;
  }
  while (b->depth > a->depth) {
    if (!Up(v, b, steps_v, budget)) return false;
  }
  while (u != v) {
    if (!a->parent.load().is_valid()) return false;  // two different roots
    if (!Up(u, a, steps_u, budget) || !Up(v, b, steps_v, budget)) return false;
  }
  *up_u = steps_u;
  *up_v = steps_v;
  return true;
}

bool TwistForest::Up(BodyIndex& body, const Node*& node, std::size_t& steps,
                     std::size_t& budget) const noexcept {
  if (budget == 0) return false;
  --budget;
  body = node->parent;
  node = FindNode(body);
  ++steps;
  return node != nullptr;
}

bool TwistForest::Connected(BodyIndex u, BodyIndex v) const noexcept {
  return PathLength(u, v) != kNoPath;
}

std::size_t TwistForest::PathLength(BodyIndex u, BodyIndex v) const noexcept {
  if (u == v) return 0;
  if (!Contains(u) || !Contains(v)) return kNoPath;
  std::size_t up_u = 0;
  std::size_t up_v = 0;
  return Meet(u, v, &up_u, &up_v) ? up_u + up_v : kNoPath;
}

std::size_t TwistForest::Path(BodyIndex u, BodyIndex v, std::span<PathStep> out) const noexcept {
  if (u == v) return 0;
  if (!Contains(u) || !Contains(v)) return kNoPath;
  std::size_t up_u = 0;
  std::size_t up_v = 0;
  if (!Meet(u, v, &up_u, &up_v)) return kNoPath;
  const std::size_t length = up_u + up_v;
  if (length > out.size()) return kPathTooLong;
  // u's side climbs towards the common ancestor: steps in path order. Meet found every body
  // on the way (a concurrent writer may have removed one since: the step is then a dead one,
  // which the reader's validation rejects).
  for (std::size_t i = 0; i < up_u; ++i) {
    const Node* node = FindNode(u);
    const BodyIndex up = node != nullptr ? node->parent.load() : BodyIndex();
    out[i] = PathStep{node != nullptr ? node->parent_edge.load() : TwistEdgeIndex(), u, up};
    u = up;
  }
  // v's side also climbs, but the path descends it: fill from the end, steps reversed.
  for (std::size_t i = 0; i < up_v; ++i) {
    const Node* node = FindNode(v);
    const BodyIndex up = node != nullptr ? node->parent.load() : BodyIndex();
    out[length - 1 - i] =
        PathStep{node != nullptr ? node->parent_edge.load() : TwistEdgeIndex(), up, v};
    v = up;
  }
  return length;
}

bool TwistForest::CanMerge(const TwistForest& other) const {
  if (&other == this) return empty();  // every edge would be parallel to itself
  // Add the smaller forest's edges, one at a time, to the larger one. The larger forest's
  // connectivity is read through FindRoot (read-only); the edges added so far are tracked in a
  // union-find over component keys: the larger forest's root of a body, or the body itself
  // when the larger forest lacks it (that body is then never also a root there). Keyed by the
  // body index's value, like the forest's own maps.
  const bool this_larger = num_edges() >= other.num_edges();
  const TwistForest& large = this_larger ? *this : other;
  const TwistForest& small = this_larger ? other : *this;
  if (small.empty()) return true;

  struct Set {
    BodyIndex parent;
    std::uint32_t size;
  };
  FlatMap<Set> sets;
  sets.Reserve(2 * small.num_edges());
  const auto set_of = [&sets](BodyIndex key) { return sets.Find(key.value()); };
  // Reserved for every key we can insert (two per edge), so pointers into `sets` stay valid.
  auto find = [&sets, &set_of](BodyIndex key) {
    Set* set = &sets.FindOrInsert(key.value(), Set{key, 1});
    // Path halving keeps the trees shallow.
    while (set->parent != key) {
      Set* up = set_of(set->parent);
      set->parent = up->parent;
      key = up->parent;
      set = set_of(key);
    }
    return key;
  };

  bool forest = true;
  small.ForEachEdge([&](TwistEdgeIndex edge, BodyIndex tail, BodyIndex head) {
    if (!forest) return;
    if (large.ContainsEdge(edge)) {
      forest = false;
      return;
    }
    const BodyIndex a = find(large.FindRoot(tail));
    const BodyIndex b = find(large.FindRoot(head));
    if (a == b) {  // tail and head are already joined: a cycle, or a parallel edge
      forest = false;
      return;
    }
    // Union by size: the smaller set hangs under the larger one's representative.
    const bool a_keeps = set_of(a)->size >= set_of(b)->size;
    Set* keep = set_of(a_keeps ? a : b);
    Set* join = set_of(a_keeps ? b : a);
    join->parent = a_keeps ? a : b;
    keep->size += join->size;
  });
  return forest;
}

// ---- Mutations --------------------------------------------------------------------------------

void TwistForest::AttachChild(BodyIndex parent, BodyIndex child) noexcept {
  Node& p = NodeAt(parent);
  Node& c = NodeAt(child);
  c.prev_sibling = BodyIndex();
  c.next_sibling = p.first_child;
  if (p.first_child.is_valid()) NodeAt(p.first_child).prev_sibling = child;
  p.first_child = child;
}

void TwistForest::DetachChild(BodyIndex parent, BodyIndex child) noexcept {
  Node& c = NodeAt(child);
  if (c.prev_sibling.is_valid()) {
    NodeAt(c.prev_sibling).next_sibling = c.next_sibling;
  } else {
    NodeAt(parent).first_child = c.next_sibling;
  }
  if (c.next_sibling.is_valid()) NodeAt(c.next_sibling).prev_sibling = c.prev_sibling;
  c.prev_sibling = BodyIndex();
  c.next_sibling = BodyIndex();
}

void TwistForest::Reroot(BodyIndex body) noexcept {
  Node& top = NodeAt(body);
  if (!top.parent.load().is_valid()) return;
  const std::uint32_t tree_size = NodeAt(FindRoot(body)).tree_size;
  BodyIndex up = top.parent;
  TwistEdgeIndex edge = top.parent_edge;
  DetachChild(up, body);
  top.parent = BodyIndex();
  top.parent_edge = TwistEdgeIndex();
  top.tree_size = tree_size;
  // Reverse the path body -> root one edge at a time. Each body is unhooked from its old
  // parent before it is hooked under its old child, so its sibling links are never shared.
  BodyIndex below = body;
  while (up.is_valid()) {
    Node& node = NodeAt(up);
    const BodyIndex next_up = node.parent;
    const TwistEdgeIndex next_edge = node.parent_edge;
    if (next_up.is_valid()) DetachChild(next_up, up);
    node.parent = below;
    node.parent_edge = edge;
    AttachChild(below, up);
    below = up;
    up = next_up;
    edge = next_edge;
  }
}

std::size_t TwistForest::Relevel(BodyIndex top, std::uint32_t top_depth) noexcept {
  // Stackless preorder walk over first_child / next_sibling / parent links.
  NodeAt(top).depth = top_depth;
  std::size_t count = 0;
  BodyIndex body = top;
  while (true) {
    ++count;
    const Node& node = NodeAt(body);
    if (node.first_child.is_valid()) {
      NodeAt(node.first_child).depth = node.depth + 1;
      body = node.first_child;
      continue;
    }
    while (body != top && !NodeAt(body).next_sibling.is_valid()) body = NodeAt(body).parent;
    if (body == top) return count;
    const Node& done = NodeAt(body);
    NodeAt(done.next_sibling).depth = done.depth;
    body = done.next_sibling;
  }
}

void TwistForest::Link(TwistEdgeIndex edge, BodyIndex tail, BodyIndex head) {
  SEMGRAPH_DEMAND(edge.is_valid() && tail.is_valid() && head.is_valid());
  SEMGRAPH_DEMAND(tail != head);
  SEMGRAPH_DEMAND(!edges_.Contains(edge.value()));
  // An absent body is its own (virtual) root, never equal to a present body's root.
  const BodyIndex tail_root = FindRoot(tail);
  const BodyIndex head_root = FindRoot(head);
  SEMGRAPH_DEMAND(tail_root != head_root);

  // All insertions first: they may rehash, so no Node reference is held across them. Both
  // maps are grown before either changes, so an allocation failure changes nothing.
  ReserveLink();
  nodes_.FindOrInsert(tail.value(), Node{});
  nodes_.FindOrInsert(head.value(), Node{});
  edges_.Insert(edge.value(), TwistEdgeEnds{tail, head});

  // Hang the smaller tree under the other endpoint: only the smaller tree is rerooted and
  // re-levelled (ties hang the tail's tree).
  const bool tail_hangs = NodeAt(tail_root).tree_size <= NodeAt(head_root).tree_size;
  const BodyIndex lower = tail_hangs ? tail : head;
  const BodyIndex upper = tail_hangs ? head : tail;
  const BodyIndex upper_root = tail_hangs ? head_root : tail_root;
  const std::uint32_t moved = NodeAt(tail_hangs ? tail_root : head_root).tree_size;

  Reroot(lower);
  Node& node = NodeAt(lower);
  node.parent = upper;
  node.parent_edge = edge;
  AttachChild(upper, lower);
  NodeAt(upper_root).tree_size += moved;
  Relevel(lower, NodeAt(upper).depth + 1);
}

void TwistForest::Unlink(TwistEdgeIndex edge) {
  const TwistEdgeEnds* ends = edges_.Find(edge.value());
  SEMGRAPH_DEMAND(ends != nullptr);
  // The endpoint whose parent link is this edge is the one below it.
  const bool tail_below = NodeAt(ends->tail).parent_edge == edge;
  const BodyIndex below = tail_below ? ends->tail : ends->head;
  const BodyIndex above = tail_below ? ends->head : ends->tail;
  SEMGRAPH_DEMAND(NodeAt(below).parent == above && NodeAt(below).parent_edge == edge);

  DetachChild(above, below);
  Node& node = NodeAt(below);
  node.parent = BodyIndex();
  node.parent_edge = TwistEdgeIndex();
  const BodyIndex root = FindRoot(above);
  const auto moved = static_cast<std::uint32_t>(Relevel(below, 0));
  NodeAt(below).tree_size = moved;
  NodeAt(root).tree_size -= moved;
  const bool root_alone = NodeAt(root).tree_size == 1;

  // Erasures last: backward shift moves entries, invalidating Node references.
  edges_.Erase(edge.value());
  if (moved == 1) nodes_.Erase(below.value());
  if (root_alone) nodes_.Erase(root.value());
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
  other.ForEachEdge(
      [this](TwistEdgeIndex edge, BodyIndex tail, BodyIndex head) { Link(edge, tail, head); });
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

  nodes_.ForEach([&](std::uint32_t key, const Node& node) {
    if (!ok) return;
    const BodyIndex body(key);
    expect(body.is_valid());
    // Children list: doubly linked, each child points back, bounded length (no cycle).
    BodyIndex prev;
    std::size_t length = 0;
    for (BodyIndex c = node.first_child; c.is_valid() && ok && length <= n;) {
      const Node* child = FindNode(c);
      expect(child != nullptr);
      if (child == nullptr) break;
      expect(child->parent == body && child->prev_sibling == prev);
      ++length;
      prev = c;
      c = child->next_sibling;
    }
    expect(length <= n);
    listed_children += length;

    if (!node.parent.load().is_valid()) {
      ++roots;
      expect(!node.parent_edge.load().is_valid() && node.depth == 0);
      expect(!node.next_sibling.is_valid() && !node.prev_sibling.is_valid());
      expect(node.first_child.is_valid());  // no isolated body
      bodies_in_trees += node.tree_size;
      // The recorded size is the size of the tree hanging from this root.
      // Links were not all validated yet (ForEach order), so look up defensively.
      std::size_t count = 0;
      BodyIndex b = body;
      const Node* at = &node;
      while (count <= n) {
        ++count;
        if (at->first_child.is_valid()) {
          b = at->first_child;
        } else {
          while (b != body && at != nullptr && !at->next_sibling.is_valid()) {
            b = at->parent;
            at = FindNode(b);
          }
          if (b == body || at == nullptr) break;
          b = at->next_sibling;
        }
        at = FindNode(b);
        if (at == nullptr) break;
      }
      expect(at != nullptr && count == node.tree_size);
      return;
    }
    const Node* up = FindNode(node.parent);
    const TwistEdgeEnds* ends = FindEdge(node.parent_edge);
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
  ForEachEdge([&](TwistEdgeIndex edge, BodyIndex tail_body, BodyIndex head_body) {
    const TwistEdgeEnds ends{tail_body, head_body};
    const Node* tail = FindNode(ends.tail);
    const Node* head = FindNode(ends.head);
    expect(edge.is_valid() && ends.tail != ends.head && tail != nullptr && head != nullptr);
    if (tail == nullptr || head == nullptr) return;
    expect((tail->parent_edge == edge && tail->parent == ends.head) ||
           (head->parent_edge == edge && head->parent == ends.tail));
  });
  return ok;
}

}  // namespace semgraph::topology
