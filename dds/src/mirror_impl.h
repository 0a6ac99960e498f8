// Internal to semgraph_dds: what the mirror's files share. Not installed.
//   mirror.cc            the object: creation, teardown, the thread-safe queries
//   mirror_parse.cc      structure samples checked and copied out; the wire's number checks
//   mirror_threads.cc    the receive paths: structures on the mirror's thread, values and
//                        batches where they arrive (Cyclone's listener or the mirror's thread)
//   mirror_reconcile.cc  the replay of the owners' structures, and the replica brought to it
// Invariants (under Impl::state_mutex): `applied`, `applied_joints` and `applied_wrenches` are
// the replica's mirrored edges, joints and wrenches; `slots` has one slot per mirrored edge,
// joint or wrench, keyed by (source, edge id, value kind); `pending` and `pending_samples` hold
// values whose structure has not come yet.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include "semgraph/dds/mirror.h"
#include "wire.h"

namespace semgraph::dds::internal {

// A joint of a structure sample (semgraph_wire_Joint, checked).
struct JointRow {
  std::uint32_t id = 0;
  std::uint64_t seq = 0;
  core::JointType type = core::JointType::kFixed;
  std::string name, parent, parent_body, child, child_body, mimic;
  double origin[7] = {1, 0, 0, 0, 0, 0, 0};
  double axis[3] = {1, 0, 0};
  double lower = 0, upper = 0, multiplier = 1, offset = 0;
  std::uint8_t state = 0;
  double q = 0, qdot = 0;
  std::int64_t time_ns = 0;
  bool has_qddot = false;  // qddot given (a stamped joint's: its newest sample's)
  double qddot = 0;
  [[nodiscard]] bool stamped() const { return state == semgraph_wire_JOINT_STATE_STAMPED; }
  // The AddJoint spec (views into this row).
  [[nodiscard]] core::JointSpec Spec() const {
    core::JointSpec s;
    s.name = name;
    s.type = type;
    s.parent = parent;
    s.parent_body = parent_body;
    s.child = child;
    s.child_body = child_body;
    s.q_origin = Eigen::Quaterniond(origin[0], origin[1], origin[2], origin[3]);
    s.p_origin = Eigen::Vector3d(origin[4], origin[5], origin[6]);
    s.axis = Eigen::Vector3d(axis[0], axis[1], axis[2]);
    s.lower = lower;
    s.upper = upper;
    s.mimic = mimic;
    s.multiplier = multiplier;
    s.offset = offset;
    return s;
  }
  // The same joint (its state aside).
  [[nodiscard]] bool SameJoint(const JointRow& o) const {
    return type == o.type && name == o.name && parent == o.parent && parent_body == o.parent_body &&
           child == o.child && child_body == o.child_body && mimic == o.mimic &&
           std::equal(origin, origin + 7, o.origin) && std::equal(axis, axis + 3, o.axis) &&
           lower == o.lower && upper == o.upper && multiplier == o.multiplier && offset == o.offset;
  }
};

struct OwnerRec {
  std::string owner;
  std::uint64_t source = 0;
  std::int64_t started_ns = 0;
  std::uint64_t revision = 0;
  bool alive = false;
  std::vector<Row> rows;
  std::vector<JointRow> joints;
  bool has_time = false;  // the structure gave time options
  core::TimeOptions time;
  bool any_stamped = false;
};

struct ValueKey {
  std::uint64_t source;
  std::uint32_t edge;
  std::uint8_t kind;
  bool operator==(const ValueKey&) const = default;
};
struct ValueKeyHash {
  std::size_t operator()(const ValueKey& k) const noexcept {
    std::uint64_t h = k.source * 0x9E3779B97F4A7C15ull ^ (std::uint64_t{k.edge} << 1 | k.kind);
    h ^= h >> 31;
    return static_cast<std::size_t>(h * 0xBF58476D1CE4E5B9ull);
  }
};

struct Slot {
  bool twist = false;
  bool joint = false;  // a joint's state (group: the joint alone; empty for fixed and mimic joints)
  bool wrench = false;  // a wrench: head = on body, tail = by body (wrench_handle)
  core::WrenchHandle wrench_handle;
  core::JointGroup group;
  bool unset = false;     // a joint never set (its first stamped state may still be on the way)
  bool stamped = false;   // a stamped edge: values come as stamped samples
  bool settable = false;  // false for a constant (same-body) pose edge: no handle
  core::PoseHandle pose;
  core::TwistHandle twist_handle;
  std::uint64_t seq = 0;
  std::uint64_t received = 0;
  std::int64_t stamp_ns = 0, receive_ns = 0;
  std::int64_t time_ns = 0;  // stamped: the newest sample's stamp applied
  std::string owner, head, tail;
};

struct Pending {
  std::uint64_t seq = 0;
  std::int64_t stamp_ns = 0;
  double n[7];
  std::int64_t time_ns = 0;  // a stamped sample's stamp
  double cov[21] = {};       // the packed covariance (wire.h)
  bool has_acc = false;      // the acceleration (twist) or qddot (joint, acc[0]) given
  double acc[6] = {};
};

// A wrench of the replica (the pair on, by) and where it came from.
struct AppliedWrench {
  std::string owner;
  std::uint64_t source = 0;
  std::uint32_t id = 0;
  std::string frame;     // the storage frame s
  bool stamped = false;  // added stamped (the pair keeps a history)
};

// An edge of the replica and where it came from.
struct Applied {
  std::string owner;
  std::uint64_t source = 0;
  const Row* row = nullptr;  // valid during a reconcile only
  bool twist = false;
  std::string head, head_body, tail, tail_body;
  double n[7];
  double cov[21] = {};  // packed (wire.h)
  std::uint32_t edge = 0;
  std::uint64_t seq = 0;
  bool stamped = false;
  bool Same(const Applied& o) const {
    if (owner != o.owner || twist != o.twist || head != o.head || head_body != o.head_body ||
        tail != o.tail || tail_body != o.tail_body || stamped != o.stamped) {
      return false;
    }
    // A constant (same-body) pose edge changes only through the structure, its covariance too.
    if (!twist && head_body == tail_body) {
      return std::equal(n, n + 7, o.n) && std::equal(cov, cov + 21, o.cov);
    }
    return true;
  }
};

// The wire's number checks (mirror_parse.cc), for structures and values alike.
bool Finite(const double* n, int k);
bool UnitQuaternion(const double* n);
bool GoodStamp(std::int64_t t);

// Checks one structure sample and copies it out; the reason when it is malformed.
std::string ParseStructure(const semgraph_wire_Structure& s, OwnerRec* out);

}  // namespace semgraph::dds::internal

