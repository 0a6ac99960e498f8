// Mirror (mirror.h): the receive thread, the deterministic replay of the owners' structures,
// and the value path through handles.
#include "semgraph/dds/mirror.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "wire.h"

namespace semgraph::dds {

using internal::Entity;
using internal::TopicKind;

namespace {

constexpr std::uint32_t kMaxElements = 1u << 20;  // per structure sample
constexpr std::size_t kMaxPending = 1u << 16;     // values waiting for their structure
constexpr int kTakeBatch = 256;
constexpr std::uint32_t kMaxSampleCapacity = 1u << 20;  // per stamped edge (a hostile one must not exhaust memory)
constexpr std::size_t kMaxPendingSamples = 1024;        // per edge waiting for its structure

struct Row {
  std::uint8_t kind = 0;
  std::uint32_t edge = 0;
  std::uint64_t seq = 0;
  std::string head, head_body, tail, tail_body;
  double n[7] = {0, 0, 0, 0, 0, 0, 0};
  bool stamped = false;
  std::int64_t time_ns = 0;
};

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
           std::equal(origin, origin + 7, o.origin) && std::equal(axis, axis + 3, o.axis) && lower == o.lower &&
           upper == o.upper && multiplier == o.multiplier && offset == o.offset;
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
  bool joint = false;     // a joint's state (group: the joint alone; empty for fixed and mimic joints)
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
};

// An edge of the replica and where it came from.
struct Applied {
  std::string owner;
  std::uint64_t source = 0;
  const Row* row = nullptr;  // valid during a reconcile only
  bool twist = false;
  std::string head, head_body, tail, tail_body;
  double n[7];
  std::uint32_t edge = 0;
  std::uint64_t seq = 0;
  bool stamped = false;
  bool Same(const Applied& o) const {
    if (owner != o.owner || twist != o.twist || head != o.head || head_body != o.head_body ||
        tail != o.tail || tail_body != o.tail_body || stamped != o.stamped) {
      return false;
    }
    // A constant (same-body) pose edge changes only through the structure.
    if (!twist && head_body == tail_body) return std::equal(n, n + 7, o.n);
    return true;
  }
};

bool Finite(const double* n, int k) {
  for (int i = 0; i < k; ++i) {
    if (!std::isfinite(n[i])) return false;
  }
  return true;
}
bool UnitQuaternion(const double* n) {  // w x y z, with coord's tolerance
  return coord::ValidateQuaternion(Eigen::Quaterniond(n[0], n[1], n[2], n[3])).has_value();
}
// Stamps the graph accepts (core/time.h).
bool GoodStamp(std::int64_t t) {
  return t >= -core::kMaxStampNanoseconds && t <= core::kMaxStampNanoseconds;
}
std::string Str(const char* s) { return s == nullptr ? std::string() : std::string(s); }
bool GoodName(const std::string& s) { return static_cast<bool>(semantics::ValidateName(s)); }

const char* KindName(std::uint8_t k) {
  switch (k) {
    case semgraph_wire_ELEMENT_BODY: return "body";
    case semgraph_wire_ELEMENT_FRAME: return "frame";
    case semgraph_wire_ELEMENT_POSE: return "pose";
    case semgraph_wire_ELEMENT_TWIST: return "twist";
  }
  return "?";
}

// Checks one structure sample and copies it out; the reason when it is malformed.
std::string ParseStructure(const semgraph_wire_Structure& s, OwnerRec* out) {
  out->owner = Str(s.owner);
  if (!GoodName(out->owner)) return "the owner name is not a valid name";
  if (s.elements._length > kMaxElements) return "more than 1048576 elements";
  if (s.elements._length > 0 && s.elements._buffer == nullptr) return "elements missing";
  out->source = s.source;
  out->started_ns = s.started_ns;
  out->revision = s.revision;
  out->rows.clear();
  out->rows.reserve(s.elements._length);
  std::map<std::pair<std::uint8_t, std::string>, int> heads;
  std::map<std::pair<std::uint8_t, std::uint32_t>, int> ids;
  for (std::uint32_t i = 0; i < s.elements._length; ++i) {
    const semgraph_wire_Element& e = s.elements._buffer[i];
    Row r;
    r.kind = e.kind;
    r.edge = e.edge;
    r.seq = e.seq;
    r.head = Str(e.head);
    r.head_body = Str(e.head_body);
    r.tail = Str(e.tail);
    r.tail_body = Str(e.tail_body);
    std::copy(e.numbers, e.numbers + 7, r.n);
    r.stamped = e.stamped;
    r.time_ns = e.time_ns;
    const std::string at = "element " + std::to_string(i) + " (" + KindName(e.kind) + " '" + r.head + "'): ";
    if (e.kind > semgraph_wire_ELEMENT_TWIST) return "element " + std::to_string(i) + ": unknown kind " + std::to_string(e.kind);
    if (!GoodName(r.head)) return at + "invalid name";
    if (e.kind != semgraph_wire_ELEMENT_BODY && !GoodName(r.head_body)) return at + "invalid body name";
    if (e.kind >= semgraph_wire_ELEMENT_POSE) {
      if (!GoodName(r.tail)) return at + "invalid reference name";
      if (e.kind == semgraph_wire_ELEMENT_POSE && !GoodName(r.tail_body)) return at + "invalid reference body name";
      if (!Finite(r.n, 7)) return at + "a number is not finite (invalid_number)";
      if (e.kind == semgraph_wire_ELEMENT_POSE && !UnitQuaternion(r.n)) return at + "not a unit quaternion (invalid_rotation)";
      if (!heads.emplace(std::pair{e.kind, r.head}, 0).second) return at + "a second edge into the same frame";
      if (!ids.emplace(std::pair{e.kind, e.edge}, 0).second) return at + "a second edge with the same id";
      if (r.stamped && !GoodStamp(r.time_ns)) return at + "the stamp is out of range (invalid_number)";
      if (r.stamped && e.kind == semgraph_wire_ELEMENT_POSE && r.head_body == r.tail_body) {
        return at + "a constant (same-body) edge cannot be stamped";
      }
      out->any_stamped = out->any_stamped || r.stamped;
    } else if (e.stamped) {
      return at + "only edges can be stamped";
    }
    out->rows.push_back(std::move(r));
  }
  if (s.joints._length > kMaxElements) return "more than 1048576 joints";
  if (s.joints._length > 0 && s.joints._buffer == nullptr) return "joints missing";
  out->joints.clear();
  out->joints.reserve(s.joints._length);
  std::map<std::string, int> joint_names;
  std::map<std::uint32_t, int> joint_ids;
  for (std::uint32_t i = 0; i < s.joints._length; ++i) {
    const semgraph_wire_Joint& w = s.joints._buffer[i];
    JointRow j;
    j.id = w.id;
    j.seq = w.seq;
    j.name = Str(w.name);
    j.parent = Str(w.parent);
    j.parent_body = Str(w.parent_body);
    j.child = Str(w.child);
    j.child_body = Str(w.child_body);
    j.mimic = Str(w.mimic);
    std::copy(w.origin, w.origin + 7, j.origin);
    std::copy(w.axis, w.axis + 3, j.axis);
    j.lower = w.lower;
    j.upper = w.upper;
    j.multiplier = w.multiplier;
    j.offset = w.offset;
    j.state = w.state;
    j.q = w.q;
    j.qdot = w.qdot;
    j.time_ns = w.time_ns;
    const std::string at = "joint " + std::to_string(i) + " ('" + j.name + "'): ";
    if (w.type > semgraph_wire_JOINT_FIXED) return at + "unknown joint type " + std::to_string(w.type);
    j.type = static_cast<core::JointType>(w.type);
    if (!GoodName(j.name) || !GoodName(j.parent) || !GoodName(j.parent_body) || !GoodName(j.child) ||
        !GoodName(j.child_body) || (!j.mimic.empty() && !GoodName(j.mimic))) {
      return at + "invalid name";
    }
    const double numbers[] = {j.lower, j.upper, j.multiplier, j.offset, j.q, j.qdot};
    if (!Finite(j.origin, 7) || !Finite(j.axis, 3) || !Finite(numbers, 6)) {
      return at + "a number is not finite (invalid_number)";
    }
    if (!UnitQuaternion(j.origin)) return at + "not a unit quaternion (invalid_rotation)";
    if (w.state > semgraph_wire_JOINT_STATE_STAMPED) return at + "unknown state " + std::to_string(w.state);
    if (j.stamped() && !GoodStamp(j.time_ns)) return at + "the stamp is out of range (invalid_number)";
    if (!joint_names.emplace(j.name, 0).second) return at + "a second joint of that name";
    if (!joint_ids.emplace(j.id, 0).second) return at + "a second joint with the same id";
    // The joint owns the edges into its child: the owner must not publish them as well.
    if (!heads.emplace(std::pair{std::uint8_t{semgraph_wire_ELEMENT_POSE}, j.child}, 0).second ||
        !heads.emplace(std::pair{std::uint8_t{semgraph_wire_ELEMENT_TWIST}, j.child}, 0).second) {
      return at + "a second edge into the same frame";
    }
    out->any_stamped = out->any_stamped || j.stamped();
    out->joints.push_back(std::move(j));
  }
  // Time options: sample_capacity 0 = not given.
  if (s.sample_capacity != 0) {
    if (s.window_ns <= 0) return "time options: the window is not positive (invalid_number)";
    if (s.sample_capacity < 2 || s.sample_capacity > kMaxSampleCapacity) {
      return "time options: sample capacity " + std::to_string(s.sample_capacity) + " is outside [2, 1048576]";
    }
    if (s.interpolation > 1 || s.duplicate_stamp > 1) return "time options: unknown interpolation or duplicate policy";
    out->has_time = true;
    out->time.window = core::Duration::Nanoseconds(s.window_ns);
    out->time.interpolation = static_cast<core::Interpolation>(s.interpolation);
    out->time.duplicate_stamp = static_cast<core::DuplicatePolicy>(s.duplicate_stamp);
    out->time.sample_capacity = s.sample_capacity;
  }
  return {};
}

bool SameTime(const core::TimeOptions& a, const core::TimeOptions& b) {
  return a.window == b.window && a.interpolation == b.interpolation && a.duplicate_stamp == b.duplicate_stamp &&
         a.sample_capacity == b.sample_capacity;
}

}  // namespace

