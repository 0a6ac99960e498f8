// File: semgraph/core/accelerations.h
//
// Accelerations on twist edges (docs/dynamics.md §7): the words of the API. A twist edge
// D -> {h}|H may carry, beside its screw twist, the acceleration AccelerationCoord(h|H, D, [h])
// (the edge form: a = classical acceleration of h's origin as a point of H relative to D,
// alpha = angular acceleration of H relative to D, both in [h]; EdgeValues::A_DH). It is given
// with the twist (SceneGraph::AddTwist with an AccelerationInput) or on its own
// (SceneGraph::AddAcceleration), in the op's point and frame, and converted to the edge form with
// the current poses and twist. A twist given without an acceleration leaves the edge without
// one (never a stale value).
//
// Queries compose the edges' accelerations along the twist path (evaluate.h,
// AccumulateAccelerationStep): each edge moved to point e and [r], inverted when traversed
// against its direction (alpha' = -alpha, a' = -a + 2 w x v), and composed with the Coriolis
// terms (alpha_MC = alpha_MB + alpha_BC + w_MB x w_BC, a_MCe = a_MBe + a_BCe + 2 w_MB x v_BCe).
// An edge on the path without an acceleration: no_acceleration, naming the edge.
// Costs: AddAcceleration O(log n + d) (one basic pose each for the point and the frame); queries
// O(k (log n + d)) as twist queries. Queries: noexcept, allocation-free, lock-free.
// Real time: SetAcceleration (by twist handle, edge form) and CompiledAcceleration
// (compiled_acceleration.h).
// Joints: a joint's twist edge carries the acceleration of its qddot when one was given
// (SceneGraph::SetJoints with accelerations, SetJointAccelerations; joints.h); adds of an
// acceleration on it are joint_edge.
// Stamped edges (docs/dynamics.md "Stamped accelerations"): each twist sample may carry its
// acceleration (edge_history.h, beside the sample); AddTwist / AddAcceleration / SetAcceleration
// with a stamp; timed queries read it as the twist (timed_read.h: interpolated linearly,
// present only when both samples carry one, held within the horizon).
#pragma once

#include "semgraph/coord/values.h"

namespace semgraph::core {

/// An acceleration given with a twist: (a, alpha) at the twist op's point, in its frame.
struct AccelerationInput {
  Eigen::Vector3d linear;   ///< a: classical acceleration of the point of the body at e
  Eigen::Vector3d angular;  ///< alpha
};

/// The parts of an acceleration answer. A linear acceleration has the full semantics (its
/// point matters); an angular one keeps the point of the coordinate frame's origin (unused).
struct LinearAcceleration {
  semantics::AccelerationSemantics semantics;
  Eigen::Vector3d value;  ///< a_DCe_R
};
struct AngularAcceleration {
  semantics::AccelerationSemantics semantics;
  Eigen::Vector3d value;  ///< alpha_DC_R
};

}  // namespace semgraph::core
