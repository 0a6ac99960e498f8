// SceneTopology: nodes, pose trees and their records, twist edges. Contract: scene_topology.h.
#include "semgraph/topology/scene_topology.h"

#include <algorithm>
#include <utility>

#include "semgraph/base/demand.h"

namespace semgraph::topology {

namespace {
// Makes room for n elements in v, growing at least twofold (O(1) amortized per element). On
// std::bad_alloc v is unchanged.
template <class Array>
void GrowCapacity(Array& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(std::max(n, 2 * v.capacity()));
}
}  // namespace

// ====================================================================== nodes

void SceneTopology::GrowNameMaps() {
  frame_of_name_.resize(names_.size(), kNone);
  body_of_name_.resize(names_.size(), kNone);
}

void SceneTopology::Reserve(std::size_t frames, std::size_t bodies) {
  GrowNodes(bodies > bodies_.size() ? bodies - bodies_.size() : 0,
            frames > frames_.size() ? frames - frames_.size() : 0);
  names_.Reserve(frames + bodies);
  GrowCapacity(frame_of_name_, frames + bodies);
  GrowCapacity(body_of_name_, frames + bodies);
  name_map_room_ = std::min(frame_of_name_.capacity(), body_of_name_.capacity());
}

void SceneTopology::GrowNodes(std::size_t bodies, std::size_t frames) {
  // Each array of a kind to the same target, so that the room is one number per kind. On
  // std::bad_alloc part way, capacities grew but the rooms stay as they were (still true).
  const std::size_t frame_target =
      std::max({frames_.size() + frames, 2 * frames_.size(), std::size_t{8}});
  const std::size_t body_target =
      std::max({bodies_.size() + bodies, 2 * bodies_.size(), std::size_t{8}});
  const std::size_t name_target = std::max(names_.size(), name_map_room_);
  GrowCapacity(frame_of_name_, name_target);
  GrowCapacity(body_of_name_, name_target);
  GrowCapacity(bodies_, body_target);
  GrowCapacity(frames_, frame_target);
  forest_.Reserve(frame_target);
  frame_room_ = frame_target - frames_.size();
  body_room_ = body_target - bodies_.size();
  name_map_room_ = std::min(frame_of_name_.capacity(), body_of_name_.capacity());
}

BodyIndex SceneTopology::CreateBody(NameId name) {
  ReserveNodes(1, 0);  // every allocation before the first change
  GrowNameMaps();
  SEMGRAPH_DEMAND(!BodyOfName(name).is_valid());
  const BodyIndex b(static_cast<std::uint32_t>(bodies_.size()));
  bodies_.push_back(BodyNode{name, kNone});
  --body_room_;
  body_of_name_[name.value()] = b.value();
  return b;
}

FrameIndex SceneTopology::CreateFrame(NameId name, BodyIndex body) {
  ReserveNodes(0, 1);  // every allocation before the first change
  GrowNameMaps();
  SEMGRAPH_DEMAND(!FrameOfName(name).is_valid() && body.value() < bodies_.size());
  const FrameIndex f = forest_.AddNode();
  SEMGRAPH_DEMAND(f.value() == frames_.size());
  frames_.push_back(FrameNode{name, body, TwistEdgeIndex(), bodies_[body.value()].first_frame});
  --frame_room_;
  bodies_[body.value()].first_frame = f.value();
  frame_of_name_[name.value()] = f.value();
  return f;
}

// ====================================================================== tree records

const TreeRecord* SceneTopology::RecordOf(FrameIndex f) const noexcept {
  const auto* index = record_of_rep_.Find(forest_.TreeKey(f).value());
  if (index == nullptr) return nullptr;
  // Checked against the size: a reader of another thread may see a stale index.
  const std::uint32_t i = *index;
  return i < records_.size() ? &records_[i] : nullptr;
}

TreeRecord* SceneTopology::MutableRecordOf(FrameIndex f) noexcept {
  const auto* index = record_of_rep_.Find(forest_.TreeKey(f).value());
  return index ? &records_[*index] : nullptr;
}

TreeRecord& SceneTopology::EnsureRecord(FrameIndex f) {
  const std::uint32_t rep = forest_.TreeKey(f).value();
  if (const auto* index = record_of_rep_.Find(rep)) return records_[*index];
  // Only a single-frame tree has no record: its body set is {body(f)}.
  SEMGRAPH_DEMAND(forest_.is_root(f) && !forest_.first_child(f).is_valid());
  return NewRecord(rep, f);
}

void SceneTopology::ReserveNewRecord(std::size_t bodies) {
  // A spare free record (an invisible change: free records hold nothing), with room for
  // `bodies` bodies and one twist edge, and room for its entry in record_of_rep_.
  if (free_records_.empty()) {
    GrowCapacity(free_records_, 1);
    GrowCapacity(records_, records_.size() + 1);
    records_.emplace_back();  // within capacity: does not allocate (empty maps own no memory)
    free_records_.push_back(static_cast<std::uint32_t>(records_.size() - 1));
  }
  TreeRecord& spare = records_[free_records_.back()];
  spare.body_counts.Reserve(bodies);
  spare.twists.ReserveLink();
  record_of_rep_.Reserve(record_of_rep_.size() + 1);
}

TreeRecord& SceneTopology::NewRecord(std::uint32_t rep, FrameIndex f) {
  ReserveNewRecord(
      1);  // no-op when the caller reserved (every mutation below is then allocation-free)
  const std::uint32_t index = free_records_.back();
  free_records_.pop_back();
  records_[index].body_counts.Clear();
  records_[index].twists.Clear();
  records_[index].body_counts.Insert(body_of(f).value(), 1);
  record_of_rep_.Insert(rep, index);
  return records_[index];
}

void SceneTopology::FreeRecord(std::uint32_t rep) {
  const auto* index = record_of_rep_.Find(rep);
  SEMGRAPH_DEMAND(index != nullptr);
  GrowCapacity(free_records_, free_records_.size() + 1);  // before any change
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

FrameIndex SceneTopology::SomeFrameOfBodyInTree(BodyIndex body,
                                                FrameIndex tree_member) const noexcept {
  for (std::uint32_t f = bodies_[body.value()].first_frame; f != kNone;
       f = frames_[f].next_in_body) {
    if (forest_.SameTree(FrameIndex(f), tree_member)) return FrameIndex(f);
  }
  return FrameIndex();
}

// ====================================================================== pose edges

void SceneTopology::ReserveLinkPose(FrameIndex tail, FrameIndex head) {
  // A frame about to be created (invalid index) is a single-frame tree without a record.
  TreeRecord* rec_t = tail.is_valid() ? MutableRecordOf(tail) : nullptr;
  TreeRecord* rec_h = head.is_valid() ? MutableRecordOf(head) : nullptr;
  const std::size_t b_t = rec_t ? rec_t->body_counts.size() : 1,
                    b_h = rec_h ? rec_h->body_counts.size() : 1;
  // The tail's tree gets a record first when it has none. Without a head record (a single
  // frame) the tail's record receives one body; otherwise the record LinkPose keeps (the larger
  // body set, the tail's on a tie) receives the other's bodies and twist edges. Only the kept
  // record grows: reserving the dropped one too would cost O(larger set) per link.
  const bool keep_tail = !rec_h || b_t >= b_h;
  const std::size_t kept_bodies = b_t + b_h;
  if (rec_t && keep_tail) rec_t->body_counts.Reserve(kept_bodies);
  if (rec_h) {
    if (!keep_tail) rec_h->body_counts.Reserve(kept_bodies);
    GrowCapacity(free_records_, free_records_.size() + 1);  // the dropped record
    // A new record's TG is empty, and merging with an empty TG allocates nothing.
    if (rec_t)
      (keep_tail ? rec_t : rec_h)->twists.ReserveMerge((keep_tail ? rec_h : rec_t)->twists);
  }
  // Last: a new record may grow records_, which would leave rec_t / rec_h dangling.
  if (!rec_t) ReserveNewRecord(keep_tail ? kept_bodies : 1);
}

void SceneTopology::LinkPose(FrameIndex tail, FrameIndex head) {
  ReserveLinkPose(tail, head);  // every allocation first: the changes below cannot fail
  LinkPoseReserved(tail, head);
}

void SceneTopology::LinkPoseReserved(FrameIndex tail, FrameIndex head) {
  const std::uint32_t rep_t = forest_.TreeKey(tail).value();
  const std::uint32_t rep_h = forest_.TreeKey(head).value();
  const auto* idx_t = record_of_rep_.Find(rep_t);
  const auto* idx_h = record_of_rep_.Find(rep_h);
  const bool head_is_single = idx_h == nullptr;
  const std::uint32_t index_h = head_is_single ? kNone : idx_h->load();
  // Records are materialized before linking (EnsureRecord relies on single-frame trees).
  const std::uint32_t index_t = idx_t ? *idx_t : (EnsureRecord(tail), *record_of_rep_.Find(rep_t));
  forest_.Link(tail, head);
  ++num_pose_edges_;
  if (head_is_single) {
    // Fast path: the head is a single frame without twists; count its body into tail's tree.
    TreeRecord& rec = records_[index_t];
    rec.body_counts.FindOrInsert(body_of(head).value(), 0) += 1;
    const std::uint32_t rep = forest_.TreeKey(tail).value();
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
  record_of_rep_.Insert(forest_.TreeKey(tail).value(), keep);
}

void SceneTopology::InstallTree(FrameIndex member, TreeRecord&& record) noexcept {
  // a single frame without twists needs no record
  if (forest_.TreeSize(member) == 1 && record.twists.empty())
    return;  // a single frame without twists needs no record
  // A record slot was reserved by CutPose: popping it and inserting into record_of_rep_ do not
  // allocate. The slot's maps take the contents in their own arrays when those have room, else
  // take over record's arrays (theirs retired, not freed: a reader thread may still read them),
  // so the memory of a slot stays within twice its largest size however often trees are cut.
  const std::uint32_t index = free_records_.back();
  free_records_.pop_back();
  records_[index].body_counts.AssignOrAdopt(std::move(record.body_counts));
  records_[index].twists.AssignOrAdopt(std::move(record.twists));
  record_of_rep_.Insert(forest_.TreeKey(member).value(), index);
}

void SceneTopology::CutPose(FrameIndex head) {
  const FrameIndex tail = forest_.parent(head);
  SEMGRAPH_DEMAND(tail.is_valid());
  const std::uint32_t old_rep = forest_.TreeKey(head).value();
  const auto* old_index = record_of_rep_.Find(old_rep);
  SEMGRAPH_DEMAND(old_index != nullptr);  // a tree with an edge has a record
  const TreeRecord& old = records_[*old_index];

  // 1. Plan the two new records (everything that allocates), changing nothing: the bodies of
  // head's subtree (counted by walking it) and the rest (the old counts minus those), and each
  // part's twist edges (those whose head frame is in head's subtree go below). O(|subtree| +
  // bodies + twist edges (log n)).
  TreeRecord below, above;
  forest_.ForEachInSubtree(
      head, [&](FrameIndex f) { below.body_counts.FindOrInsert(body_of(f).value(), 0) += 1; });
  above.body_counts = old.body_counts;
  below.body_counts.ForEach([&](std::uint32_t body, std::uint32_t count) {
    std::uint32_t& rest = *above.body_counts.Find(body);
    rest -= count;
  });
  below.body_counts.ForEach([&](std::uint32_t body, std::uint32_t) {
    if (*above.body_counts.Find(body) == 0) above.body_counts.Erase(body);
  });
  old.twists.ForEachEdge([&](TwistEdgeIndex edge, BodyIndex from, BodyIndex to) {
    (forest_.IsAncestor(head, twist_edges_[edge.value()].head) ? below : above)
        .twists.Link(edge, from, to);
  });
  // Room for the second record (the old one is freed and reused for the first) and for the
  // record_of_rep_ entries (one erased, at most two inserted).
  GrowCapacity(free_records_, free_records_.size() + 2);
  if (free_records_.empty()) GrowCapacity(records_, records_.size() + 1);
  record_of_rep_.Reserve(record_of_rep_.size() + 1);

  // 2. Apply: nothing below allocates.
  FreeRecord(old_rep);
  if (free_records_.size() < 2) {
    records_.emplace_back();  // within capacity
    free_records_.push_back(static_cast<std::uint32_t>(records_.size() - 1));
  }
  forest_.Cut(head);
  --num_pose_edges_;
  InstallTree(tail, std::move(above));
  InstallTree(head, std::move(below));
}

// ====================================================================== twist edges

void SceneTopology::ReserveLinkTwist(FrameIndex head) {
  if (free_twist_edges_.empty()) GrowCapacity(twist_edges_, twist_edges_.size() + 1);
  // A frame about to be created (invalid index) is a single-frame tree without a record.
  if (TreeRecord* rec = head.is_valid() ? MutableRecordOf(head) : nullptr) {
    rec->twists.ReserveLink();
  } else {
    ReserveNewRecord(1);
  }
}

TwistEdgeIndex SceneTopology::LinkTwist(BodyIndex tail, FrameIndex head,
                                        const semantics::TwistSemantics& s) {
  SEMGRAPH_DEMAND(!frames_[head.value()].twist_edge.load().is_valid() && tail != body_of(head));
  ReserveLinkTwist(head);  // every allocation first: the changes below cannot fail
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
  EnsureRecord(head).twists.Link(TwistEdgeIndex(index), tail, body_of(head));
  ++num_twist_edges_;
  return TwistEdgeIndex(index);
}

void SceneTopology::UnlinkTwist(TwistEdgeIndex e) {
  TwistEdge& te = twist_edges_[e.value()];
  SEMGRAPH_DEMAND(te.alive);
  const FrameIndex h = te.head;
  TreeRecord* rec = MutableRecordOf(h);
  SEMGRAPH_DEMAND(rec != nullptr);
  // The two lists that may grow, before any change (TwistForest::Unlink never allocates).
  GrowCapacity(free_twist_edges_, free_twist_edges_.size() + 1);
  GrowCapacity(free_records_, free_records_.size() + 1);
  rec->twists.Unlink(e);
  frames_[h.value()].twist_edge = TwistEdgeIndex();
  te.alive = false;
  free_twist_edges_.push_back(e.value());
  --num_twist_edges_;
  // A single-frame tree without twists needs no record.
  if (rec->twists.empty() && !forest_.first_child(h).is_valid() && forest_.is_root(h)) {
    FreeRecord(forest_.TreeKey(h).value());
  }
}

void SceneTopology::ReserveLinkJoint(FrameIndex tail, FrameIndex head) {
  ReserveLinkPose(tail, head);
  if (free_twist_edges_.empty()) GrowCapacity(twist_edges_, twist_edges_.size() + 1);
  // The twist edge goes into the merged tree's TG. Which storage holds it after LinkPose: the
  // kept record is the tail side's (its record, or the spare ReserveLinkPose prepared, which has
  // room for one edge) unless the head's record has more bodies (as ReserveLinkPose decides), and
  // TwistForest::Merge keeps the storage of the forest with more edges (the kept one on a tie).
  // That storage needs room for the other side's bodies and edges and one more edge.
  TreeRecord* rec_t = tail.is_valid() ? MutableRecordOf(tail) : nullptr;
  TreeRecord* rec_h = head.is_valid() ? MutableRecordOf(head) : nullptr;
  const std::size_t b_t = rec_t ? rec_t->body_counts.size() : 1,
                    b_h = rec_h ? rec_h->body_counts.size() : 1;
  const std::size_t e_t = rec_t ? rec_t->twists.num_edges() : 0,
                    e_h = rec_h ? rec_h->twists.num_edges() : 0;
  const bool keep_tail = !rec_h || b_t >= b_h;
  const bool storage_tail = e_t != e_h ? e_t > e_h : keep_tail;
  if (storage_tail) {
    if (rec_t) rec_t->twists.ReserveMore(2 + (rec_h ? rec_h->twists.num_bodies() : 0), 1 + e_h);
    // else: the spare record (empty TG with room for one edge), and e_h == 0: nothing merges.
  } else {
    rec_h->twists.ReserveMore(2 + (rec_t ? rec_t->twists.num_bodies() : 0), 1 + e_t);
  }
}

void SceneTopology::ReserveUnlinkAfterCut() {
  // CutPose may leave up to one more free record than before, UnlinkTwist frees a twist slot
  // and possibly one more record.
  GrowCapacity(free_twist_edges_, free_twist_edges_.size() + 1);
  GrowCapacity(free_records_, free_records_.size() + 3);
}

std::size_t SceneTopology::ApproximateBytesExcludingNames() const noexcept {
  std::size_t bytes = sizeof(*this);
  bytes += frames_.bytes() + bodies_.bytes();
  bytes += forest_.ApproximateBytes();
  bytes += record_of_rep_.ApproximateBytes();
  for (std::size_t i = 0; i < records_.size(); ++i)
    bytes += records_[i].body_counts.ApproximateBytes() + records_[i].twists.ApproximateBytes();
  bytes += twist_edges_.bytes();
  bytes += frame_of_name_.bytes() + body_of_name_.bytes();
  return bytes;
}

}  // namespace semgraph::topology