struct Mirror::Impl {
  MirrorOptions options;
  core::SceneGraph<> graph;
  Entity participant, structure_reader, value_reader, sample_reader, batch_reader, status_writer, waitset, guard;
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
  void Reconcile();
  // Applies a value (time: a stamped sample's stamp); true when the graph took it. `from` (the
  // message on the wire) names its edge and source when the setter refuses its numbers.
  bool ApplyValue(Slot& slot, std::uint64_t seq, std::int64_t stamp, const double* n, const std::string& what,
                  std::optional<std::int64_t> time = std::nullopt, const In* from = nullptr);
};

Mirror::Mirror(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Mirror::~Mirror() {
  // No listener runs after this (dds_set_listener waits for the callbacks in progress).
  for (const Entity* r : {&impl_->value_reader, &impl_->sample_reader, &impl_->batch_reader}) {
    if (r->ok()) (void)dds_set_listener(r->get(), nullptr);
  }
  impl_->stop.store(true);
  if (impl_->guard.ok()) dds_set_guardcondition(impl_->guard.get(), true);
  if (impl_->thread.joinable()) impl_->thread.join();
}

base::Expected<std::unique_ptr<Mirror>, std::string> Mirror::Create(MirrorOptions options) {
  auto impl = std::make_unique<Impl>();
  impl->options = std::move(options);
  Impl& m = *impl;
  m.participant = Entity(dds_create_participant(m.options.domain, nullptr, nullptr));
  if (!m.participant.ok()) return base::Unexpected{internal::DdsError("cannot join the DDS domain", m.participant.get())};
  const dds_entity_t p = m.participant.get();
  const dds_entity_t st = internal::CreateTopic(p, TopicKind::kStructure);
  const dds_entity_t vt = internal::CreateTopic(p, TopicKind::kValue);
  const dds_entity_t tt = internal::CreateTopic(p, TopicKind::kStatus);
  const dds_entity_t at = internal::CreateTopic(p, TopicKind::kSample);
  const dds_entity_t bt = internal::CreateTopic(p, TopicKind::kBatch);
  if (st < 0 || vt < 0 || tt < 0 || at < 0 || bt < 0) {
    return base::Unexpected{std::string("cannot create the DDS topics")};
  }
  m.structure_reader = Entity(internal::CreateReader(p, st, TopicKind::kStructure));
  m.value_reader = Entity(internal::CreateReader(p, vt, TopicKind::kValue));
  m.sample_reader = Entity(internal::CreateReader(p, at, TopicKind::kSample));
  m.batch_reader = Entity(internal::CreateReader(p, bt, TopicKind::kBatch));
  m.status_writer = Entity(internal::CreateWriter(p, tt, TopicKind::kStatus));
  m.waitset = Entity(dds_create_waitset(p));
  m.guard = Entity(dds_create_guardcondition(p));
  if (!m.structure_reader.ok() || !m.value_reader.ok() || !m.sample_reader.ok() || !m.batch_reader.ok() ||
      !m.status_writer.ok() ||
      !m.waitset.ok() ||
      !m.guard.ok()) {
    return base::Unexpected{std::string("cannot create the DDS readers and writers")};
  }
  const dds_entity_t c1 = dds_create_readcondition(m.structure_reader.get(), DDS_ANY_STATE);
  const dds_entity_t c2 = dds_create_readcondition(m.value_reader.get(), DDS_ANY_STATE);
  const dds_entity_t c3 = dds_create_readcondition(m.sample_reader.get(), DDS_ANY_STATE);
  const dds_entity_t c4 = dds_create_readcondition(m.batch_reader.get(), DDS_ANY_STATE);
  if (dds_waitset_attach(m.waitset.get(), c1, 1) < 0 || dds_waitset_attach(m.waitset.get(), c2, 2) < 0 ||
      dds_waitset_attach(m.waitset.get(), c3, 3) < 0 || dds_waitset_attach(m.waitset.get(), c4, 4) < 0 ||
      dds_waitset_attach(m.waitset.get(), m.guard.get(), 0) < 0) {
    return base::Unexpected{std::string("cannot attach the DDS conditions")};
  }
  // Values are taken where they arrive: a data-available listener runs on Cyclone's receive
  // thread (one thread hand-off less than waking the mirror's thread); the mirror's thread
  // still takes whatever is left (e.g. samples that arrived before the listener was set).
  {
    dds_listener_t* listener = dds_create_listener(&m);
    dds_lset_data_available(listener, [](dds_entity_t reader, void* arg) {
      Impl& self = *static_cast<Impl*>(arg);
      if (reader == self.batch_reader.get()) {
        self.TakeBatches();
      } else {
        self.TakeValues(reader, reader == self.sample_reader.get());
      }
    });
    for (const Entity* r : {&m.value_reader, &m.sample_reader, &m.batch_reader}) {
      if (dds_set_listener(r->get(), listener) < 0) {
        dds_delete_listener(listener);
        return base::Unexpected{std::string("cannot set the DDS reader listeners")};
      }
    }
    dds_delete_listener(listener);
  }
  m.thread = std::thread([&m] { m.Loop(); });
  return std::unique_ptr<Mirror>(new Mirror(std::move(impl)));
}

void Mirror::Impl::Loop() {
  while (!stop.load()) {
    (void)dds_waitset_wait(waitset.get(), nullptr, 0, DDS_MSECS(100));
    if (stop.load()) break;
    TakeStructure();
    TakeValues(value_reader.get(), false);
    TakeValues(sample_reader.get(), true);
    TakeBatches();
  }
}

void Mirror::Impl::TakeStructure() {
  bool changed = false;
  std::lock_guard<std::mutex> lock(state_mutex);
  for (;;) {
    void* samples[16] = {nullptr};
    dds_sample_info_t infos[16];
    const dds_return_t n = dds_take(structure_reader.get(), samples, infos, 16, 16);
    if (n <= 0) break;
    for (int i = 0; i < n; ++i) {
      const dds_sample_info_t& info = infos[i];
      if (info.valid_data) {
        OwnerRec rec;
        const std::string why = ParseStructure(*static_cast<const semgraph_wire_Structure*>(samples[i]), &rec);
        if (!why.empty()) {
          Reject(rec.owner, "structure from owner '" + rec.owner + "': " + why);
          continue;
        }
        rec.alive = true;
        owner_of_instance[info.instance_handle] = rec.owner;
        auto it = owners.find(rec.owner);
        if (it != owners.end() && it->second.source == rec.source && it->second.revision >= rec.revision) {
          continue;  // a repeat or an older revision of this incarnation
        }
        const bool was_dead = it != owners.end() && !it->second.alive;
        const std::string name = rec.owner;
        owners[name] = std::move(rec);
        if (was_dead) Emit({"alive", name, "", "publisher '" + name + "' is alive again"});
        changed = true;
      } else if (info.instance_state == DDS_IST_NOT_ALIVE_NO_WRITERS ||
                 info.instance_state == DDS_IST_NOT_ALIVE_DISPOSED) {
        auto name = owner_of_instance.find(info.instance_handle);
        if (name == owner_of_instance.end()) continue;
        auto it = owners.find(name->second);
        if (it == owners.end() || !it->second.alive) continue;
        it->second.alive = false;
        Emit({"liveliness_lost", it->first, "",
              "publisher '" + it->first + "' is gone; its edges keep their last values"});
      }
    }
    dds_return_loan(structure_reader.get(), samples, n);
    if (n < 16) break;
  }
  if (changed) {
    std::lock_guard<std::mutex> topo(topology_mutex);
    if (options.topology_hook) {
      options.topology_hook([this] { Reconcile(); });
    } else {
      Reconcile();
    }
    generation.fetch_add(1, std::memory_order_release);
    Changed();
  }
}

bool Mirror::Impl::ApplyValue(Slot& slot, std::uint64_t seq, std::int64_t stamp, const double* n,
                              const std::string& what, std::optional<std::int64_t> time,
                              const In* from) {
  if (time.has_value() != slot.stamped) {
    Reject(slot.owner, what + (time ? ": a stamped sample for the unstamped " : ": an unstamped value for the stamped ") +
                           (slot.joint ? "joint '" : "edge into '") + slot.head + "'");
    return false;
  }
  base::ErrorCode code;
  core::UpdateError bad;  // the setter's verdict on the numbers: which, and which limit
  const Eigen::Vector3d a(n[0], n[1], n[2]), b(n[3], n[4], n[5]);
  const Eigen::Quaterniond q(n[0], n[1], n[2], n[3]);
  const Eigen::Vector3d p(n[4], n[5], n[6]);
  if (slot.joint) {
    if (!slot.settable) {
      Reject(slot.owner, what + ": a state for the fixed or mimic joint '" + slot.head + "'");
      return false;
    }
    const double q[1] = {n[0]}, qdot[1] = {n[1]};
    code = time ? graph.SetJointState(slot.group, q, qdot, core::Stamp::Nanoseconds(*time), &bad)
                : graph.SetJointState(slot.group, q, qdot, &bad);
  } else if (slot.twist) {
    code = time ? graph.SetTwist(slot.twist_handle, a, b, core::Stamp::Nanoseconds(*time), &bad)
                : graph.SetTwist(slot.twist_handle, a, b, &bad);
  } else if (slot.settable) {
    code = time ? graph.SetPose(slot.pose, q, p, core::Stamp::Nanoseconds(*time), &bad)
                : graph.SetPose(slot.pose, q, p, &bad);
  } else {
    Reject(slot.owner, what + ": a value for the constant edge into '" + slot.head + "'");
    return false;
  }
  if (code == base::ErrorCode::kStampTooOld || code == base::ErrorCode::kDuplicateStamp) {
    // The history's rules decide reordered and repeated samples (docs/time.md): not malformed.
    dropped.fetch_add(1, std::memory_order_relaxed);
    slot.seq = std::max(slot.seq, seq);
    return false;
  }
  if (code != base::ErrorCode::kOk) {
    const bool numbers = code == base::ErrorCode::kInvalidNumber ||
                         code == base::ErrorCode::kInvalidRotation ||
                         code == base::ErrorCode::kJointLimit;
    Reject(slot.owner, what + " into '" + slot.head + "': " + std::string(base::ToString(code)) +
                           (numbers ? ": " + core::Describe(bad) : std::string()) +
                           (from ? " (" + what + " of edge " + std::to_string(from->edge) + " from source " +
                                       std::to_string(from->source) + ")"
                                 : std::string()));
    return false;
  }
  // A stamped sample may be older than one applied before (the history sorts them).
  slot.seq = std::max(slot.seq, seq);
  ++slot.received;
  slot.stamp_ns = stamp;
  slot.receive_ns = internal::NowNs();
  if (time) slot.time_ns = std::max(slot.time_ns, *time);
  return true;
}

// One value from the value or sample topic, or from a batch; true when applied.
bool Mirror::Impl::HandleValue(const In& v, bool samples) {
  // The numbers are checked by the graph's setter when applied (ApplyValue: its UpdateError).
  const char* why = v.kind > semgraph_wire_VALUE_JOINT      ? ": unknown kind"
                    : samples && !GoodStamp(v.time_ns)      ? ": the stamp is out of range (invalid_number)"
                                                            : nullptr;
  if (why != nullptr) {
    Reject("", std::string(samples ? "sample" : "value") + " of edge " + std::to_string(v.edge) + " from source " +
                   std::to_string(v.source) + why);
    return false;
  }
  const ValueKey key{v.source, v.edge, v.kind};
  auto it = slots.find(key);
  // A joint never set may become stamped by a structure still on the way: hold its samples.
  const bool hold = it != slots.end() && samples && it->second.joint && it->second.unset && it->second.received == 0;
  if (it == slots.end() || hold) {
    // Its structure may still be on the way: keep the latest value (every sample, up to
    // kMaxPendingSamples) until it comes.
    if (!hold && pending.size() + pending_samples.size() >= kMaxPending && !pending.count(key) &&
        !pending_samples.count(key)) {
      Reject("", "value of unknown edge " + std::to_string(v.edge) + " (too many unknown edges)");
      return false;
    }
    Pending got;
    got.seq = v.seq;
    got.stamp_ns = v.stamp_ns;
    got.time_ns = v.time_ns;
    std::copy(v.numbers, v.numbers + 7, got.n);
    if (samples) {
      std::vector<Pending>& list = pending_samples[key];
      if (list.size() < kMaxPendingSamples) list.push_back(got);
    } else {
      Pending& p = pending[key];
      if (v.seq > p.seq) p = got;
    }
    return false;
  }
  // Unstamped values: a repeat or an older value is dropped by its number. Stamped samples go
  // to the history, whose rules decide.
  if (!samples && v.seq <= it->second.seq) return false;
  return ApplyValue(it->second, v.seq, v.stamp_ns, v.numbers, samples ? "sample" : "value",
                    samples ? std::optional<std::int64_t>(v.time_ns) : std::nullopt, &v);
}

void Mirror::Impl::TakeValues(dds_entity_t reader, bool samples) {
  static thread_local semgraph_wire_Value buffer[kTakeBatch];
  static thread_local void* ptrs[kTakeBatch];
  static thread_local dds_sample_info_t infos[kTakeBatch];
  for (int i = 0; i < kTakeBatch; ++i) ptrs[i] = &buffer[i];
  for (;;) {
    const dds_return_t n = dds_take(reader, ptrs, infos, kTakeBatch, kTakeBatch);
    if (n <= 0) break;
    std::uint64_t applied_now = 0;
    {
      std::lock_guard<std::mutex> lock(state_mutex);
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const semgraph_wire_Value& v = buffer[i];
        const In in{v.source, v.edge, v.kind, v.seq, v.stamp_ns, v.time_ns, v.numbers};
        if (HandleValue(in, samples)) ++applied_now;
      }
    }
    if (applied_now > 0) {
      values.fetch_add(applied_now, std::memory_order_release);
      Changed();
    }
    if (n < kTakeBatch) break;
  }
}

