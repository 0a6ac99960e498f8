// Mirror (mirror.h): the reconcile. The owners' structures are replayed from scratch on a
// scratch graph (deterministic order, the graph's own checks decide); the replica is then
// brought to what the scratch graph accepted: removals first, then adds, so edges that stay
// keep their handles (and compiled queries on them stay valid).
#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "mirror_impl.h"

namespace semgraph::dds {

namespace {

bool SameTime(const core::TimeOptions& a, const core::TimeOptions& b) {
  return a.window == b.window && a.interpolation == b.interpolation &&
         a.duplicate_stamp == b.duplicate_stamp && a.sample_capacity == b.sample_capacity;
}

// Adds the edge of a structure row to g with its covariance, in the edge form as the wire
// carries it (stamped: the newest sample, with its stamp; a zero covariance: exact).
core::BuildResult AddEdge(core::SceneGraph<>& g, const Row& r) {
  const Eigen::Vector3d a(r.n[0], r.n[1], r.n[2]), b(r.n[3], r.n[4], r.n[5]);
  const Eigen::Quaterniond q(r.n[0], r.n[1], r.n[2], r.n[3]);
  const Eigen::Vector3d p(r.n[4], r.n[5], r.n[6]);
  const coord::Covariance6 S = internal::UnpackCovariance(r.cov);
  core::CovarianceInput covariance;
  if (internal::HasCovariance(r.cov)) covariance.matrix = &S;
  if (r.kind == semgraph_wire_ELEMENT_TWIST) {
    const core::TwistSpec spec =
        core::TwistSpec::Of(r.head, r.head_body).RelativeTo(r.tail).ExpressedIn(r.head);
    if (!r.stamped) return g.AddTwist(spec, a, b, covariance);
    const core::Stamp t = core::Stamp::Nanoseconds(r.time_ns);
    return covariance.matrix != nullptr ? g.AddTwist(spec, a, b, t, covariance)
                                        : g.AddTwist(spec, a, b, t);
  }
  const core::PoseSpec spec =
      core::PoseSpec::Of(r.head, r.head_body).RelativeTo(r.tail, r.tail_body);
  if (!r.stamped) return g.AddPose(spec, q, p, covariance);
  const core::Stamp t = core::Stamp::Nanoseconds(r.time_ns);
  return covariance.matrix != nullptr ? g.AddPose(spec, q, p, t, covariance)
                                      : g.AddPose(spec, q, p, t);
}

// Adds the wrench of a structure row to g at its storage frame (no conversion): stamped, its
// newest sample at its stamp (the pair then keeps a history).
core::BuildResult AddWrenchRow(core::SceneGraph<>& g, const Row& r) {
  const Eigen::Vector3d f(r.n[0], r.n[1], r.n[2]), m(r.n[3], r.n[4], r.n[5]);
  const core::WrenchSpec spec = core::WrenchSpec::On(r.head_body).By(r.tail_body).At(r.head);
  if (!r.stamped) return g.AddWrench(spec, f, m);
  return g.AddWrench(spec, f, m, core::Stamp::Nanoseconds(r.time_ns));
}

// A refusal of one of `owner`'s relations, as reported (code: the graph's, or the replay's).
Report Refusal(const std::string& owner, base::ErrorCode code, const std::string& text) {
  return {"refused", owner, std::string(base::ToString(code)), "owner '" + owner + "': " + text};
}

}  // namespace

// A joint the replay accepted, and its owner.
struct Mirror::Impl::DesiredJoint {
  std::string owner;
  std::uint64_t source;
  const JointRow* row;
};

// A wrench the replay accepted (its row: on = head_body, by = tail_body, s = head).
struct Mirror::Impl::DesiredWrench {
  std::string owner;
  std::uint64_t source;
  const Row* row;
};

// The replay: the scratch graph, the edges and joints it accepted (their rows point into
// `owners`, unchanged during a reconcile), the refusals in the deterministic order, and the
// owner that took each (twist, head).
struct Mirror::Impl::Replay {
  explicit Replay(core::SceneGraph<>&& g) : scratch(std::move(g)) {}
  core::SceneGraph<> scratch;
  std::vector<Applied> edges;
  std::vector<DesiredJoint> joints;
  std::vector<DesiredWrench> wrenches;
  std::vector<Report> refused;
  std::map<std::pair<bool, std::string>, std::string> edge_owner;
  std::map<std::pair<std::string, std::string>, std::string> wrench_owner;  // {on, by} sorted
};

// The replica from scratch in a scratch graph, then the live graph brought to it (mirror.h).
void Mirror::Impl::Reconcile() {
  const std::vector<const OwnerRec*> order = OwnersInOrder();
  SettleTimeOptions(order);
  auto scratch_made = core::SceneGraph<>::Create(graph.time_options());
  Replay replay(std::move(*scratch_made));
  for (const OwnerRec* o : order) {
    ReplayEdges(*o, replay);
    // The owner's joints, in its order (masters before their mimics), after its edges.
    ReplayJoints(*o, replay);
    // Its wrenches last: their bodies and storage frames are in the scratch graph by then.
    ReplayWrenches(*o, replay);
  }

  // Bring the replica to the replay: removals first (joints, then twists, then poses), then
  // the adds in the deterministic order. Every intermediate edge set is a subset of the
  // accepted one, so the adds pass the same checks they passed on the scratch graph.
  RemoveChangedJoints(replay.joints);
  RemoveChangedEdges(replay.edges);
  RemoveChangedWrenches(replay.wrenches);
  AddMissingBodiesAndFrames(replay.scratch);
  Slots new_slots;
  AddEdges(replay.edges, replay.refused, new_slots);
  AddJoints(replay.joints, replay.refused, new_slots);
  AddWrenches(replay.wrenches, replay.refused, new_slots);
  slots = std::move(new_slots);
  ReportNewRefusals(std::move(replay.refused));
}

// The owners in the replay's order: (start time of their incarnation, owner name).
std::vector<const OwnerRec*> Mirror::Impl::OwnersInOrder() const {
  std::vector<const OwnerRec*> order;
  for (const auto& [name, rec] : owners) order.push_back(&rec);
  std::sort(order.begin(), order.end(), [](const OwnerRec* a, const OwnerRec* b) {
    return std::tie(a->started_ns, a->owner) < std::tie(b->started_ns, b->owner);
  });
  return order;
}

// Time options: the replica takes the first timed owner's while it is still empty (no frame:
// nothing can have been compiled on it); an owner whose stamped edges need other options is
// reported once per structure revision (its edges are stamped with the replica's options).
void Mirror::Impl::SettleTimeOptions(const std::vector<const OwnerRec*>& order) {
  for (const OwnerRec* o : order) {
    if (!o->has_time || !o->any_stamped) continue;
    if (graph.num_frames() == 0 && !SameTime(o->time, graph.time_options())) {
      auto made = core::SceneGraph<>::Create(o->time);
      if (made) graph = std::move(*made);
    }
    break;
  }
  for (const OwnerRec* o : order) {
    if (!o->has_time || !o->any_stamped || SameTime(o->time, graph.time_options())) continue;
    auto w = time_warned.find(o->owner);
    if (w != time_warned.end() && w->second == o->revision) continue;
    time_warned[o->owner] = o->revision;
    Emit({"time_options_differ", o->owner, "",
          "owner '" + o->owner +
              "' keeps its stamped edges with other time options (window, interpolation, "
              "duplicate policy, capacity) than this mirror's replica; queries at a time may "
              "differ"});
  }
}

// Replays one owner's elements on the scratch graph: bodies, frames, poses, then twists. An edge
// into a head another owner took already is refused multiple_pose_parents
// (multiple_twist_parents); the graph's own checks decide the rest.
void Mirror::Impl::ReplayEdges(const OwnerRec& o, Replay& replay) {
  core::SceneGraph<>& scratch = replay.scratch;
  const auto refuse = [&](base::ErrorCode code, const std::string& text) {
    replay.refused.push_back(Refusal(o.owner, code, text));
  };
  for (std::uint8_t kind = 0; kind <= semgraph_wire_ELEMENT_TWIST; ++kind) {
    for (const Row& r : o.rows) {
      if (r.kind != kind) continue;
      if (kind == semgraph_wire_ELEMENT_BODY) {
        if (scratch.FindBody(r.head).is_valid()) continue;
        auto res = scratch.AddBody(r.head);
        if (!res) refuse(res.error().code, res.error().message);
      } else if (kind == semgraph_wire_ELEMENT_FRAME) {
        const core::FrameIndex f = scratch.FindFrame(r.head);
        if (f.is_valid() && scratch.body_name(scratch.body_of(f)) == r.head_body) continue;
        if (!scratch.FindBody(r.head_body).is_valid()) (void)scratch.AddBody(r.head_body);
        auto res = scratch.AddFrame(r.head, r.head_body);
        if (!res) refuse(res.error().code, res.error().message);
      } else {
        const bool twist = kind == semgraph_wire_ELEMENT_TWIST;
        const std::string what = std::string(twist ? "twist of {" : "pose of {") + r.head + "}|" +
                                 r.head_body + " wrt " +
                                 (twist ? r.tail : "{" + r.tail + "}|" + r.tail_body);
        auto prior = replay.edge_owner.find({twist, r.head});
        if (prior != replay.edge_owner.end()) {
          const base::ErrorCode code = twist ? base::ErrorCode::kMultipleTwistParents
                                             : base::ErrorCode::kMultiplePoseParents;
          refuse(code, what + " rejected (" + std::string(base::ToString(code)) + "): {" + r.head +
                           "} already has a " + (twist ? "twist" : "pose") +
                           " parent published by '" + prior->second + "'");
          continue;
        }
        core::BuildResult res = AddEdge(scratch, r);
        if (!res) {
          refuse(res.error().code, res.error().message);
          continue;
        }
        replay.edge_owner[{twist, r.head}] = o.owner;
        Applied a;
        a.owner = o.owner;
        a.source = o.source;
        a.row = &r;
        a.twist = twist;
        a.head = r.head;
        a.head_body = r.head_body;
        a.tail = r.tail;
        a.tail_body = twist ? std::string() : r.tail_body;
        std::copy(r.n, r.n + 7, a.n);
        std::copy(r.cov, r.cov + 21, a.cov);
        a.edge = r.edge;
        a.seq = r.seq;
        a.stamped = r.stamped;
        replay.edges.push_back(std::move(a));
      }
    }
  }
}

// Replays one owner's joints on the scratch graph (a joint takes both parents of its child).
void Mirror::Impl::ReplayJoints(const OwnerRec& o, Replay& replay) {
  for (const JointRow& j : o.joints) {
    const std::string what = "joint " + j.name + " ({" + j.child + "}|" + j.child_body + " wrt {" +
                             j.parent + "}|" + j.parent_body + ")";
    auto prior = replay.edge_owner.find({false, j.child});
    if (prior == replay.edge_owner.end()) prior = replay.edge_owner.find({true, j.child});
    if (prior != replay.edge_owner.end()) {
      const base::ErrorCode code = base::ErrorCode::kMultiplePoseParents;
      replay.refused.push_back(
          Refusal(o.owner, code,
                  what + " rejected (" + std::string(base::ToString(code)) + "): {" + j.child +
                      "} already has a parent published by '" + prior->second + "'"));
      continue;
    }
    core::BuildResult res = replay.scratch.AddJoint(j.Spec());
    if (!res) {
      replay.refused.push_back(Refusal(o.owner, res.error().code, res.error().message));
      continue;
    }
    replay.edge_owner[{false, j.child}] = o.owner;
    replay.edge_owner[{true, j.child}] = o.owner;
    replay.joints.push_back({o.owner, o.source, &j});
  }
}

// Whether the replica's joint (when it has it) keeps a history: its first state was stamped.
bool Mirror::Impl::JointStampedInReplica(const core::internal::JointRecord* rec) const {
  return rec != nullptr && graph.pose_history(rec->child) != nullptr;
}

// Removes the replica's joints that are no longer wanted or changed (a joint's removal is the
// removal of its pose edge), and with a removed master its mimics; mimics before masters.
void Mirror::Impl::RemoveChangedJoints(const std::vector<DesiredJoint>& desired_joints) {
  std::map<std::string, const DesiredJoint*> want_joints;
  for (const DesiredJoint& d : desired_joints) want_joints[d.row->name] = &d;
  std::set<std::string> remove;
  for (const auto& [name, aj] : applied_joints) {
    auto w = want_joints.find(name);
    bool keep =
        w != want_joints.end() && w->second->owner == aj.owner && w->second->row->SameJoint(aj.row);
    if (keep) {
      // Stamped and timeless edges do not convert: such a change re-adds the joint.
      const core::internal::JointRecord* rec = graph.joint_table().Find(name);
      const bool stamped_now = JointStampedInReplica(rec);
      const bool timeless_now = rec != nullptr && rec->timeless;
      const JointRow& r = *w->second->row;
      keep = rec != nullptr && !(r.stamped() && timeless_now) &&
             !(r.state == semgraph_wire_JOINT_STATE_TIMELESS && stamped_now);
    }
    if (!keep) remove.insert(name);
  }
  for (bool grew = true; grew;) {
    grew = false;
    for (const auto& [name, aj] : applied_joints) {
      if (!aj.row.mimic.empty() && remove.count(aj.row.mimic) && remove.insert(name).second) {
        grew = true;
      }
    }
  }
  for (const bool mimics : {true, false}) {
    for (auto it = applied_joints.begin(); it != applied_joints.end();) {
      if (!remove.count(it->first) || it->second.row.mimic.empty() != !mimics) {
        ++it;
        continue;
      }
      const core::BuildResult res = graph.RemovePose(it->second.row.child, it->second.row.parent);
      if (!res) Log("cannot remove joint " + it->first + ": " + res.error().message);
      it = applied_joints.erase(it);
    }
  }
}

// Removes the replica's edges that are not wanted or changed: twists, then poses.
void Mirror::Impl::RemoveChangedEdges(const std::vector<Applied>& desired) {
  std::map<std::pair<bool, std::string>, const Applied*> want;
  for (const Applied& a : desired) want[{a.twist, a.head}] = &a;
  for (const bool twist : {true, false}) {
    for (auto it = applied.begin(); it != applied.end();) {
      if (it->first.first != twist) {
        ++it;
        continue;
      }
      auto w = want.find(it->first);
      if (w != want.end() && w->second->Same(it->second)) {
        ++it;
        continue;
      }
      const core::BuildResult res = twist ? graph.RemoveTwist(it->second.head, it->second.tail)
                                          : graph.RemovePose(it->second.head, it->second.tail);
      if (!res) Log("cannot remove " + it->second.head + ": " + res.error().message);
      it = applied.erase(it);
    }
  }
}

// The scratch graph's bodies and frames the replica does not have yet.
void Mirror::Impl::AddMissingBodiesAndFrames(const core::SceneGraph<>& scratch) {
  for (std::uint32_t i = 0; i < scratch.num_bodies(); ++i) {
    const std::string_view b = scratch.body_name(core::BodyIndex(i));
    if (!graph.FindBody(b).is_valid()) (void)graph.AddBody(b);
  }
  for (std::uint32_t i = 0; i < scratch.num_frames(); ++i) {
    const core::FrameIndex f(i);
    if (!graph.FindFrame(scratch.frame_name(f)).is_valid()) {
      (void)graph.AddFrame(scratch.frame_name(f), scratch.body_name(scratch.body_of(f)));
    }
  }
}

// The slot of an edge or joint the replica keeps (known: its counters and number carry over),
// or a fresh one for one just added.
Slot Mirror::Impl::TakeSlot(const ValueKey& key, bool added, bool* known) {
  Slot slot;
  auto old = slots.find(key);
  *known = old != slots.end() && !added;
  if (*known) slot = std::move(old->second);
  return slot;
}

// Values and samples that arrived before the structure named their edge: applied now.
void Mirror::Impl::ApplyPending(const ValueKey& key, Slot& slot) {
  auto p = pending.find(key);
  if (p != pending.end()) {
    if (p->second.seq > slot.seq) {
      ApplyValue(slot, p->second.seq, p->second.stamp_ns, p->second.n, p->second.cov,
                 p->second.has_acc ? p->second.acc : nullptr, "value");
    }
    pending.erase(p);
  }
  auto ps = pending_samples.find(key);
  if (ps != pending_samples.end()) {
    for (const Pending& e : ps->second) {
      ApplyValue(slot, e.seq, e.stamp_ns, e.n, e.cov, e.has_acc ? e.acc : nullptr, "sample",
                 e.time_ns);
    }
    pending_samples.erase(ps);
  }
}

// Adds the wanted edges the replica lacks (in the deterministic order), and gives every wanted
// edge its slot: its handle, and the value its structure announced when newer.
void Mirror::Impl::AddEdges(const std::vector<Applied>& desired, std::vector<Report>& refused,
                            Slots& new_slots) {
  for (const Applied& a : desired) {
    const Row& r = *a.row;
    auto have = applied.find({a.twist, a.head});
    bool added = false;
    if (have == applied.end()) {
      const core::BuildResult res = AddEdge(graph, r);
      if (!res) {
        // Only a name clash with a frame the replica kept from an earlier structure can do this.
        refused.push_back(Refusal(a.owner, res.error().code, res.error().message));
        continue;
      }
      have = applied.emplace(std::pair{a.twist, a.head}, a).first;
      added = true;
    } else {
      have->second.source = a.source;
      have->second.edge = a.edge;
    }
    have->second.row = nullptr;
    const std::uint8_t vkind = a.twist ? semgraph_wire_VALUE_TWIST : semgraph_wire_VALUE_POSE;
    const ValueKey key{a.source, a.edge, vkind};
    bool known = false;
    Slot slot = TakeSlot(key, added, &known);
    slot.twist = a.twist;
    slot.stamped = a.stamped;
    slot.owner = a.owner;
    slot.head = a.head;
    slot.tail = a.tail;
    if (a.twist) {
      auto h = graph.FindTwistEdge(a.head, a.tail);
      slot.settable = static_cast<bool>(h);
      if (h) slot.twist_handle = *h;
    } else {
      auto h = graph.FindPoseEdge(a.head, a.tail);
      slot.settable = static_cast<bool>(h);
      if (h) slot.pose = *h;
    }
    const std::optional<std::int64_t> time =
        a.stamped ? std::optional<std::int64_t>(r.time_ns) : std::nullopt;
    if (added) {
      slot.seq = r.seq;
      if (time) slot.time_ns = *time;
      if (r.has_acc && a.twist && slot.settable) {
        // The twist was added with the structure's value; its acceleration (checked finite), a
        // stamped edge's on its newest sample.
        const Eigen::Vector3d lin(r.acc[0], r.acc[1], r.acc[2]), ang(r.acc[3], r.acc[4], r.acc[5]);
        const base::ErrorCode code = time ? graph.SetAcceleration(slot.twist_handle, lin, ang,
                                                                  core::Stamp::Nanoseconds(*time))
                                          : graph.SetAcceleration(slot.twist_handle, lin, ang);
        if (code != base::ErrorCode::kOk) {
          Log("the acceleration of the twist into " + a.head +
              " is refused: " + std::string(base::ToString(code)));
        }
      }
    } else if (!known || r.seq > slot.seq) {
      // A kept edge under a new incarnation, or a newer value announced by the structure.
      if (slot.settable) {
        ApplyValue(slot, r.seq, 0, r.n, r.cov, r.has_acc ? r.acc : nullptr, "structure value",
                   time);
      }
      slot.seq = r.seq;
    }
    ApplyPending(key, slot);
    new_slots.emplace(key, std::move(slot));
  }
}

// Adds the wanted joints the replica lacks, then gives each its slot (mimics follow their
// masters, so all adds come first).
void Mirror::Impl::AddJoints(const std::vector<DesiredJoint>& desired_joints,
                             std::vector<Report>& refused, Slots& new_slots) {
  std::vector<std::pair<const JointRow*, bool>> joint_slots;  // row, added
  for (const DesiredJoint& d : desired_joints) {
    const JointRow& j = *d.row;
    auto have = applied_joints.find(j.name);
    bool added = false;
    if (have == applied_joints.end()) {
      const core::BuildResult res = graph.AddJoint(j.Spec());
      if (!res) {
        refused.push_back(Refusal(d.owner, res.error().code, res.error().message));
        continue;
      }
      have = applied_joints.emplace(j.name, AppliedJoint{d.owner, d.source, j}).first;
      added = true;
    } else {
      have->second.source = d.source;
      have->second.row = j;
    }
    joint_slots.push_back({&j, added});
  }
  for (const auto& [j, added] : joint_slots) MakeJointSlot(*j, added, new_slots);
}

// A joint's slot: its group (a settable joint's alone), and its state. A new joint's first
// state decides its kind (timeless or stamped); a kept joint takes a newer announced state.
void Mirror::Impl::MakeJointSlot(const JointRow& j, bool added, Slots& new_slots) {
  const AppliedJoint& aj = applied_joints.at(j.name);
  const ValueKey key{aj.source, j.id, semgraph_wire_VALUE_JOINT};
  bool known = false;
  Slot slot = TakeSlot(key, added, &known);
  slot.joint = true;
  slot.stamped = j.stamped();
  slot.owner = aj.owner;
  slot.head = j.name;
  slot.tail = j.parent;
  slot.settable = false;
  slot.unset = j.state == semgraph_wire_JOINT_STATE_NONE;
  if (j.type != core::JointType::kFixed && j.mimic.empty()) {
    const std::string_view names[] = {j.name};
    auto group = graph.MakeJointGroup(names);
    if (group) {
      slot.group = std::move(*group);
      slot.settable = true;
    }
  }
  const bool replica_stamped = JointStampedInReplica(graph.joint_table().Find(j.name));
  if (slot.settable && j.state != semgraph_wire_JOINT_STATE_NONE &&
      (added || (j.stamped() && !replica_stamped))) {
    // The joint's first state decides its kind (timeless or stamped: histories allocated here).
    const core::JointValue q[] = {{j.name, j.q}}, qdot[] = {{j.name, j.qdot}},
                           qddot[] = {{j.name, j.qddot}};
    const std::span<const core::JointValue> a = j.has_qddot
                                                    ? std::span<const core::JointValue>(qddot)
                                                    : std::span<const core::JointValue>();
    const core::BuildResult res =
        j.stamped()
            ? (j.has_qddot ? graph.SetJoints(q, qdot, a, core::Stamp::Nanoseconds(j.time_ns))
                           : graph.SetJoints(q, qdot, core::Stamp::Nanoseconds(j.time_ns)))
        : j.has_qddot ? graph.SetJoints(q, qdot, a)
                      : graph.SetJoints(q, qdot);
    if (!res) Log("joint " + j.name + ": its state is refused: " + res.error().message);
    slot.seq = j.seq;
    if (j.stamped()) slot.time_ns = j.time_ns;
  } else if (added) {
    slot.seq = j.seq;
  } else if (slot.settable && (!known || j.seq > slot.seq)) {
    const double n[7] = {j.q, j.qdot, 0, 0, 0, 0, 0};
    ApplyValue(slot, j.seq, 0, n, nullptr, j.has_qddot ? &j.qddot : nullptr, "structure value",
               j.stamped() ? std::optional<std::int64_t>(j.time_ns) : std::nullopt);
    slot.seq = j.seq;
  }
  ApplyPending(key, slot);
  new_slots.emplace(key, std::move(slot));
}

// Replays one owner's wrenches on the scratch graph (core/wrenches.h): a pair whose bodies
// (either order) another owner took already is refused duplicate_wrench; a storage frame that
// is not a frame of `on` in the scratch graph (another owner's frame of that name) is refused
// unknown_frame; AddWrench's own checks decide the rest.
void Mirror::Impl::ReplayWrenches(const OwnerRec& o, Replay& replay) {
  core::SceneGraph<>& scratch = replay.scratch;
  for (const Row& r : o.rows) {
    if (r.kind != semgraph_wire_ELEMENT_WRENCH) continue;
    const std::string what =
        "wrench on " + r.head_body + " by " + r.tail_body + " at {" + r.head + "}";
    const auto [lo, hi] = std::minmax(r.head_body, r.tail_body);
    auto prior = replay.wrench_owner.find({lo, hi});
    if (prior != replay.wrench_owner.end()) {
      replay.refused.push_back(Refusal(o.owner, base::ErrorCode::kDuplicateWrench,
                                       what + " rejected (duplicate_wrench): the pair is " +
                                           "published by '" + prior->second + "'"));
      continue;
    }
    const core::FrameIndex s = scratch.FindFrame(r.head);
    const core::BodyIndex on = scratch.FindBody(r.head_body);
    if (!s.is_valid() || !on.is_valid() || scratch.body_of(s) != on) {
      replay.refused.push_back(Refusal(o.owner, base::ErrorCode::kUnknownFrame,
                                       what + " rejected (unknown_frame): {" + r.head +
                                           "} is not a frame of " + r.head_body + " here"));
      continue;
    }
    const core::BuildResult res = AddWrenchRow(scratch, r);
    if (!res) {
      replay.refused.push_back(Refusal(o.owner, res.error().code, res.error().message));
      continue;
    }
    replay.wrench_owner[{lo, hi}] = o.owner;
    replay.wrenches.push_back({o.owner, o.source, &r});
  }
}

// Removes the replica's wrenches that are no longer wanted, or wanted from another owner or at
// another storage frame, or now stamped (timeless).
void Mirror::Impl::RemoveChangedWrenches(const std::vector<DesiredWrench>& desired) {
  std::map<std::pair<std::string, std::string>, const DesiredWrench*> want;
  for (const DesiredWrench& d : desired) want[{d.row->head_body, d.row->tail_body}] = &d;
  for (auto it = applied_wrenches.begin(); it != applied_wrenches.end();) {
    auto w = want.find(it->first);
    if (w != want.end() && w->second->owner == it->second.owner &&
        w->second->row->head == it->second.frame && w->second->row->stamped == it->second.stamped) {
      ++it;
      continue;
    }
    const core::BuildResult res = graph.RemoveWrench(it->first.first, it->first.second);
    if (!res) Log("cannot remove the wrench on " + it->first.first + ": " + res.error().message);
    it = applied_wrenches.erase(it);
  }
}

// Adds the wanted wrenches the replica lacks (stored at their storage frame: no conversion), and
// gives each its slot: its handle, and the value its structure announced when newer.
void Mirror::Impl::AddWrenches(const std::vector<DesiredWrench>& desired,
                               std::vector<Report>& refused, Slots& new_slots) {
  for (const DesiredWrench& d : desired) {
    const Row& r = *d.row;
    const std::pair<std::string, std::string> pair{r.head_body, r.tail_body};
    auto have = applied_wrenches.find(pair);
    bool added = false;
    if (have == applied_wrenches.end()) {
      const core::BuildResult res = AddWrenchRow(graph, r);
      if (!res) {
        refused.push_back(Refusal(d.owner, res.error().code, res.error().message));
        continue;
      }
      have =
          applied_wrenches
              .emplace(pair, internal::AppliedWrench{d.owner, d.source, r.edge, r.head, r.stamped})
              .first;
      added = true;
    } else {
      have->second.source = d.source;
      have->second.id = r.edge;
    }
    const ValueKey key{d.source, r.edge, semgraph_wire_VALUE_WRENCH};
    bool known = false;
    Slot slot = TakeSlot(key, added, &known);
    slot.wrench = true;
    slot.stamped = r.stamped;
    slot.owner = d.owner;
    slot.head = r.head_body;
    slot.tail = r.tail_body;
    auto h = graph.FindWrench(r.head_body, r.tail_body);
    slot.settable = static_cast<bool>(h);
    if (h) slot.wrench_handle = *h;
    const std::optional<std::int64_t> time =
        r.stamped ? std::optional<std::int64_t>(r.time_ns) : std::nullopt;
    if (added) {
      slot.seq = r.seq;
      if (time) slot.time_ns = *time;
    } else if (!known || r.seq > slot.seq) {
      if (slot.settable) ApplyValue(slot, r.seq, 0, r.n, nullptr, nullptr, "structure value", time);
      slot.seq = r.seq;
    }
    ApplyPending(key, slot);
    new_slots.emplace(key, std::move(slot));
  }
}

// Reports each refusal once, in the deterministic order; they become the current refusals.
void Mirror::Impl::ReportNewRefusals(std::vector<Report> refused) {
  for (const Report& r : refused) {
    const bool known = std::any_of(refusals.begin(), refusals.end(), [&](const Report& o) {
      return o.owner == r.owner && o.code == r.code && o.message == r.message;
    });
    if (!known) Emit(r);
  }
  refusals = std::move(refused);
}

}  // namespace semgraph::dds
