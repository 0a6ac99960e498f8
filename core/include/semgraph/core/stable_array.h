// File: semgraph/core/stable_array.h
//
// StableArray<T>: the growable array whose elements never move, defined in the base layer
// (semgraph/base/stable_array.h: layout, invariants, costs, thread safety), for the topology
// and the edge values alike.
#pragma once

#include "semgraph/base/stable_array.h"

namespace semgraph::core {

using base::StableArray;

}  // namespace semgraph::core
