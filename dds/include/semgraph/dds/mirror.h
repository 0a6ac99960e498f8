// File: semgraph/dds/mirror.h
//
// Mirror: a local replica of the scene shared on a DDS domain by any number of publishers
// (publisher.h; docs/distributed.md). The mirror's receive thread takes the structure samples;
// values are taken where they arrive (a data-available listener on Cyclone's receive thread,
// and the mirror's thread for any left over). Writers of the replica graph run one at a time
// (one lock), so the graph has one writer at any moment:
//   - structure: every owner's latest structure is kept; after each change the mirror decides
//     the replica from scratch, deterministically: owners in the order (start time of their
//     incarnation, owner name), each owner's elements in the order bodies, frames, poses,
//     twists, applied to an empty graph through the graph's own checks (AddPose/AddTwist), and
//     an edge whose head already has a pose (twist) parent from another owner is refused with
//     multiple_pose_parents (multiple_twist_parents). The replica is then brought to that
//     result by removing the edges it should not have and adding the missing ones (edges that
//     stay keep their handles, so compiled queries on them stay valid). Every mirror holding the
//     same structures therefore holds the same graph and refuses the same relations; each new
//     refusal is reported to the callback and on the status topic.
//   - values: the receive thread writes them through handles (SceneGraph::SetPose/SetTwist),
//     so compiled queries evaluated on other threads stay lock-free (sequence locks). Per edge,
//     a value numbered at or below the last applied one is dropped (repeats, reorders).
//   - time: an edge the structure announces stamped is added stamped (with its newest sample),
//     and its stamped samples go into its history through the stamped setters; the history's
//     rules (out of order inserts, duplicate policy, window) decide reorders and repeats
//     (refusals counted in samples_dropped()). The replica takes the time options of the first
//     timed owner while it is still empty; an owner needing others is reported
//     `time_options_differ`. A stamped sample for an unstamped edge (or the reverse) is rejected.
//   - joints: added through AddJoint (after the owner's edges; a joint whose child already has
//     a parent from an earlier owner is refused multiple_pose_parents, any other AddJoint error
//     with its code); their states through SetJoints / SetJointState, stamped or not, so mimics
//     follow and the joint rules (limits, stamp rules) apply as in the publisher.
//   - accelerations: a twist edge's value (or structure element) carries its acceleration or
//     says it has none; the mirror sets the twist then the acceleration (checked first, so a
//     refused one changes nothing), and a twist without one clears the replica's; a stamped
//     sample likewise with the stamped setters (SetTwist, then SetAcceleration at its stamp). A
//     joint state with qddot goes through SetJointState with accelerations (atomic); a stamped
//     one through the stamped SetJoints with accelerations (by name: allocates).
//   - wrenches: each owner's (on, by) pairs are replayed after its joints (AddWrench at the
//     storage frame; a pair, or its reaction, another owner took is refused duplicate_wrench);
//     the replica adds and removes them as edges (a stamped pair stamped, with its newest
//     sample), and their values and stamped samples go through SetWrench on the wrench's handle.
//   - batches (Publisher::BeginBatch / Flush): a batch's values are applied in order under the
//     same rules as single values, then on_change is called once.
//   - faults: a publisher whose lease ends (killed, cut off) is reported `liveliness_lost`; its
//     edges and last values stay. Its restarted incarnation (same owner name) replaces its
//     structure: the replica is reconciled to it (no duplicate, no leftover edge). A
//     malformed message (bad number, bad rotation, bad name, unknown kind, an owner's duplicate
//     edge) is rejected whole, with a log line; it changes nothing.
// Topology changes (adds, removals) need exclusive access to the graph: compile queries inside
// WithGraph(); readers that evaluate while the structure may change must be paused by
// MirrorOptions::topology_hook, through which the mirror runs every topology change (until the
// scene graph supports topology changes under running readers).
// Costs: a structure change O(the whole scene) (the replay); a value O(1) (hash lookup + SetPose).
// Thread safety: graph() may be read by any thread as above; the other calls are thread-safe.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/dds/export.h"
#include "semgraph/dds/publisher.h"