void Mirror::Impl::TakeBatches() {
  for (;;) {
    void* samples[16] = {nullptr};
    dds_sample_info_t infos[16];
    const dds_return_t n = dds_take(batch_reader.get(), samples, infos, 16, 16);
    if (n <= 0) break;
    std::uint64_t applied_now = 0;
    {
      std::lock_guard<std::mutex> lock(state_mutex);
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto& b = *static_cast<const semgraph_wire_Batch*>(samples[i]);
        if (b.updates._length > internal::kMaxBatchUpdates || (b.updates._length > 0 && b.updates._buffer == nullptr)) {
          Reject("", "batch " + std::to_string(b.serial) + " from source " + std::to_string(b.source) + ": " +
                         std::to_string(b.updates._length) + " updates (at most " +
                         std::to_string(internal::kMaxBatchUpdates) + ")");
          continue;
        }
        for (std::uint32_t k = 0; k < b.updates._length; ++k) {
          const semgraph_wire_Update& u = b.updates._buffer[k];
          const In in{b.source, u.edge, u.kind, u.seq, u.stamp_ns, u.time_ns, u.numbers};
          if (HandleValue(in, u.stamped)) ++applied_now;
        }
      }
    }
    dds_return_loan(batch_reader.get(), samples, n);
    if (applied_now > 0) {
      values.fetch_add(applied_now, std::memory_order_release);
      Changed();
    }
    if (n < 16) break;
  }
}

