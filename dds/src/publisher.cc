// Publisher (publisher.h): the graph's structure as one sample per owner, values per edge.
#include "semgraph/dds/publisher.h"

#include <atomic>
#include <map>
#include <optional>
#include <random>
#include <vector>

#include "semgraph/coord/validate.h"
#include "semgraph/core/timed_read.h"
#include "wire.h"

namespace semgraph::dds {

using internal::Entity;
using internal::TopicKind;

struct Publisher::Impl {
  core::SceneGraph<>* graph = nullptr;
  std::string owner;
  std::uint64_t source = 0;
  std::int64_t started_ns = 0;
  std::uint64_t revision = 0;
  std::uint64_t write_failures = 0;
  // Per frame (the edge id of the pose or twist edge into it): values published so far.
  std::vector<std::uint64_t> pose_seq, twist_seq;
  std::vector<std::uint64_t> joint_seq;   // per joint index: states published so far
  std::vector<std::uint64_t> wrench_seq;  // per wrench slot (wrenches.h): values published so far

  // The next value of edge or joint `id` (of `kind`): numbered by its counter in `seqs` (0 for
  // an id the last structure did not count), on the publisher's clock; numbers still to fill.
  semgraph_wire_Value NewValue(std::uint8_t kind, std::uint32_t id,
                               std::vector<std::uint64_t>& seqs) noexcept {
    semgraph_wire_Value v{};
    v.source = source;
    v.edge = id;
    v.kind = kind;
    v.seq = id < seqs.size() ? ++seqs[id] : 0;
    v.stamp_ns = internal::NowNs();
    return v;
  }
  // Publishes joint `index`'s state (q, qdot), stamped or not, with the joint's qddot when it
  // has one (a stamped sample's: the qddot the graph kept for the joint, which its samples take
  // when a call gives none).
  // `qddot` (non-null): the sample's own qddot, given with it.
  void PublishJoint(std::uint32_t index, double q, double qdot, std::optional<core::Stamp> stamp,
                    const double* qddot = nullptr) noexcept {
    semgraph_wire_Value v = NewValue(semgraph_wire_VALUE_JOINT, index, joint_seq);
    v.numbers[0] = q;
    v.numbers[1] = qdot;
    if (stamp) v.time_ns = stamp->nanoseconds();
    if (qddot != nullptr) {
      v.has_acceleration = true;
      v.acceleration[0] = *qddot;
    } else if (const core::internal::JointRecord& j = graph->joint_table().joints[index];
               j.has_qddot) {
      v.has_acceleration = true;
      v.acceleration[0] = j.qddot;
    }
    Send(v, stamp.has_value());
  }
  // After a group's state was set: q (and qdot, qddot when given) from the input, the other
  // fields the joint's current ones (a positions-only call does not change the newest velocity).
  void PublishGroup(const core::JointGroup& group, const double* q, const double* qdot,
                    std::optional<core::Stamp> stamp, const double* qddot = nullptr) noexcept {
    for (std::size_t i = 0; i < group.size(); ++i) {
      const core::JointHandle h = group.joints[i];
      PublishJoint(h.index.value(), q != nullptr ? q[i] : graph->joint_position(h),
                   qdot != nullptr ? qdot[i] : graph->joint_velocity(h), stamp,
                   qddot != nullptr ? qddot + i : nullptr);
    }
  }
  // After an unstamped set of a group: each joint's state as the graph holds it (q, qdot, qddot).
  void PublishGroupState(const core::JointGroup& group) noexcept {
    const core::internal::JointTable& t = graph->joint_table();
    for (std::size_t i = 0; i < group.size(); ++i) {
      const std::uint32_t index = group.joints[i].index.value();
      PublishJoint(index, t.joints[index].q, t.joints[index].qdot, std::nullopt);
    }
  }
  // Batching (BeginBatch / Flush): the cycle's values, preallocated (kMaxBatchUpdates).
  bool batching = false;
  std::vector<semgraph_wire_Update> batch;
  std::uint64_t batch_serial = 0;
  // Set by Cyclone's thread when a reader matched the batch writer: the next Flush republishes
  // the structure (with every edge's latest value) for it, as the batches name only changes.
  std::atomic<bool> matched{false};