namespace semgraph::dds {

/// Something a mirror decided or noticed (also published on the status topic).
struct Report {
  std::string event;    ///< refused | rejected_message | liveliness_lost | alive
  std::string owner;    ///< the publisher concerned (may be empty for a message without one)
  std::string code;     ///< refused: the error code's snake_case name ("multiple_pose_parents")
  std::string message;  ///< text naming the relation and why
};

struct MirrorOptions {
  std::string name = "mirror";  ///< names the mirror in status reports
  std::uint32_t domain = kDefaultDomain;
  /// On a receive thread, for every report (refusals in the deterministic order).
  std::function<void(const Report&)> on_report;
  /// On a receive thread (the mirror's or Cyclone's), one call at a time, after each batch of
  /// values (or structure change) was applied.
  std::function<void()> on_change;
  /// Runs each topology change: called with the change, which it must call once (e.g. after
  /// pausing readers). Default: call it directly.
  std::function<void(const std::function<void()>& apply)> topology_hook;
  /// A log line (rejected messages); default: to stderr with the prefix "semgraph-dds: ".
  std::function<void(const std::string&)> log;
};

/// What a mirror knows of one publisher.
struct OwnerState {
  std::string owner;
  std::uint64_t source = 0;
  std::int64_t started_ns = 0;
  std::uint64_t revision = 0;
  bool alive = false;
  std::size_t elements = 0;
};

/// Per mirrored edge: who publishes it and how its values arrive (for `semgraph monitor`).
struct EdgeState {
  std::string owner;
  bool twist = false;
  std::string head, tail;
  std::uint64_t seq = 0;           ///< number of the last applied value
  std::uint64_t received = 0;      ///< values applied so far
  std::int64_t last_stamp_ns = 0;  ///< publisher's clock of the last value (0: from the structure)
  std::int64_t last_receive_ns = 0;
  bool stamped = false;             ///< a stamped edge (its values are samples in a history)
  std::int64_t newest_time_ns = 0;  ///< stamped: the newest sample's stamp (the graph's time)
  bool joint = false;   ///< a joint's state: head = the joint's name, tail = its parent frame
  bool wrench = false;  ///< a wrench: head = the body it acts on, tail = the body exerting it
};

class SEMGRAPH_DDS_EXPORT Mirror {
 public:
  static base::Expected<std::unique_ptr<Mirror>, std::string> Create(MirrorOptions options);
  /// Stops the receive thread and leaves the domain.
  ~Mirror();
  Mirror(const Mirror&) = delete;
  Mirror& operator=(const Mirror&) = delete;

  /// The replica. Compiled queries made on it (inside WithGraph) may be evaluated on any
  /// thread while values stream in.
  [[nodiscard]] const core::SceneGraph<>& graph() const noexcept;
  /// Runs fn with the graph while no topology change runs (compile queries here).
  void WithGraph(const std::function<void(const core::SceneGraph<>&)>& fn) const;

  /// Incremented after every applied structure change / batch of values.
  [[nodiscard]] std::uint64_t structure_generation() const noexcept;
  [[nodiscard]] std::uint64_t values_applied() const noexcept;
  [[nodiscard]] std::uint64_t messages_rejected() const noexcept;
  /// Stamped samples the replica's histories refused by their rules (stamp_too_old, or
  /// duplicate_stamp under the reject policy): reordered or repeated samples, not malformed.
  [[nodiscard]] std::uint64_t samples_dropped() const noexcept;

  [[nodiscard]] std::vector<OwnerState> Owners() const;
  [[nodiscard]] std::vector<EdgeState> Edges() const;
  /// Every report so far, in order.
  [[nodiscard]] std::vector<Report> Reports() const;
  /// The relations currently refused (deterministic order), as reports.
  [[nodiscard]] std::vector<Report> Refusals() const;

  /// True when, for every owner known, the replica holds its latest structure's edges with at
  /// least the values that structure announced (a publisher that published its structure after
  /// its last value update is then mirrored exactly).
  [[nodiscard]] bool CaughtUp() const;
  /// Waits (polling) until pred() or the timeout; returns pred().
  bool WaitUntil(const std::function<bool()>& pred, std::chrono::milliseconds timeout) const;

 private:
  struct Impl;
  explicit Mirror(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace semgraph::dds