// Adds the edge of a structure row to g (stamped: with its newest sample's stamp).
static core::BuildResult AddEdge(core::SceneGraph<>& g, const Row& r) {
  const Eigen::Vector3d a(r.n[0], r.n[1], r.n[2]), b(r.n[3], r.n[4], r.n[5]);
  const Eigen::Quaterniond q(r.n[0], r.n[1], r.n[2], r.n[3]);
  const Eigen::Vector3d p(r.n[4], r.n[5], r.n[6]);
  if (r.kind == semgraph_wire_ELEMENT_TWIST) {
    const core::TwistSpec spec = core::TwistSpec::Of(r.head, r.head_body).RelativeTo(r.tail).ExpressedIn(r.head);
    return r.stamped ? g.AddTwist(spec, a, b, core::Stamp::Nanoseconds(r.time_ns)) : g.AddTwist(spec, a, b);
  }
  const core::PoseSpec spec = core::PoseSpec::Of(r.head, r.head_body).RelativeTo(r.tail, r.tail_body);
  return r.stamped ? g.AddPose(spec, q, p, core::Stamp::Nanoseconds(r.time_ns)) : g.AddPose(spec, q, p);
}

// The replica from scratch in a scratch graph, then the live graph brought to it (mirror.h).
void Mirror::Impl::Reconcile() {
  std::vector<const OwnerRec*> order;
  for (const auto& [name, rec] : owners) order.push_back(&rec);
  std::sort(order.begin(), order.end(), [](const OwnerRec* a, const OwnerRec* b) {
    return std::tie(a->started_ns, a->owner) < std::tie(b->started_ns, b->owner);
  });

  // Time options: the replica takes the first timed owner's while it is still empty (no frame:
  // nothing can have been compiled on it); an owner whose stamped edges need other options is
  // reported once per structure revision (its edges are stamped with the replica's options).
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
          "owner '" + o->owner + "' keeps its stamped edges with other time options (window, interpolation, "
          "duplicate policy, capacity) than this mirror's replica; queries at a time may differ"});
  }
  auto scratch_made = core::SceneGraph<>::Create(graph.time_options());
  core::SceneGraph<> scratch = std::move(*scratch_made);
  std::vector<Applied> desired;
  struct DesiredJoint {
    std::string owner;
    std::uint64_t source;
    const JointRow* row;
  };
  std::vector<DesiredJoint> desired_joints;
  std::vector<Report> refused;
  std::map<std::pair<bool, std::string>, std::string> edge_owner;
  auto refuse = [&](const OwnerRec& o, const auto&, base::ErrorCode code, const std::string& text) {
    refused.push_back({"refused", o.owner, std::string(base::ToString(code)),
                       "owner '" + o.owner + "': " + text});
  };
  for (const OwnerRec* o : order) {
    for (std::uint8_t kind = 0; kind <= semgraph_wire_ELEMENT_TWIST; ++kind) {
      for (const Row& r : o->rows) {
        if (r.kind != kind) continue;
        if (kind == semgraph_wire_ELEMENT_BODY) {
          if (scratch.FindBody(r.head).is_valid()) continue;
          auto res = scratch.AddBody(r.head);
          if (!res) refuse(*o, r, res.error().code, res.error().message);
        } else if (kind == semgraph_wire_ELEMENT_FRAME) {
          const core::FrameIndex f = scratch.FindFrame(r.head);
          if (f.is_valid() && scratch.body_name(scratch.body_of(f)) == r.head_body) continue;
          if (!scratch.FindBody(r.head_body).is_valid()) (void)scratch.AddBody(r.head_body);
          auto res = scratch.AddFrame(r.head, r.head_body);
          if (!res) refuse(*o, r, res.error().code, res.error().message);
        } else {
          const bool twist = kind == semgraph_wire_ELEMENT_TWIST;
          const std::string what = std::string(twist ? "twist of {" : "pose of {") + r.head + "}|" + r.head_body +
                                   " wrt " + (twist ? r.tail : "{" + r.tail + "}|" + r.tail_body);
          auto prior = edge_owner.find({twist, r.head});
          if (prior != edge_owner.end()) {
            const base::ErrorCode code =
                twist ? base::ErrorCode::kMultipleTwistParents : base::ErrorCode::kMultiplePoseParents;
            refuse(*o, r, code,
                   what + " rejected (" + std::string(base::ToString(code)) + "): {" + r.head + "} already has a " +
                       (twist ? "twist" : "pose") + " parent published by '" + prior->second + "'");
            continue;
          }
          core::BuildResult res = AddEdge(scratch, r);
          if (!res) {
            refuse(*o, r, res.error().code, res.error().message);
            continue;
          }
          edge_owner[{twist, r.head}] = o->owner;
          Applied a;
          a.owner = o->owner;
          a.source = o->source;
          a.row = &r;
          a.twist = twist;
          a.head = r.head;
          a.head_body = r.head_body;
          a.tail = r.tail;
          a.tail_body = twist ? std::string() : r.tail_body;
          std::copy(r.n, r.n + 7, a.n);
          a.edge = r.edge;
          a.seq = r.seq;
          a.stamped = r.stamped;
          desired.push_back(std::move(a));
        }
      }
    }
    // The owner's joints, in its order (masters before their mimics), after its edges.
    for (const JointRow& j : o->joints) {
      const std::string what = "joint " + j.name + " ({" + j.child + "}|" + j.child_body + " wrt {" + j.parent +
                               "}|" + j.parent_body + ")";
      auto prior = edge_owner.find({false, j.child});
      if (prior == edge_owner.end()) prior = edge_owner.find({true, j.child});
      if (prior != edge_owner.end()) {
        const base::ErrorCode code = base::ErrorCode::kMultiplePoseParents;
        refuse(*o, j, code,
               what + " rejected (" + std::string(base::ToString(code)) + "): {" + j.child +
                   "} already has a parent published by '" + prior->second + "'");
        continue;
      }
      core::BuildResult res = scratch.AddJoint(j.Spec());
      if (!res) {
        refuse(*o, j, res.error().code, res.error().message);
        continue;
      }
      edge_owner[{false, j.child}] = o->owner;
      edge_owner[{true, j.child}] = o->owner;
      desired_joints.push_back({o->owner, o->source, &j});
    }
  }

  // Bring the replica to `desired`: removals first (twists, then poses), then the adds in the
  // deterministic order. Every intermediate edge set is a subset of the accepted one, so the
  // adds pass the same checks they passed on the scratch graph.
  std::map<std::pair<bool, std::string>, const Applied*> want;
  for (const Applied& a : desired) want[{a.twist, a.head}] = &a;
  // Joints first (a joint's removal is the removal of its pose edge): those no longer wanted
  // or changed, and with a removed master its mimics; mimics before masters.
  {
    std::map<std::string, const DesiredJoint*> want_joints;
    for (const DesiredJoint& d : desired_joints) want_joints[d.row->name] = &d;
    std::set<std::string> remove;
    for (const auto& [name, aj] : applied_joints) {
      auto w = want_joints.find(name);
      bool keep = w != want_joints.end() && w->second->owner == aj.owner && w->second->row->SameJoint(aj.row);
      if (keep) {
        // Stamped and timeless edges do not convert: such a change re-adds the joint.
        const core::internal::JointRecord* rec = graph.joint_table().Find(name);
        const bool stamped_now = rec != nullptr && graph.pose_history(rec->child) != nullptr;
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
        if (!aj.row.mimic.empty() && remove.count(aj.row.mimic) && remove.insert(name).second) grew = true;
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
  std::unordered_map<ValueKey, Slot, ValueKeyHash> new_slots;
  // Values and samples that arrived before the structure named their edge: applied now.
  const auto apply_pending = [&](const ValueKey& key, Slot& slot) {
    auto p = pending.find(key);
    if (p != pending.end()) {
      if (p->second.seq > slot.seq) ApplyValue(slot, p->second.seq, p->second.stamp_ns, p->second.n, "value");
      pending.erase(p);
    }
    auto ps = pending_samples.find(key);
    if (ps != pending_samples.end()) {
      for (const Pending& e : ps->second) ApplyValue(slot, e.seq, e.stamp_ns, e.n, "sample", e.time_ns);
      pending_samples.erase(ps);
    }
  };
  for (const Applied& a : desired) {
    const Row& r = *a.row;
    auto have = applied.find({a.twist, a.head});
    bool added = false;
    if (have == applied.end()) {
      const core::BuildResult res = AddEdge(graph, r);
      if (!res) {
        // Only a name clash with a frame the replica kept from an earlier structure can do this.
        refused.push_back({"refused", a.owner, std::string(base::ToString(res.error().code)),
                           "owner '" + a.owner + "': " + res.error().message});
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
    Slot slot;
    auto old = slots.find(key);
    const bool known = old != slots.end() && !added;
    if (known) slot = std::move(old->second);
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
    const std::optional<std::int64_t> time = a.stamped ? std::optional<std::int64_t>(r.time_ns) : std::nullopt;
    if (added) {
      slot.seq = r.seq;
      if (time) slot.time_ns = *time;
    } else if (!known || r.seq > slot.seq) {
      // A kept edge under a new incarnation, or a newer value announced by the structure.
      if (slot.settable) ApplyValue(slot, r.seq, 0, r.n, "structure value", time);
      slot.seq = r.seq;
    }
    apply_pending(key, slot);
    new_slots.emplace(key, std::move(slot));
  }
  // Joints: all adds, then the states of the new ones (mimics follow their masters).
  std::vector<std::pair<const JointRow*, bool>> joint_slots;  // row, added
  for (const DesiredJoint& d : desired_joints) {
    const JointRow& j = *d.row;
    auto have = applied_joints.find(j.name);
    bool added = false;
    if (have == applied_joints.end()) {
      const core::BuildResult res = graph.AddJoint(j.Spec());
      if (!res) {
        refused.push_back({"refused", d.owner, std::string(base::ToString(res.error().code)),
                           "owner '" + d.owner + "': " + res.error().message});
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
  for (std::size_t i = 0; i < joint_slots.size(); ++i) {
    const JointRow& j = *joint_slots[i].first;
    const bool added = joint_slots[i].second;
    const AppliedJoint& aj = applied_joints.at(j.name);
    const ValueKey key{aj.source, j.id, semgraph_wire_VALUE_JOINT};
    Slot slot;
    auto old = slots.find(key);
    const bool known = old != slots.end() && !added;
    if (known) slot = std::move(old->second);
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
    const core::internal::JointRecord* rec = graph.joint_table().Find(j.name);
    const bool replica_stamped = rec != nullptr && graph.pose_history(rec->child) != nullptr;
    if (slot.settable && j.state != semgraph_wire_JOINT_STATE_NONE &&
        (added || (j.stamped() && !replica_stamped))) {
      // The joint's first state decides its kind (timeless or stamped: histories allocated here).
      const core::JointValue q[] = {{j.name, j.q}}, qdot[] = {{j.name, j.qdot}};
      const core::BuildResult res = j.stamped() ? graph.SetJoints(q, qdot, core::Stamp::Nanoseconds(j.time_ns))
                                                : graph.SetJoints(q, qdot);
      if (!res) Log("joint " + j.name + ": its state is refused: " + res.error().message);
      slot.seq = j.seq;
      if (j.stamped()) slot.time_ns = j.time_ns;
    } else if (added) {
      slot.seq = j.seq;
    } else if (slot.settable && (!known || j.seq > slot.seq)) {
      const double n[7] = {j.q, j.qdot, 0, 0, 0, 0, 0};
      ApplyValue(slot, j.seq, 0, n, "structure value",
                 j.stamped() ? std::optional<std::int64_t>(j.time_ns) : std::nullopt);
      slot.seq = j.seq;
    }
    apply_pending(key, slot);
    new_slots.emplace(key, std::move(slot));
  }
  slots = std::move(new_slots);

  // Report each refusal once, in the deterministic order.
  for (const Report& r : refused) {
    const bool known = std::any_of(refusals.begin(), refusals.end(), [&](const Report& o) {
      return o.owner == r.owner && o.code == r.code && o.message == r.message;
    });
    if (!known) Emit(r);
  }
  refusals = std::move(refused);
}

const core::SceneGraph<>& Mirror::graph() const noexcept { return impl_->graph; }

void Mirror::WithGraph(const std::function<void(const core::SceneGraph<>&)>& fn) const {
  std::lock_guard<std::mutex> topo(impl_->topology_mutex);
  fn(impl_->graph);
}

std::uint64_t Mirror::structure_generation() const noexcept { return impl_->generation.load(std::memory_order_acquire); }
std::uint64_t Mirror::values_applied() const noexcept { return impl_->values.load(std::memory_order_acquire); }
std::uint64_t Mirror::messages_rejected() const noexcept { return impl_->rejected.load(std::memory_order_acquire); }
std::uint64_t Mirror::samples_dropped() const noexcept { return impl_->dropped.load(std::memory_order_acquire); }

std::vector<OwnerState> Mirror::Owners() const {
  std::lock_guard<std::mutex> lock(impl_->state_mutex);
  std::vector<OwnerState> out;
  for (const auto& [name, o] : impl_->owners) {
    out.push_back({name, o.source, o.started_ns, o.revision, o.alive, o.rows.size()});
  }
  return out;
}

std::vector<EdgeState> Mirror::Edges() const {
  std::lock_guard<std::mutex> lock(impl_->state_mutex);
  std::vector<EdgeState> out;
  for (const auto& [key, s] : impl_->slots) {
    out.push_back({s.owner, s.twist, s.head, s.tail, s.seq, s.received, s.stamp_ns, s.receive_ns, s.stamped, s.time_ns,
                   s.joint});
  }
  std::sort(out.begin(), out.end(), [](const EdgeState& a, const EdgeState& b) {
    return std::tie(a.joint, a.twist, a.head) < std::tie(b.joint, b.twist, b.head);
  });
  return out;
}

std::vector<Report> Mirror::Reports() const {
  std::lock_guard<std::mutex> lock(impl_->state_mutex);
  return impl_->reports;
}

std::vector<Report> Mirror::Refusals() const {
  std::lock_guard<std::mutex> lock(impl_->state_mutex);
  return impl_->refusals;
}

bool Mirror::CaughtUp() const {
  std::lock_guard<std::mutex> lock(impl_->state_mutex);
  if (impl_->owners.empty()) return false;
  for (const auto& [name, o] : impl_->owners) {
    for (const Row& r : o.rows) {
      if (r.kind < semgraph_wire_ELEMENT_POSE) continue;
      const std::uint8_t vkind = r.kind == semgraph_wire_ELEMENT_TWIST ? semgraph_wire_VALUE_TWIST : semgraph_wire_VALUE_POSE;
      auto it = impl_->slots.find({o.source, r.edge, vkind});
      if (it == impl_->slots.end()) {
        // Refused edges have no slot; any other missing edge means not caught up.
        const auto& owner = name;  // clang 14 cannot capture a structured binding
        const bool refused = std::any_of(impl_->refusals.begin(), impl_->refusals.end(),
                                         [&](const Report& rep) { return rep.owner == owner; });
        if (!refused) return false;
        continue;
      }
      if (it->second.seq < r.seq) return false;
    }
    for (const JointRow& j : o.joints) {
      auto it = impl_->slots.find({o.source, j.id, semgraph_wire_VALUE_JOINT});
      if (it == impl_->slots.end()) {
        const auto& owner = name;
        if (!std::any_of(impl_->refusals.begin(), impl_->refusals.end(),
                         [&](const Report& rep) { return rep.owner == owner; })) {
          return false;
        }
        continue;
      }
      if (it->second.seq < j.seq) return false;
    }
  }
  return true;
}

bool Mirror::WaitUntil(const std::function<bool()>& pred, std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!pred()) {
    if (std::chrono::steady_clock::now() >= deadline) return pred();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

}  // namespace semgraph::dds
