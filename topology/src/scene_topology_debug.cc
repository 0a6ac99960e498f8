// SceneTopology::CheckInvariants: every invariant of scene_topology.h verified from scratch,
// for tests and fuzzers (Drake keeps the same split: spanning_forest_debug.cc). Slow by design:
// it recounts every tree instead of trusting the records.
#include <sstream>
#include <string>

#include "semgraph/topology/scene_topology.h"

namespace semgraph::topology {

std::string SceneTopology::CheckInvariants() const {
  std::ostringstream out;
  const auto text = [&](FrameIndex f) {
    return "{" + std::string(frame_name(f)) + "}|" + std::string(body_name(body_of(f)));
  };
  if (!forest_.CheckInvariants()) out << "pose forest invariants broken\n";
  // Tree keys = pose trees; records = body multisets and TG of each tree.
  for (std::uint32_t i = 0; i < frames_.size(); ++i) {
    const FrameIndex f(i);
    if (forest_.TreeKey(f) != forest_.TreeKey(forest_.Root(f))) {
      out << "frame " << text(f) << " has another tree key than its root\n";
    }
    if (FrameOfName(frames_[i].name) != f) out << "name map of frame " << text(f) << " broken\n";
  }
  // Per tree: recount bodies, check P3 (a body's frames in one tree are same-body connected:
  // count of frames of body X == 1 + number of same-body edges among them), and TG is a forest.
  for (std::uint32_t i = 0; i < frames_.size(); ++i) {
    const FrameIndex root(i);
    if (!forest_.is_root(root)) continue;
    FlatMap<std::uint32_t> counts, same_edges;
    std::size_t size = 0;
    forest_.ForEachInSubtree(root, [&](FrameIndex f) {
      ++size;
      counts.FindOrInsert(body_of(f).value(), 0) += 1;
      const FrameIndex p = forest_.parent(f);
      if (p.is_valid() && body_of(p) == body_of(f))
        same_edges.FindOrInsert(body_of(f).value(), 0) += 1;
    });
    counts.ForEach([&](std::uint32_t body, std::uint32_t c) {
      const std::uint32_t* s = same_edges.Find(body);
      if (c != 1 + (s ? *s : 0)) {
        out << "P3: body " << body_name(BodyIndex(body)) << " is reachable twice in the tree of "
            << text(root) << "\n";
      }
    });
    const TreeRecord* rec = RecordOf(root);
    if (rec) {
      if (rec->body_counts.size() != counts.size())
        out << "body set size mismatch at " << text(root) << "\n";
      counts.ForEach([&](std::uint32_t body, std::uint32_t c) {
        const std::uint32_t* stored = rec->body_counts.Find(body);
        if (!stored || *stored != c) out << "body count mismatch at " << text(root) << "\n";
      });
      if (!rec->twists.CheckInvariants()) out << "twist forest broken at " << text(root) << "\n";
    } else if (size != 1) {
      out << "tree of " << text(root) << " has no record\n";
    }
  }
  std::size_t live = 0;
  for (std::uint32_t i = 0; i < twist_edges_.size(); ++i) {
    const TwistEdge& te = twist_edges_[i];
    if (!te.alive) continue;
    ++live;
    const TreeRecord* rec = RecordOf(te.head);
    if (!rec || !rec->twists.FindEdge(TwistEdgeIndex(i)))
      out << "twist edge " << i << " missing from its tree's TG\n";
    if (te.tail == body_of(te.head)) out << "W2 broken\n";
    if (frames_[te.head.load().value()].twist_edge != TwistEdgeIndex(i))
      out << "W1 bookkeeping broken\n";
  }
  if (live != num_twist_edges_) out << "twist edge count mismatch\n";
  std::size_t edges = 0;
  ForEachPoseEdge([&](FrameIndex, FrameIndex) { ++edges; });
  if (edges != num_pose_edges_) out << "pose edge count mismatch\n";
  return out.str();
}

}  // namespace semgraph::topology
