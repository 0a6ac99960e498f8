// File: semgraph/topology/ids.h
//
// The strong index types of the topology layer, all base::StrongIndex instances (dense
// std::uint32_t, distinct types, invalid by default; invariants and costs: base/index.h):
//   FrameIndex      a frame node of the pose forest
//   BodyIndex       a body node
//   TwistEdgeIndex  a twist edge slot (also the edge's key in its tree's TwistForest)
#pragma once

#include <cstdint>

#include "semgraph/base/index.h"

namespace semgraph::topology {

struct FrameTag {};
struct BodyTag {};
struct TwistEdgeTag {};

/// A frame node of the pose forest.
using FrameIndex = base::StrongIndex<FrameTag>;
/// A body node.
using BodyIndex = base::StrongIndex<BodyTag>;
/// A twist edge slot (slots of removed edges are reused).
using TwistEdgeIndex = base::StrongIndex<TwistEdgeTag>;

static_assert(sizeof(FrameIndex) == sizeof(std::uint32_t));
static_assert(sizeof(BodyIndex) == sizeof(std::uint32_t));

}  // namespace semgraph::topology