  // The latest value of a timeless edge as the graph stores it, with its covariance (zero after
  // a value without one: exact), on the value topic or into the batch.
  void PublishPose(core::FrameIndex child) noexcept;
  void PublishTwist(core::TwistHandle edge) noexcept;
  // The value of the wrench in `slot` (wrenches.h) as the store holds it.
  void PublishWrench(std::uint32_t slot) noexcept;
  // The sample of a stamped edge at `stamp` as its history stores it, with its covariance (zero:
  // exact), on the sample topic or into the batch.
  void PublishPoseSample(core::FrameIndex child, core::Stamp stamp) noexcept;
  void PublishTwistSample(core::TwistHandle edge, core::Stamp stamp) noexcept;
  // The sample of the stamped wrench in `slot` at `stamp` as its history stores it.
  void PublishWrenchSample(std::uint32_t slot, core::Stamp stamp) noexcept;
  // Sends one value: into the batch while batching, else on the value or sample topic.
  void Send(const semgraph_wire_Value& v, bool stamped) noexcept {
    if (!batching) {
      if (dds_write(stamped ? sample_writer.get() : value_writer.get(), &v) != DDS_RETCODE_OK)
        ++write_failures;
      return;
    }
    if (batch.size() == internal::kMaxBatchUpdates) WriteBatch();
    semgraph_wire_Update u{};
    u.edge = v.edge;
    u.kind = v.kind;
    u.stamped = stamped;
    u.seq = v.seq;
    u.stamp_ns = v.stamp_ns;
    u.time_ns = v.time_ns;
    std::copy(v.numbers, v.numbers + 7, u.numbers);
    std::copy(v.covariance, v.covariance + internal::kPackedCovariance, u.covariance);
    u.has_acceleration = v.has_acceleration;
    std::copy(v.acceleration, v.acceleration + 6, u.acceleration);
    batch.push_back(u);  // within the reserved capacity: no allocation
  }
  void WriteBatch() noexcept {
    if (batch.empty()) return;
    semgraph_wire_Batch b{};
    b.source = source;
    b.serial = ++batch_serial;
    b.updates._length = b.updates._maximum = static_cast<std::uint32_t>(batch.size());
    b.updates._buffer = batch.data();
    b.updates._release = false;
    if (dds_write(batch_writer.get(), &b) != DDS_RETCODE_OK) write_failures += batch.size();
    batch.clear();
  }

