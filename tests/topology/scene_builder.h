// A SceneTopology built by name for the topology tests (no numbers): bodies and frames are
// created on first mention, and every link is checked against the rules first, as core does,
// so a test scene is a valid scene graph by construction.
#pragma once

#include <gtest/gtest.h>

#include <string_view>

#include "semgraph/topology/rules.h"
#include "semgraph/topology/scene_topology.h"

namespace semgraph::topology::testing {

class SceneBuilder {
 public:
  SceneTopology t;

  BodyIndex Body(std::string_view name) {
    const NameId id = *t.mutable_names().Intern(name);
    if (t.BodyOfName(id).is_valid()) return t.BodyOfName(id);
    t.ReserveNodes(1, 0);
    return t.CreateBody(id);
  }
  /// The frame `name` of `body` (created, as a single-frame tree, if new).
  FrameIndex Frame(std::string_view name, std::string_view body) {
    const BodyIndex b = Body(body);
    const NameId id = *t.mutable_names().Intern(name);
    if (t.FrameOfName(id).is_valid()) return t.FrameOfName(id);
    t.ReserveNodes(0, 1);
    return t.CreateFrame(id, b);
  }
  /// The new pose edge tail -> head between existing frames, as the rules see it.
  NewPoseEdge Edge(FrameIndex tail, FrameIndex head) const {
    return NewPoseEdge{tail, head, t.body_of(tail), t.body_of(head),
                       t.body_of(tail) == t.body_of(head)};
  }
  /// Links tail -> head after every rule passed.
  void Pose(FrameIndex tail, FrameIndex head) {
    const auto v = CheckNewPoseEdge(t, Edge(tail, head));
    ASSERT_FALSE(v.has_value()) << "rule " << static_cast<int>(v->code)
                                << " refused a test scene's edge";
    t.LinkPose(tail, head);
  }
  /// The twist edge D -> {h}|H, semantics TwistCoord(h|H, D, [h]), after W1 and W3 passed.
  TwistEdgeIndex Twist(BodyIndex tail, FrameIndex head) {
    const auto v = CheckNewTwistEdge(t, NewTwistEdge{tail, head, t.body_of(head)});
    EXPECT_FALSE(v.has_value());
    const semantics::TwistSemantics s{t.FrameSem(head).origin(), t.BodyOfSem(head), t.BodySem(tail),
                                      t.FrameSem(head).axes()};
    return t.LinkTwist(tail, head, s);
  }
};

}  // namespace semgraph::topology::testing
