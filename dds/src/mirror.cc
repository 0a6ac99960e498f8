// Mirror (mirror.h): creation (the DDS entities, the listener, the receive thread), teardown,
// and the thread-safe queries. The receive paths are in mirror_threads.cc, the checks of a
// structure sample in mirror_parse.cc, the replay in mirror_reconcile.cc.
#include "semgraph/dds/mirror.h"

#include <algorithm>
#include <mutex>
#include <thread>
#include <tuple>

#include "mirror_impl.h"

namespace semgraph::dds {

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
  if (!m.participant.ok())
    return base::Unexpected{internal::DdsError("cannot join the DDS domain", m.participant.get())};
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
  if (!m.structure_reader.ok() || !m.value_reader.ok() || !m.sample_reader.ok() ||
      !m.batch_reader.ok() || !m.status_writer.ok() || !m.waitset.ok() || !m.guard.ok()) {
    return base::Unexpected{std::string("cannot create the DDS readers and writers")};
  }
  const dds_entity_t c1 = dds_create_readcondition(m.structure_reader.get(), DDS_ANY_STATE);
  const dds_entity_t c2 = dds_create_readcondition(m.value_reader.get(), DDS_ANY_STATE);
  const dds_entity_t c3 = dds_create_readcondition(m.sample_reader.get(), DDS_ANY_STATE);
  const dds_entity_t c4 = dds_create_readcondition(m.batch_reader.get(), DDS_ANY_STATE);
  if (dds_waitset_attach(m.waitset.get(), c1, 1) < 0 ||
      dds_waitset_attach(m.waitset.get(), c2, 2) < 0 ||
      dds_waitset_attach(m.waitset.get(), c3, 3) < 0 ||
      dds_waitset_attach(m.waitset.get(), c4, 4) < 0 ||
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

const core::SceneGraph<>& Mirror::graph() const noexcept { return impl_->graph; }

void Mirror::WithGraph(const std::function<void(const core::SceneGraph<>&)>& fn) const {
  std::lock_guard<std::mutex> topo(impl_->topology_mutex);
  fn(impl_->graph);
}

std::uint64_t Mirror::structure_generation() const noexcept {
  return impl_->generation.load(std::memory_order_acquire);
}
std::uint64_t Mirror::values_applied() const noexcept {
  return impl_->values.load(std::memory_order_acquire);
}
std::uint64_t Mirror::messages_rejected() const noexcept {
  return impl_->rejected.load(std::memory_order_acquire);
}
std::uint64_t Mirror::samples_dropped() const noexcept {
  return impl_->dropped.load(std::memory_order_acquire);
}

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
    out.push_back({s.owner, s.twist, s.head, s.tail, s.seq, s.received, s.stamp_ns, s.receive_ns,
                   s.stamped, s.time_ns, s.joint, s.wrench});
  }
  std::sort(out.begin(), out.end(), [](const EdgeState& a, const EdgeState& b) {
    return std::tie(a.wrench, a.joint, a.twist, a.head, a.tail) <
           std::tie(b.wrench, b.joint, b.twist, b.head, b.tail);
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

bool Mirror::Impl::HasRefusal(const std::string& owner) const {
  return std::any_of(refusals.begin(), refusals.end(),
                     [&](const Report& rep) { return rep.owner == owner; });
}

bool Mirror::CaughtUp() const {
  const Impl& m = *impl_;
  std::lock_guard<std::mutex> lock(m.state_mutex);
  if (m.owners.empty()) return false;
  // The slot of an announced edge or joint holds at least the announced value. Refused ones
  // have no slot; any other missing one means not caught up.
  const auto holds = [&m](const std::string& owner, const ValueKey& key, std::uint64_t seq) {
    auto it = m.slots.find(key);
    return it == m.slots.end() ? m.HasRefusal(owner) : it->second.seq >= seq;
  };
  for (const auto& [name, o] : m.owners) {
    for (const Row& r : o.rows) {
      if (r.kind < semgraph_wire_ELEMENT_POSE) continue;
      const std::uint8_t vkind = r.kind == semgraph_wire_ELEMENT_TWIST ? semgraph_wire_VALUE_TWIST
                                 : r.kind == semgraph_wire_ELEMENT_WRENCH
                                     ? semgraph_wire_VALUE_WRENCH
                                     : semgraph_wire_VALUE_POSE;
      if (!holds(name, {o.source, r.edge, vkind}, r.seq)) return false;
    }
    for (const JointRow& j : o.joints) {
      if (!holds(name, {o.source, j.id, semgraph_wire_VALUE_JOINT}, j.seq)) return false;
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