namespace semgraph::dds {

// The mirror's files name these unqualified (this header is theirs alone).
using internal::Applied;
using internal::Entity;
using internal::JointRow;
using internal::OwnerRec;
using internal::Pending;
using internal::Row;
using internal::Slot;
using internal::TopicKind;
using internal::ValueKey;
using internal::ValueKeyHash;

struct Mirror::Impl {
  MirrorOptions options;
  core::SceneGraph<> graph;
  Entity participant, structure_reader, value_reader, sample_reader, batch_reader, status_writer,
      waitset, guard;
  std::thread thread;
  std::atomic<bool> stop{false};
  std::atomic<std::uint64_t> generation{0}, values{0}, rejected{0}, dropped{0};

  mutable std::mutex state_mutex;     // everything below; held by the receive thread per batch
  mutable std::mutex topology_mutex;  // topology changes of `graph` (WithGraph)
  std::map<std::string, OwnerRec> owners;
  std::map<dds_instance_handle_t, std::string> owner_of_instance;
  std::map<std::pair<bool, std::string>, Applied> applied;  // (twist, head) -> edge
  struct AppliedJoint {
    std::string owner;
    std::uint64_t source = 0;
    JointRow row;
  };
  std::map<std::string, AppliedJoint> applied_joints;  // joint name -> joint
  std::map<std::pair<std::string, std::string>, internal::AppliedWrench>
      applied_wrenches;  // (on, by) -> wrench
  std::unordered_map<ValueKey, Slot, ValueKeyHash> slots;
  std::unordered_map<ValueKey, Pending, ValueKeyHash> pending;
  std::unordered_map<ValueKey, std::vector<Pending>, ValueKeyHash> pending_samples;
  std::map<std::string, std::uint64_t> time_warned;  // owner -> revision whose options differ
  std::vector<Report> reports, refusals;
  std::uint64_t serial = 0;
  std::uint64_t log_count = 0;