  // Declared last, destroyed first: the writers (and their listener) go before what they use.
  Entity participant, structure_writer, value_writer, sample_writer, batch_writer;
};

std::int64_t NowNs() noexcept { return internal::NowNs(); }

Publisher::Publisher(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Publisher::~Publisher() {
  if (impl_ && impl_->batching) impl_->WriteBatch();
}

void Publisher::BeginBatch() noexcept { impl_->batching = true; }

void Publisher::Flush() {
  Impl& m = *impl_;
  m.WriteBatch();
  m.batching = false;
  if (m.matched.exchange(false, std::memory_order_acq_rel) && m.revision > 0) {
    if (!PublishStructure()) ++m.write_failures;
  }
}

base::Expected<std::unique_ptr<Publisher>, std::string> Publisher::Create(
    core::SceneGraph<>& graph, PublisherOptions options) {
  if (!semantics::ValidateName(options.owner)) {
    return base::Unexpected{std::string("publisher owner '") + options.owner +
                            "' is not a valid name"};
  }
  auto impl = std::make_unique<Impl>();
  impl->graph = &graph;
  impl->owner = std::move(options.owner);
  std::random_device rd;
  impl->source = (static_cast<std::uint64_t>(rd()) << 32) ^ rd() ^
                 static_cast<std::uint64_t>(internal::NowNs());
  impl->started_ns = internal::NowNs();
  impl->participant = Entity(dds_create_participant(options.domain, nullptr, nullptr));
  if (!impl->participant.ok()) {
    return base::Unexpected{
        internal::DdsError("cannot join the DDS domain", impl->participant.get())};
  }
  const dds_entity_t p = impl->participant.get();
  const dds_entity_t st = internal::CreateTopic(p, TopicKind::kStructure);
  const dds_entity_t vt = internal::CreateTopic(p, TopicKind::kValue);
  const dds_entity_t at = internal::CreateTopic(p, TopicKind::kSample);
  const dds_entity_t bt = internal::CreateTopic(p, TopicKind::kBatch);
  if (st < 0 || vt < 0 || at < 0 || bt < 0) {
    return base::Unexpected{internal::DdsError("cannot create the topics", st < 0   ? st
                                                                           : vt < 0 ? vt
                                                                           : at < 0 ? at
                                                                                    : bt)};
  }
  impl->structure_writer = Entity(internal::CreateWriter(p, st, TopicKind::kStructure));
  impl->value_writer = Entity(internal::CreateWriter(p, vt, TopicKind::kValue));
  impl->sample_writer = Entity(internal::CreateWriter(p, at, TopicKind::kSample));
  {
    dds_listener_t* listener = dds_create_listener(impl.get());
    dds_lset_publication_matched(
        listener, [](dds_entity_t, const dds_publication_matched_status_t status, void* arg) {
          if (status.current_count_change > 0)
            static_cast<Impl*>(arg)->matched.store(true, std::memory_order_release);
        });
    dds_qos_t* qos = internal::MakeQos(TopicKind::kBatch);
    impl->batch_writer = Entity(dds_create_writer(p, bt, qos, listener));
    dds_delete_qos(qos);
    dds_delete_listener(listener);
  }
  impl->batch.reserve(internal::kMaxBatchUpdates);
  if (!impl->structure_writer.ok() || !impl->value_writer.ok() || !impl->sample_writer.ok() ||
      !impl->batch_writer.ok()) {
    return base::Unexpected{std::string("cannot create the DDS writers")};
  }
  return std::unique_ptr<Publisher>(new Publisher(std::move(impl)));
}

namespace {

void PutPose(double* n, const coord::QuaternionBackend::PoseCoords& X) {
  const Eigen::Quaterniond& q = X.rotation;
  n[0] = q.w();
  n[1] = q.x();
  n[2] = q.y();
  n[3] = q.z();
  n[4] = X.translation.x();
  n[5] = X.translation.y();
  n[6] = X.translation.z();
}

void PutTwist(double* n, const Eigen::Vector3d& v, const Eigen::Vector3d& w) {
  for (int i = 0; i < 3; ++i) {
    n[i] = v[i];
    n[3 + i] = w[i];
  }
  n[6] = 0.0;
}

// The acceleration stored on the twist edge into f (edge form), if any: the wire's flag and
// numbers (semgraph_wire.idl). Timeless edges (a stamped one's: PutSampleAcceleration).
void PutAcceleration(const core::SceneGraph<>& g, core::FrameIndex f, bool* has, double* a) {
  const std::optional<coord::Acceleration> A = g.acceleration_value(f);
  *has = A.has_value();
  if (!A) return;
  for (int i = 0; i < 3; ++i) {
    a[i] = A->linear[i];
    a[3 + i] = A->angular[i];
  }
}

// The acceleration words of a twist history's sample at `stamp` (edge_history.h: a, alpha, the
// present flag), as the wire's flag and numbers: none when the sample carries none.
void PutSampleAcceleration(const core::TwistHistory& h, std::int64_t stamp, bool* has, double* a) {
  double words[core::TwistHistory::kAccelerationWords];
  *has = h.AccelerationAt(stamp, words) && words[6] != 0.0;
  if (*has) std::copy(words, words + 6, a);
}

// A history's stored sample (x y z w p / v w) in wire order.
void PutPoseSample(double* n, const double (&h)[7]) {
  n[0] = h[3];
  n[1] = h[0];
  n[2] = h[1];
  n[3] = h[2];
  n[4] = h[4];
  n[5] = h[5];
  n[6] = h[6];
}

// A history's covariance words (core's layout) in the wire's packed form.
void PutCovarianceWords(double* packed, const double (&words)[21]) {
  coord::Covariance6 S;
  core::internal::CovarianceFromWords(words, S);
  internal::PackCovariance(S, packed);
}

// The covariance of a history's newest sample, packed (zeros when it has none).
template <class History>
void PutNewestCovariance(double* packed, const History& h) {
  double words[21];
  if (h.CovarianceAt(h.newest_stamp(), words)) PutCovarianceWords(packed, words);
}

// The stored wrenches (wrenches.h), one element per live slot: on (head_body), by (tail_body),
// the storage frame (head), the value (f_S, m_So_S); a stamped pair's is its newest sample, with
// its stamp.
void WrenchRows(const core::SceneGraph<>& g, const std::vector<std::uint64_t>& wrench_seq,
                std::vector<internal::Row>& rows) {
  const core::internal::WrenchStore& store = g.wrench_store();
  for (std::uint32_t i = 0; i < store.slots.size(); ++i) {
    const core::internal::WrenchSlot& w = store.slots[i];
    if (!w.live) continue;
    internal::Row r{semgraph_wire_ELEMENT_WRENCH,
                    i,
                    wrench_seq[i],
                    std::string(g.frame_name(w.frame)),
                    std::string(g.body_name(w.on)),
                    {},
                    std::string(g.body_name(w.by))};
    const core::WrenchNumbers W = store.values[i].Load();
    PutTwist(r.n, W.f_S, W.m_So_S);  // (f, m, 0): the same layout
    if (const auto* h = store.history.of(i)) {
      r.stamped = true;
      r.time_ns = h->newest_stamp();
    }
    rows.push_back(std::move(r));
  }
}

// The structure's elements: bodies, frames, then the pose and twist edges a joint does not own,
// each with the number of its last value and its covariance (stamped edges: the newest sample's
// stamp and covariance; timeless twist edges: their acceleration or none), then the wrenches.
std::vector<internal::Row> ElementRows(const core::SceneGraph<>& g,
                                       const std::vector<std::uint64_t>& pose_seq,
                                       const std::vector<std::uint64_t>& twist_seq,
                                       const std::vector<std::uint64_t>& wrench_seq) {
  using internal::Row;
  const core::internal::JointTable& joints = g.joint_table();
  std::vector<Row> rows;
  rows.reserve(g.num_bodies() + 3 * g.num_frames());
  for (std::uint32_t i = 0; i < g.num_bodies(); ++i) {
    rows.push_back({semgraph_wire_ELEMENT_BODY,
                    0,
                    0,
                    std::string(g.body_name(core::BodyIndex(i))),
                    {},
                    {},
                    {}});
  }
  for (std::uint32_t i = 0; i < g.num_frames(); ++i) {
    const core::FrameIndex f(i);
    rows.push_back({semgraph_wire_ELEMENT_FRAME,
                    0,
                    0,
                    std::string(g.frame_name(f)),
                    std::string(g.body_name(g.body_of(f))),
                    {},
                    {}});
  }
  for (std::uint32_t i = 0; i < g.num_frames(); ++i) {
    const core::FrameIndex f(i);
    const core::FrameIndex t = g.pose_parent(f);
    if (!t.is_valid() || joints.OfChild(f) != nullptr)
      continue;  // a joint's edge goes with the joint
    Row r{semgraph_wire_ELEMENT_POSE,
          i,
          pose_seq[i],
          std::string(g.frame_name(f)),
          std::string(g.body_name(g.body_of(f))),
          std::string(g.frame_name(t)),
          std::string(g.body_name(g.body_of(t)))};
    PutPose(r.n, g.pose_value(f));
    if (const core::PoseHistory* h = g.pose_history(f)) {
      r.stamped = true;
      r.time_ns = h->newest_stamp();
      PutNewestCovariance(r.cov, *h);
    } else {
      internal::PackCovariance(g.pose_covariance(f), r.cov);
    }
    rows.push_back(std::move(r));
  }
  for (std::uint32_t i = 0; i < g.num_frames(); ++i) {
    const core::FrameIndex f(i);
    const core::BodyIndex d = g.twist_parent(f);
    if (!d.is_valid() || joints.OfChild(f) != nullptr) continue;
    const auto V = g.twist_value(f);
    Row r{semgraph_wire_ELEMENT_TWIST,
          i,
          twist_seq[i],
          std::string(g.frame_name(f)),
          std::string(g.body_name(g.body_of(f))),
          std::string(g.body_name(d)),
          {}};
    PutTwist(r.n, V->linear, V->angular);
    if (const core::TwistHistory* h = g.twist_history(g.topology().twist_edge_of(f))) {
      r.stamped = true;
      r.time_ns = h->newest_stamp();
      PutNewestCovariance(r.cov, *h);
      PutSampleAcceleration(*h, r.time_ns, &r.has_acc, r.acc);
    } else {
      internal::PackCovariance(g.twist_covariance(f), r.cov);
      PutAcceleration(g, f, &r.has_acc, r.acc);
    }
    rows.push_back(std::move(r));
  }
  WrenchRows(g, wrench_seq, rows);
  return rows;
}

// The wire elements of `rows` (pointing into their names).
std::vector<semgraph_wire_Element> WireElements(std::vector<internal::Row>& rows) {
  std::vector<semgraph_wire_Element> elements(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    semgraph_wire_Element& e = elements[k];
    e.kind = rows[k].kind;
    e.edge = rows[k].edge;
    e.seq = rows[k].seq;
    e.head = rows[k].head.data();
    e.head_body = rows[k].head_body.data();
    e.tail = rows[k].tail.data();
    e.tail_body = rows[k].tail_body.data();
    for (int j = 0; j < 7; ++j) e.numbers[j] = rows[k].n[j];
    e.stamped = rows[k].stamped;
    e.time_ns = rows[k].time_ns;
    std::copy(rows[k].cov, rows[k].cov + internal::kPackedCovariance, e.covariance);
    e.has_acceleration = rows[k].has_acc;
    std::copy(rows[k].acc, rows[k].acc + 6, e.acceleration);
  }
  return elements;
}

// A joint's names, owned: its wire joint points into them.
struct JointNames {
  std::string name, parent, parent_body, child, child_body, mimic;
};

// The structure's joints (the live ones), each with the number of its last state; joint_names
// holds the names they point into (reserved first: no reallocation moves a name).
std::vector<semgraph_wire_Joint> WireJoints(const core::SceneGraph<>& g,
                                            const std::vector<std::uint64_t>& joint_seq,
                                            std::vector<JointNames>& joint_names) {
  const core::internal::JointTable& joints = g.joint_table();
  std::vector<semgraph_wire_Joint> joint_rows;
  joint_names.reserve(joints.joints.size());
  joint_rows.reserve(joints.joints.size());
  for (std::uint32_t i = 0; i < joints.joints.size(); ++i) {
    const core::internal::JointRecord& j = joints.joints[i];
    if (!j.alive) continue;
    joint_names.push_back(
        {std::string(joints.name(j)), std::string(g.frame_name(j.parent)),
         std::string(g.body_name(j.parent_body)), std::string(g.frame_name(j.child)),
         std::string(g.body_name(j.child_body)),
         j.is_mimic() ? std::string(joints.name(joints[j.master])) : std::string()});
    const JointNames& names = joint_names.back();
    semgraph_wire_Joint w{};
    w.id = i;
    w.seq = joint_seq[i];
    w.type = static_cast<std::uint8_t>(j.type);
    w.name = const_cast<char*>(names.name.c_str());
    w.parent = const_cast<char*>(names.parent.c_str());
    w.parent_body = const_cast<char*>(names.parent_body.c_str());
    w.child = const_cast<char*>(names.child.c_str());
    w.child_body = const_cast<char*>(names.child_body.c_str());
    w.mimic = const_cast<char*>(names.mimic.c_str());
    w.origin[0] = j.q_origin.w();
    w.origin[1] = j.q_origin.x();
    w.origin[2] = j.q_origin.y();
    w.origin[3] = j.q_origin.z();
    for (int k = 0; k < 3; ++k) {
      w.origin[4 + k] = j.p_origin[k];
      w.axis[k] = j.axis[k];
    }
    w.lower = j.lower;
    w.upper = j.upper;
    w.multiplier = j.multiplier;
    w.offset = j.offset;
    w.q = j.q;
    w.qdot = j.qdot;
    w.has_qddot = j.has_qddot;
    w.qddot = j.has_qddot ? j.qddot : 0.0;
    if (const core::PoseHistory* h = g.pose_history(j.child)) {
      w.state = semgraph_wire_JOINT_STATE_STAMPED;
      w.time_ns = h->newest_stamp();
    } else {
      w.state = j.timeless ? semgraph_wire_JOINT_STATE_TIMELESS : semgraph_wire_JOINT_STATE_NONE;
    }
    joint_rows.push_back(w);
  }
  return joint_rows;
}

}  // namespace

base::Expected<base::Ok, std::string> Publisher::PublishStructure() {
  Impl& m = *impl_;
  const core::SceneGraph<>& g = *m.graph;
  m.pose_seq.resize(g.num_frames(), 0);
  m.twist_seq.resize(g.num_frames(), 0);
  m.joint_seq.resize(g.joint_table().joints.size(), 0);
  m.wrench_seq.resize(g.wrench_store().slots.size(), 0);
  // Names are copied into strings first: the sample points into them.
  std::vector<internal::Row> rows = ElementRows(g, m.pose_seq, m.twist_seq, m.wrench_seq);
  std::vector<semgraph_wire_Element> elements = WireElements(rows);
  std::vector<JointNames> joint_names;
  std::vector<semgraph_wire_Joint> joint_rows = WireJoints(g, m.joint_seq, joint_names);
  semgraph_wire_Structure s{};
  s.joints._length = s.joints._maximum = static_cast<std::uint32_t>(joint_rows.size());
  s.joints._buffer = joint_rows.data();
  s.joints._release = false;
  s.owner = m.owner.data();
  s.source = m.source;
  s.started_ns = m.started_ns;
  s.revision = ++m.revision;
  s.elements._length = s.elements._maximum = static_cast<std::uint32_t>(elements.size());
  s.elements._buffer = elements.data();
  s.elements._release = false;
  const core::TimeOptions& time = g.time_options();
  s.window_ns = time.window.nanoseconds();
  s.interpolation = static_cast<std::uint8_t>(time.interpolation);
  s.duplicate_stamp = static_cast<std::uint8_t>(time.duplicate_stamp);
  s.sample_capacity = static_cast<std::uint32_t>(time.sample_capacity);
  const dds_return_t rc = dds_write(m.structure_writer.get(), &s);
  if (rc != DDS_RETCODE_OK)
    return base::Unexpected{internal::DdsError("cannot publish the structure", rc)};
  return base::Ok{};
}

void Publisher::Impl::PublishPose(core::FrameIndex child) noexcept {
  semgraph_wire_Value v = NewValue(semgraph_wire_VALUE_POSE, child.value(), pose_seq);
  PutPose(v.numbers, graph->pose_value(child));
  internal::PackCovariance(graph->pose_covariance(child), v.covariance);
  Send(v, false);
}

void Publisher::Impl::PublishTwist(core::TwistHandle edge) noexcept {
  const core::FrameIndex head = graph->topology().twist_edge(edge.slot).head;
  semgraph_wire_Value v = NewValue(semgraph_wire_VALUE_TWIST, head.value(), twist_seq);
  const auto V = graph->twist_value(head);
  PutTwist(v.numbers, V->linear, V->angular);
  internal::PackCovariance(graph->twist_covariance(head), v.covariance);
  PutAcceleration(*graph, head, &v.has_acceleration, v.acceleration);
  Send(v, false);
}

void Publisher::Impl::PublishWrench(std::uint32_t slot) noexcept {
  semgraph_wire_Value v = NewValue(semgraph_wire_VALUE_WRENCH, slot, wrench_seq);
  const core::WrenchNumbers W = graph->wrench_store().values[slot].Load();
  PutTwist(v.numbers, W.f_S, W.m_So_S);
  Send(v, false);
}

base::ErrorCode Publisher::SetPose(core::PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                   const Eigen::Vector3d& p_ToHo_T) noexcept {
  Impl& m = *impl_;
  const base::ErrorCode code = m.graph->SetPose(edge, q_TH, p_ToHo_T);
  if (code == base::ErrorCode::kOk) m.PublishPose(edge.child);
  return code;
}

base::ErrorCode Publisher::SetPose(core::PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                   const Eigen::Vector3d& p_ToHo_T,
                                   const core::CovarianceInput& covariance) noexcept {
  Impl& m = *impl_;
  const base::ErrorCode code = m.graph->SetPose(edge, q_TH, p_ToHo_T, covariance);
  if (code == base::ErrorCode::kOk) m.PublishPose(edge.child);
  return code;
}

base::ErrorCode Publisher::SetTwist(core::TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                    const Eigen::Vector3d& w_DH_H) noexcept {
  Impl& m = *impl_;
  const base::ErrorCode code = m.graph->SetTwist(edge, v_DHo_H, w_DH_H);
  if (code == base::ErrorCode::kOk) m.PublishTwist(edge);
  return code;
}

base::ErrorCode Publisher::SetTwist(core::TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                    const Eigen::Vector3d& w_DH_H,
                                    const core::CovarianceInput& covariance) noexcept {
  Impl& m = *impl_;
  const base::ErrorCode code = m.graph->SetTwist(edge, v_DHo_H, w_DH_H, covariance);
  if (code == base::ErrorCode::kOk) m.PublishTwist(edge);
  return code;
}

base::ErrorCode Publisher::SetTwist(core::TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                    const Eigen::Vector3d& w_DH_H,
                                    const core::AccelerationInput& acceleration) noexcept {
  Impl& m = *impl_;
  // Checked first, so that a refused acceleration leaves the twist as it was.
  if (!coord::ValidateVector(acceleration.linear, coord::ValueRole::kLinearAcceleration) ||
      !coord::ValidateVector(acceleration.angular, coord::ValueRole::kAngularAcceleration)) {
    return base::ErrorCode::kInvalidNumber;
  }
  const base::ErrorCode code = m.graph->SetTwist(edge, v_DHo_H, w_DH_H);
  if (code != base::ErrorCode::kOk) return code;
  const base::ErrorCode with =
      m.graph->SetAcceleration(edge, acceleration.linear, acceleration.angular);
  m.PublishTwist(edge);  // the twist is set: it goes out, with the acceleration when taken
  return with;
}

base::ErrorCode Publisher::SetAcceleration(core::TwistHandle edge, const Eigen::Vector3d& a_DHo_H,
                                           const Eigen::Vector3d& alpha_DH_H) noexcept {
  Impl& m = *impl_;
  const base::ErrorCode code = m.graph->SetAcceleration(edge, a_DHo_H, alpha_DH_H);
  if (code == base::ErrorCode::kOk) m.PublishTwist(edge);
  return code;
}

base::ErrorCode Publisher::SetWrench(core::WrenchHandle wrench, const Eigen::Vector3d& f_S,
                                     const Eigen::Vector3d& m_So_S) noexcept {
  Impl& m = *impl_;
  const base::ErrorCode code = m.graph->SetWrench(wrench, f_S, m_So_S);
  if (code == base::ErrorCode::kOk) m.PublishWrench(wrench.slot);
  return code;
}

void Publisher::Impl::PublishPoseSample(core::FrameIndex child, core::Stamp stamp) noexcept {
  const core::PoseHistory* history = graph->pose_history(child);
  double h[7], c[21];
  // The sample as stored (the newest value may be another sample's: out-of-order stamps).
  if (history == nullptr || !history->ValueAt(stamp.nanoseconds(), h) ||
      !history->CovarianceAt(stamp.nanoseconds(), c)) {
    return;
  }
  semgraph_wire_Value v = NewValue(semgraph_wire_VALUE_POSE, child.value(), pose_seq);
  v.time_ns = stamp.nanoseconds();
  PutPoseSample(v.numbers, h);
  PutCovarianceWords(v.covariance, c);
  Send(v, true);
}

void Publisher::Impl::PublishTwistSample(core::TwistHandle edge, core::Stamp stamp) noexcept {
  const core::TwistHistory* history = graph->twist_history(edge.slot);
  double h[6], c[21];
  if (history == nullptr || !history->ValueAt(stamp.nanoseconds(), h) ||
      !history->CovarianceAt(stamp.nanoseconds(), c)) {
    return;
  }
  const std::uint32_t id = graph->topology().twist_edge(edge.slot).head.load().value();
  semgraph_wire_Value v = NewValue(semgraph_wire_VALUE_TWIST, id, twist_seq);
  v.time_ns = stamp.nanoseconds();
  for (int i = 0; i < 6; ++i) v.numbers[i] = h[i];
  PutCovarianceWords(v.covariance, c);
  PutSampleAcceleration(*history, v.time_ns, &v.has_acceleration, v.acceleration);
  Send(v, true);
}

void Publisher::Impl::PublishWrenchSample(std::uint32_t slot, core::Stamp stamp) noexcept {
  const auto* history = graph->wrench_store().history.of(slot);
  double h[6];
  if (history == nullptr || !history->ValueAt(stamp.nanoseconds(), h)) return;
  semgraph_wire_Value v = NewValue(semgraph_wire_VALUE_WRENCH, slot, wrench_seq);
  v.time_ns = stamp.nanoseconds();
  std::copy(h, h + 6, v.numbers);  // (f_S, m_So_S, 0)
  Send(v, true);
}

base::ErrorCode Publisher::SetTwist(core::TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                    const Eigen::Vector3d& w_DH_H, core::Stamp stamp,
                                    const core::AccelerationInput& acceleration) noexcept {
  Impl& m = *impl_;
  // Checked first, so that a refused acceleration leaves the history as it was.
  if (!coord::ValidateVector(acceleration.linear, coord::ValueRole::kLinearAcceleration) ||
      !coord::ValidateVector(acceleration.angular, coord::ValueRole::kAngularAcceleration)) {
    return base::ErrorCode::kInvalidNumber;
  }
  const base::ErrorCode code = m.graph->SetTwist(edge, v_DHo_H, w_DH_H, stamp);
  if (code != base::ErrorCode::kOk) return code;
  const base::ErrorCode with =
      m.graph->SetAcceleration(edge, acceleration.linear, acceleration.angular, stamp);
  m.PublishTwistSample(edge, stamp);  // the sample is set: it goes out, with what it carries
  return with;
}

base::ErrorCode Publisher::SetAcceleration(core::TwistHandle edge, const Eigen::Vector3d& a_DHo_H,
                                           const Eigen::Vector3d& alpha_DH_H,
                                           core::Stamp stamp) noexcept {
  Impl& m = *impl_;
  const base::ErrorCode code = m.graph->SetAcceleration(edge, a_DHo_H, alpha_DH_H, stamp);
  if (code == base::ErrorCode::kOk) m.PublishTwistSample(edge, stamp);
  return code;
}

base::ErrorCode Publisher::SetWrench(core::WrenchHandle wrench, const Eigen::Vector3d& f_S,
                                     const Eigen::Vector3d& m_So_S, core::Stamp stamp) noexcept {
  Impl& m = *impl_;
  const base::ErrorCode code = m.graph->SetWrench(wrench, f_S, m_So_S, stamp);
  if (code == base::ErrorCode::kOk) m.PublishWrenchSample(wrench.slot, stamp);
  return code;
}

base::ErrorCode Publisher::SetPose(core::PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                   const Eigen::Vector3d& p_ToHo_T, core::Stamp stamp) noexcept {
  Impl& m = *impl_;
  const base::ErrorCode code = m.graph->SetPose(edge, q_TH, p_ToHo_T, stamp);
  if (code == base::ErrorCode::kOk) m.PublishPoseSample(edge.child, stamp);
  return code;
}

base::ErrorCode Publisher::SetTwist(core::TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                    const Eigen::Vector3d& w_DH_H, core::Stamp stamp) noexcept {
  Impl& m = *impl_;
  const base::ErrorCode code = m.graph->SetTwist(edge, v_DHo_H, w_DH_H, stamp);
  if (code == base::ErrorCode::kOk) m.PublishTwistSample(edge, stamp);
  return code;
}

base::ErrorCode Publisher::SetPose(core::PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                   const Eigen::Vector3d& p_ToHo_T, core::Stamp stamp,
                                   const core::CovarianceInput& covariance) noexcept {
  Impl& m = *impl_;
  const base::ErrorCode code = m.graph->SetPose(edge, q_TH, p_ToHo_T, stamp, covariance);
  if (code == base::ErrorCode::kOk) m.PublishPoseSample(edge.child, stamp);
  return code;
}

base::ErrorCode Publisher::SetTwist(core::TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                    const Eigen::Vector3d& w_DH_H, core::Stamp stamp,
                                    const core::CovarianceInput& covariance) noexcept {
  Impl& m = *impl_;
  const base::ErrorCode code = m.graph->SetTwist(edge, v_DHo_H, w_DH_H, stamp, covariance);
  if (code == base::ErrorCode::kOk) m.PublishTwistSample(edge, stamp);
  return code;
}

namespace {

// The joints a by-name call names, each with the value it was given (the last one, as the
// graph applies them), in the order of first mention.
struct Named {
  std::uint32_t index;
  std::optional<double> q, qdot;
};
std::vector<Named> NamedJoints(const core::SceneGraph<>& g,
                               std::span<const core::JointValue> positions,
                               std::span<const core::JointValue> velocities,
                               std::span<const core::JointValue> accelerations = {}) {
  std::vector<Named> out;
  std::map<std::uint32_t, std::size_t> at;
  // (An acceleration names its joint only: the state published is the graph's after the call.)
  auto add = [&](const core::JointValue& v, int field) {
    auto h = g.FindJoint(v.joint);
    if (!h) return;
    auto [it, fresh] = at.emplace(h->index.value(), out.size());
    if (fresh) out.push_back({h->index.value(), std::nullopt, std::nullopt});
    if (field == 0) out[it->second].q = v.value;
    if (field == 1) out[it->second].qdot = v.value;
  };
  for (const core::JointValue& v : positions) add(v, 0);
  for (const core::JointValue& v : velocities) add(v, 1);
  for (const core::JointValue& v : accelerations) add(v, 2);
  return out;
}

}  // namespace

core::BuildResult Publisher::SetJoints(std::span<const core::JointValue> positions,
                                       std::span<const core::JointValue> velocities) {
  Impl& m = *impl_;
  core::BuildResult res = m.graph->SetJoints(positions, velocities);
  if (!res) return res;
  const core::internal::JointTable& t = m.graph->joint_table();
  for (const Named& n : NamedJoints(*m.graph, positions, velocities)) {
    const core::internal::JointRecord& j = t.joints[n.index];
    m.PublishJoint(n.index, n.q.value_or(j.q), n.qdot.value_or(j.qdot), std::nullopt);
  }
  return res;
}

core::BuildResult Publisher::SetJoints(std::span<const core::JointValue> positions,
                                       std::span<const core::JointValue> velocities,
                                       std::span<const core::JointValue> accelerations) {
  Impl& m = *impl_;
  core::BuildResult res = m.graph->SetJoints(positions, velocities, accelerations);
  if (!res) return res;
  const core::internal::JointTable& t = m.graph->joint_table();
  for (const Named& n : NamedJoints(*m.graph, positions, velocities, accelerations)) {
    const core::internal::JointRecord& j = t.joints[n.index];
    m.PublishJoint(n.index, j.q, j.qdot, std::nullopt);
  }
  return res;
}

core::BuildResult Publisher::SetJoints(std::span<const core::JointValue> positions,
                                       std::span<const core::JointValue> velocities,
                                       core::Stamp stamp) {
  return SetJoints(positions, velocities, {}, stamp);
}

core::BuildResult Publisher::SetJoints(std::span<const core::JointValue> positions,
                                       std::span<const core::JointValue> velocities,
                                       std::span<const core::JointValue> accelerations,
                                       core::Stamp stamp) {
  Impl& m = *impl_;
  const std::vector<Named> named = NamedJoints(*m.graph, positions, velocities, accelerations);
  const core::internal::JointTable& t = m.graph->joint_table();
  std::vector<bool> was_stamped;
  for (const Named& n : named)
    was_stamped.push_back(m.graph->pose_history(t.joints[n.index].child) != nullptr);
  core::BuildResult res = accelerations.empty()
                              ? m.graph->SetJoints(positions, velocities, stamp)
                              : m.graph->SetJoints(positions, velocities, accelerations, stamp);
  if (!res) return res;
  bool structure = false;
  for (std::size_t i = 0; i < named.size(); ++i) {
    const Named& n = named[i];
    const core::internal::JointRecord& j = t.joints[n.index];
    if (!was_stamped[i]) {
      // Its first stamped state: the joint's edges became stamped, a structure change (the
      // structure carries this state as the newest sample).
      if (n.index < m.joint_seq.size()) ++m.joint_seq[n.index];
      structure = true;
      continue;
    }
    // A field not given keeps the newest sample's value, which the call did not change.
    m.PublishJoint(n.index, n.q.value_or(j.q), n.qdot.value_or(j.qdot), stamp);
  }
  if (structure) {
    auto published = PublishStructure();
    if (!published) ++m.write_failures;
  }
  return res;
}

base::ErrorCode Publisher::SetJointPositions(const core::JointGroup& group,
                                             std::span<const double> q) noexcept {
  const base::ErrorCode code = impl_->graph->SetJointPositions(group, q);
  if (code == base::ErrorCode::kOk) impl_->PublishGroup(group, q.data(), nullptr, std::nullopt);
  return code;
}
base::ErrorCode Publisher::SetJointPositions(const core::JointGroup& group,
                                             std::span<const double> q,
                                             core::Stamp stamp) noexcept {
  const base::ErrorCode code = impl_->graph->SetJointPositions(group, q, stamp);
  if (code == base::ErrorCode::kOk) impl_->PublishGroup(group, q.data(), nullptr, stamp);
  return code;
}
base::ErrorCode Publisher::SetJointState(const core::JointGroup& group, std::span<const double> q,
                                         std::span<const double> qdot) noexcept {
  const base::ErrorCode code = impl_->graph->SetJointState(group, q, qdot);
  if (code == base::ErrorCode::kOk) impl_->PublishGroup(group, q.data(), qdot.data(), std::nullopt);
  return code;
}
base::ErrorCode Publisher::SetJointState(const core::JointGroup& group, std::span<const double> q,
                                         std::span<const double> qdot, core::Stamp stamp) noexcept {
  const base::ErrorCode code = impl_->graph->SetJointState(group, q, qdot, stamp);
  if (code == base::ErrorCode::kOk) impl_->PublishGroup(group, q.data(), qdot.data(), stamp);
  return code;
}

base::ErrorCode Publisher::SetJointAccelerations(const core::JointGroup& group,
                                                 std::span<const double> qddot) noexcept {
  const base::ErrorCode code = impl_->graph->SetJointAccelerations(group, qddot);
  if (code == base::ErrorCode::kOk) impl_->PublishGroupState(group);
  return code;
}
base::ErrorCode Publisher::SetJointState(const core::JointGroup& group, std::span<const double> q,
                                         std::span<const double> qdot,
                                         std::span<const double> qddot) noexcept {
  const base::ErrorCode code = impl_->graph->SetJointState(group, q, qdot, qddot);
  if (code == base::ErrorCode::kOk) impl_->PublishGroupState(group);
  return code;
}

base::ErrorCode Publisher::SetJointAccelerations(const core::JointGroup& group,
                                                 std::span<const double> qddot,
                                                 core::Stamp stamp) noexcept {
  const base::ErrorCode code = impl_->graph->SetJointAccelerations(group, qddot, stamp);
  if (code == base::ErrorCode::kOk)
    impl_->PublishGroup(group, nullptr, nullptr, stamp, qddot.data());
  return code;
}
base::ErrorCode Publisher::SetJointState(const core::JointGroup& group, std::span<const double> q,
                                         std::span<const double> qdot,
                                         std::span<const double> qddot,
                                         core::Stamp stamp) noexcept {
  const base::ErrorCode code = impl_->graph->SetJointState(group, q, qdot, qddot, stamp);
  if (code == base::ErrorCode::kOk)
    impl_->PublishGroup(group, q.data(), qdot.data(), stamp, qddot.data());
  return code;
}

base::Expected<base::Ok, std::string> Publisher::WaitForMirrors(std::uint32_t count,
                                                                std::chrono::milliseconds timeout) {
  const Impl& m = *impl_;
  const dds_time_t deadline = dds_time() + DDS_MSECS(timeout.count());
  for (const Entity* w :
       {&m.structure_writer, &m.value_writer, &m.sample_writer, &m.batch_writer}) {
    std::uint32_t matched = 0;
    const dds_return_t rc = dds_shared::WaitForMatches(w->get(), count, deadline, &matched);
    if (rc == DDS_RETCODE_TIMEOUT) {
      return base::Unexpected{std::to_string(matched) + " mirror(s) matched of " +
                              std::to_string(count) + " expected within " +
                              std::to_string(timeout.count()) + " ms"};
    }
    if (rc != DDS_RETCODE_OK) return base::Unexpected{internal::DdsError("matching", rc)};
  }
  return base::Ok{};
}

const std::string& Publisher::owner() const noexcept { return impl_->owner; }
std::uint64_t Publisher::source() const noexcept { return impl_->source; }
std::uint64_t Publisher::revision() const noexcept { return impl_->revision; }
std::uint64_t Publisher::write_failures() const noexcept { return impl_->write_failures; }

}  // namespace semgraph::dds
