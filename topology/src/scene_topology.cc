// SceneTopology: nodes, pose trees and their records, twist edges. Contract: scene_topology.h.
#include "semgraph/topology/scene_topology.h"

#include <utility>

#include "semgraph/base/demand.h"

namespace semgraph::topology {

// ====================================================================== nodes

void SceneTopology::GrowNameMaps() {
  frame_of_name_.resize(names_.size(), kNone);
  body_of_name_.resize(names_.size(), kNone);
}

void SceneTopology::Reserve(std::size_t frames, std::size_t bodies) {
  frames_.reserve(frames);
  bodies_.reserve(bodies);
  forest_.Reserve(frames);
  trees_.Reserve(frames);
  names_.Reserve(frames + bodies);
  frame_of_name_.reserve(frames + bodies);
  body_of_name_.reserve(frames + bodies);
}

BodyIndex SceneTopology::CreateBody(NameId name) {
  GrowNameMaps();
  SEMGRAPH_DEMAND(!BodyOfName(name).is_valid());
  const BodyIndex b(static_cast<std::uint32_t>(bodies_.size()));
  bodies_.push_back(BodyNode{name, kNone});
  body_of_name_[name.value()] = b.value();
  return b;
}

FrameIndex SceneTopology::CreateFrame(NameId name, BodyIndex body) {
  GrowNameMaps();
  SEMGRAPH_DEMAND(!FrameOfName(name).is_valid() && body.value() < bodies_.size());
  const FrameIndex f = forest_.AddNode();
  const std::uint32_t uf = trees_.AddElement();
  SEMGRAPH_DEMAND(f.value() == frames_.size() && uf == f.value());
  frames_.push_back(FrameNode{name, body, TwistEdgeIndex(), bodies_[body.value()].first_frame});
  bodies_[body.value()].first_frame = f.value();
  frame_of_name_[name.value()] = f.value();
  return f;
}

// ====================================================================== tree records

const TreeRecord* SceneTopology::RecordOf(FrameIndex f) const noexcept {
  const std::uint32_t* index = record_of_rep_.Find(trees_.FindConst(f.value()));
  return index ? &records_[*index] : nullptr;
}

TreeRecord* SceneTopology::MutableRecordOf(FrameIndex f) noexcept {
  const std::uint32_t* index = record_of_rep_.Find(trees_.Find(f.value()));
  return index ? &records_[*index] : nullptr;
}

TreeRecord& SceneTopology::EnsureRecord(FrameIndex f) {
  const std::uint32_t rep = trees_.Find(f.value());
  if (const std::uint32_t* index = record_of_rep_.Find(rep)) return records_[*index];
  // Only a single-frame tree has no record: its body set is {body(f)}.
  SEMGRAPH_DEMAND(forest_.is_root(f) && !forest_.first_child(f).is_valid());
  return NewRecord(rep, f);
}

TreeRecord& SceneTopology::NewRecord(std::uint32_t rep, FrameIndex f) {
  std::uint32_t index;
  if (!free_records_.empty()) {
    index = free_records_.back();
    free_records_.pop_back();
  } else {
    index = static_cast<std::uint32_t>(records_.size());
    records_.emplace_back();
  }
  records_[index].body_counts.Clear();
  records_[index].twists.Clear();
  records_[index].body_counts.Insert(body_of(f).value(), 1);
  record_of_rep_.Insert(rep, index);
  return records_[index];
}

void SceneTopology::FreeRecord(std::uint32_t rep) {
  const std::uint32_t* index = record_of_rep_.Find(rep);
  SEMGRAPH_DEMAND(index != nullptr);
  records_[*index].body_counts.Clear();
  records_[*index].twists.Clear();
  free_records_.push_back(*index);
  record_of_rep_.Erase(rep);
}

bool SceneTopology::TreeHasBody(FrameIndex f, BodyIndex body) const noexcept {
  if (const TreeRecord* rec = RecordOf(f)) return rec->body_counts.Contains(body.value());
  return body_of(f) == body;
}

BodyIndex SceneTopology::SharedBody(FrameIndex t, FrameIndex h, BodyIndex allowed) const noexcept {
  const TreeRecord* rec_t = RecordOf(t);
  const TreeRecord* rec_h = RecordOf(h);
  // Iterate the smaller body set, look each body up in the other: O(min(b_t, b_h)).
  const std::size_t size_t_ = rec_t ? rec_t->body_counts.size() : 1;
  const std::size_t size_h = rec_h ? rec_h->body_counts.size() : 1;
  const FrameIndex small = size_t_ <= size_h ? t : h;
  const FrameIndex large = size_t_ <= size_h ? h : t;
  const TreeRecord* rec_small = size_t_ <= size_h ? rec_t : rec_h;
  BodyIndex found;
  if (!rec_small) {
    const BodyIndex b = body_of(small);
    if (b != allowed && TreeHasBody(large, b)) found = b;
    return found;
  }
  rec_small->body_counts.ForEach([&](std::uint32_t body, const std::uint32_t&) {
    if (found.is_valid()) return;
    const BodyIndex b(body);
    if (b != allowed && TreeHasBody(large, b)) found = b;
  });
  return found;
}

FrameIndex SceneTopology::SomeFrameOfBodyInTree(BodyIndex body, FrameIndex tree_member) const noexcept {
  for (std::uint32_t f = bodies_[body.value()].first_frame; f != kNone; f = frames_[f].next_in_body) {
    if (trees_.SameSet(f, tree_member.value())) return FrameIndex(f);
  }
  return FrameIndex();
}

// ====================================================================== pose edges

void SceneTopology::LinkPose(FrameIndex tail, FrameIndex head) {
  const std::uint32_t rep_t = trees_.Find(tail.value());
  const std::uint32_t rep_h = trees_.Find(head.value());
  const std::uint32_t* idx_t = record_of_rep_.Find(rep_t);
  const std::uint32_t* idx_h = record_of_rep_.Find(rep_h);
  const bool head_is_single = idx_h == nullptr;
  const std::uint32_t index_h = head_is_single ? kNone : *idx_h;
  // Records are materialized before linking (EnsureRecord relies on single-frame trees).
  const std::uint32_t index_t = idx_t ? *idx_t : (EnsureRecord(tail), *record_of_rep_.Find(rep_t));
  forest_.Link(tail, head);
  ++num_pose_edges_;
  if (head_is_single) {
    // Fast path: the head is a single frame without twists; count its body into tail's tree.
    TreeRecord& rec = records_[index_t];
    rec.body_counts.FindOrInsert(body_of(head).value(), 0) += 1;
    const std::uint32_t rep = trees_.Union(tail.value(), head.value());
    if (rep != rep_t) {
      record_of_rep_.Erase(rep_t);
      record_of_rep_.Insert(rep, index_t);
    }
    return;
  }
  record_of_rep_.Erase(rep_t);
  record_of_rep_.Erase(rep_h);
  // Merge the smaller record into the larger.
  std::uint32_t keep = index_t, drop = index_h;
  if (records_[keep].body_counts.size() < records_[drop].body_counts.size()) std::swap(keep, drop);
  records_[drop].body_counts.ForEach([&](std::uint32_t body, std::uint32_t count) {
    records_[keep].body_counts.FindOrInsert(body, 0) += count;
  });
  records_[keep].twists.Merge(std::move(records_[drop].twists));
  records_[drop].body_counts.Clear();
  records_[drop].twists.Clear();
  free_records_.push_back(drop);
  const std::uint32_t rep = trees_.Union(tail.value(), head.value());
  record_of_rep_.Insert(rep, keep);
}

// Rebuilds the union-find set and the record of the tree rooted at `root` after a split.
// `twist_edges` holds the twist edges of the old tree; those whose head is in this tree are
// linked into its new TG. O(|tree| + twist edges).
void SceneTopology::RebuildTree(FrameIndex root, const std::vector<std::uint32_t>& twist_edges) {
  std::size_t count = 0;
  forest_.ForEachInSubtree(root, [&](FrameIndex f) {
    trees_.Union(root.value(), f.value());
    ++count;
  });
  bool has_twist = false;
  for (std::uint32_t e : twist_edges) {
    if (trees_.SameSet(twist_edges_[e].head.value(), root.value())) has_twist = true;
  }
  if (count == 1 && !has_twist) return;  // a single frame needs no record
  TreeRecord& rec = NewRecord(trees_.Find(root.value()), root);
  rec.body_counts.Clear();
  forest_.ForEachInSubtree(root, [&](FrameIndex f) {
    rec.body_counts.FindOrInsert(body_of(f).value(), 0) += 1;
  });
  for (std::uint32_t e : twist_edges) {
    const TwistEdge& te = twist_edges_[e];
    if (trees_.SameSet(te.head.value(), root.value())) {
      rec.twists.Link(e, te.tail.value(), body_of(te.head).value());
    }
  }
}

void SceneTopology::CutPose(FrameIndex head) {
  const FrameIndex tail = forest_.parent(head);
  SEMGRAPH_DEMAND(tail.is_valid());
  // Collect the old tree's twist edges, split the forest, then rebuild both trees' sets.
  std::vector<std::uint32_t> twist_edges;
  const std::uint32_t old_rep = trees_.Find(head.value());
  if (const std::uint32_t* index = record_of_rep_.Find(old_rep)) {
    records_[*index].twists.ForEachEdge(
        [&](std::uint32_t edge, std::uint32_t, std::uint32_t) { twist_edges.push_back(edge); });
    FreeRecord(old_rep);
  }
  const FrameIndex old_root = forest_.Root(tail);
  forest_.ForEachInSubtree(old_root, [&](FrameIndex f) { trees_.Reset(f.value()); });
  forest_.Cut(head);
  --num_pose_edges_;
  RebuildTree(old_root, twist_edges);
  RebuildTree(head, twist_edges);
}

// ====================================================================== twist edges

TwistEdgeIndex SceneTopology::LinkTwist(BodyIndex tail, FrameIndex head,
                                        const semantics::TwistSemantics& s) {
  SEMGRAPH_DEMAND(!frames_[head.value()].twist_edge.is_valid() && tail != body_of(head));
  std::uint32_t index;
  if (!free_twist_edges_.empty()) {
    index = free_twist_edges_.back();
    free_twist_edges_.pop_back();
  } else {
    index = static_cast<std::uint32_t>(twist_edges_.size());
    twist_edges_.emplace_back();
  }
  TwistEdge& te = twist_edges_[index];
  te.tail = tail;
  te.head = head;
  te.alive = true;
  te.semantics = s;
  frames_[head.value()].twist_edge = TwistEdgeIndex(index);
  EnsureRecord(head).twists.Link(index, tail.value(), body_of(head).value());
  ++num_twist_edges_;
  return TwistEdgeIndex(index);
}

void SceneTopology::UnlinkTwist(TwistEdgeIndex e) {
  TwistEdge& te = twist_edges_[e.value()];
  SEMGRAPH_DEMAND(te.alive);
  const FrameIndex h = te.head;
  TreeRecord* rec = MutableRecordOf(h);
  SEMGRAPH_DEMAND(rec != nullptr);
  rec->twists.Unlink(e.value());
  frames_[h.value()].twist_edge = TwistEdgeIndex();
  te.alive = false;
  free_twist_edges_.push_back(e.value());
  --num_twist_edges_;
  // A single-frame tree without twists needs no record.
  if (rec->twists.empty() && !forest_.first_child(h).is_valid() && forest_.is_root(h)) {
    FreeRecord(trees_.Find(h.value()));
  }
}

std::size_t SceneTopology::ApproximateBytesExcludingNames() const noexcept {
  std::size_t bytes = sizeof(*this);
  bytes += frames_.capacity() * sizeof(FrameNode) + bodies_.capacity() * sizeof(BodyNode);
  bytes += forest_.ApproximateBytes();
  bytes += trees_.size() * 2 * sizeof(std::uint32_t);
  bytes += record_of_rep_.ApproximateBytes();
  for (const TreeRecord& r : records_) bytes += r.body_counts.ApproximateBytes() + r.twists.ApproximateBytes();
  bytes += twist_edges_.capacity() * sizeof(TwistEdge);
  bytes += (frame_of_name_.capacity() + body_of_name_.capacity()) * sizeof(std::uint32_t);
  return bytes;
}

}  // namespace semgraph::topology