  void Log(const std::string& line) {
    if (options.log) {
      options.log(line);
    } else {
      std::fprintf(stderr, "semgraph-dds: %s\n", line.c_str());
    }
  }
  void Emit(Report r) {
    if (status_writer.ok()) {
      semgraph_wire_Status s{};
      s.mirror = options.name.data();
      s.serial = ++serial;
      s.event = r.event.data();
      s.owner = r.owner.data();
      s.code = r.code.data();
      s.message = r.message.data();
      (void)dds_write(status_writer.get(), &s);
    }
    if (options.on_report) options.on_report(r);
    reports.push_back(std::move(r));
  }
  void Reject(const std::string& owner, const std::string& what) {
    rejected.fetch_add(1, std::memory_order_relaxed);
    // Hostile streams must not flood the log: the first 20, then every 1000th.
    if (log_count < 20 || log_count % 1000 == 0) Log("rejected " + what);
    ++log_count;
    Emit({"rejected_message", owner, "malformed_message", what});
  }

  void Loop();
  void TakeStructure();
  // One value as the value/sample topics and batches carry it.
  struct In {
    std::uint64_t source;
    std::uint32_t edge;
    std::uint8_t kind;
    std::uint64_t seq;
    std::int64_t stamp_ns, time_ns;
    const double* numbers;
    const double* covariance;    // packed, 21 (wire.h)
    const double* acceleration;  // null: none; twist: 6 numbers, joint: qddot (wire.h)
  };
  bool HandleValue(const In& v, bool samples);
  // on_change, one call at a time (values are taken on Cyclone's and the mirror's threads).
  std::mutex change_mutex;
  void Changed() {
    if (!options.on_change) return;
    std::lock_guard<std::mutex> lock(change_mutex);
    options.on_change();
  }
  void TakeValues(dds_entity_t reader, bool samples);
  void TakeBatches();
  // After a batch of values: the counter, then on_change.
  void CountApplied(std::uint64_t applied_now);
  // Applies a value (time: a stamped sample's stamp) with its packed covariance `cov` (null or
  // all zero: exact) and its acceleration `acc` (null: none; a twist's is then cleared, a
  // joint keeps its qddot); true when the graph took it. `from` (the message on the wire) names
  // its edge and source when the setter refuses its numbers.
  bool ApplyValue(Slot& slot, std::uint64_t seq, std::int64_t stamp, const double* n,
                  const double* cov, const double* acc, const std::string& what,
                  std::optional<std::int64_t> time = std::nullopt, const In* from = nullptr);
  // ApplyValue's steps: what the value carries beside its numbers (the reason it is malformed,
  // or empty), and the setter of the slot's kind (noexcept, allocation-free).
  [[nodiscard]] std::string Malformed(const Slot& slot, bool has_covariance,
                                      const double* acc) const;
  base::ErrorCode SetSlot(Slot& slot, const double* n, const coord::Covariance6* S,
                          const double* acc, std::optional<core::Stamp> at,
                          core::UpdateError* bad) noexcept;
  // True when a refusal of the current structures names `owner`.
  [[nodiscard]] bool HasRefusal(const std::string& owner) const;

  // The reconcile (mirror_reconcile.cc), step by step.
  void Reconcile();
  struct DesiredJoint;
  struct DesiredWrench;
  struct Replay;  // the scratch graph and what it accepted
  using Slots = std::unordered_map<ValueKey, Slot, ValueKeyHash>;
  [[nodiscard]] std::vector<const OwnerRec*> OwnersInOrder() const;
  void SettleTimeOptions(const std::vector<const OwnerRec*>& order);
  static void ReplayEdges(const OwnerRec& o, Replay& replay);
  static void ReplayJoints(const OwnerRec& o, Replay& replay);
  static void ReplayWrenches(const OwnerRec& o, Replay& replay);
  void RemoveChangedWrenches(const std::vector<DesiredWrench>& desired);
  void AddWrenches(const std::vector<DesiredWrench>& desired, std::vector<Report>& refused,
                   Slots& new_slots);
  [[nodiscard]] bool JointStampedInReplica(const core::internal::JointRecord* rec) const;
  void RemoveChangedJoints(const std::vector<DesiredJoint>& desired_joints);
  void RemoveChangedEdges(const std::vector<Applied>& desired);
  void AddMissingBodiesAndFrames(const core::SceneGraph<>& scratch);
  Slot TakeSlot(const ValueKey& key, bool added, bool* known);
  void ApplyPending(const ValueKey& key, Slot& slot);
  void AddEdges(const std::vector<Applied>& desired, std::vector<Report>& refused,
                Slots& new_slots);
  void AddJoints(const std::vector<DesiredJoint>& desired_joints, std::vector<Report>& refused,
                 Slots& new_slots);
  void MakeJointSlot(const JointRow& j, bool added, Slots& new_slots);
  void ReportNewRefusals(std::vector<Report> refused);
};

}  // namespace semgraph::dds
