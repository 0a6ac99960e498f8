// Mirror (mirror.h): the receive paths. The mirror's thread waits on the readers and takes the
// structures (then reconciles); values, samples and batches are taken where they arrive
// (Cyclone's listener, or the mirror's thread for what is left) and applied through handles.
#include <algorithm>
#include <cmath>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "mirror_impl.h"
#include "semgraph/coord/validate.h"

namespace semgraph::dds {

using internal::GoodStamp;
using internal::ParseStructure;

namespace {

constexpr std::size_t kMaxPending = 1u << 16;  // values waiting for their structure
constexpr int kTakeBatch = 256;
constexpr std::size_t kMaxPendingSamples = 1024;  // per edge waiting for its structure

}  // namespace

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
        const std::string why =
            ParseStructure(*static_cast<const semgraph_wire_Structure*>(samples[i]), &rec);
        if (!why.empty()) {
          Reject(rec.owner, "structure from owner '" + rec.owner + "': " + why);
          continue;
        }
        rec.alive = true;
        owner_of_instance[info.instance_handle] = rec.owner;
        auto it = owners.find(rec.owner);
        if (it != owners.end() && it->second.source == rec.source &&
            it->second.revision >= rec.revision) {
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

// The graph's setter for the slot's kind, with the stamped, covariance (S null: exact) and
// acceleration (null: none) variants; the twist's acceleration is set right after the twist.
base::ErrorCode Mirror::Impl::SetSlot(Slot& slot, const double* n, const coord::Covariance6* S,
                                      const double* acc, std::optional<core::Stamp> at,
                                      core::UpdateError* bad) noexcept {
  const Eigen::Vector3d a(n[0], n[1], n[2]), b(n[3], n[4], n[5]);
  const Eigen::Quaterniond q(n[0], n[1], n[2], n[3]);
  const Eigen::Vector3d p(n[4], n[5], n[6]);
  const coord::Covariance6 zero = coord::Covariance6::Zero();
  core::CovarianceInput covariance;
  covariance.matrix = S != nullptr ? S : &zero;
  const bool has_covariance = S != nullptr;
  if (slot.wrench) {
    return at ? graph.SetWrench(slot.wrench_handle, a, b, *at, bad)
              : graph.SetWrench(slot.wrench_handle, a, b, bad);
  }
  if (slot.joint) {
    const double qv[1] = {n[0]}, qdot[1] = {n[1]};
    const double qddot[1] = {acc != nullptr ? acc[0] : 0.0};
    return at && acc ? graph.SetJointState(slot.group, qv, qdot, qddot, *at, bad)
           : at      ? graph.SetJointState(slot.group, qv, qdot, *at, bad)
           : acc     ? graph.SetJointState(slot.group, qv, qdot, qddot, bad)
                     : graph.SetJointState(slot.group, qv, qdot, bad);
  }
  if (slot.twist) {
    const base::ErrorCode code =
        at && has_covariance ? graph.SetTwist(slot.twist_handle, a, b, *at, covariance, bad)
        : at                 ? graph.SetTwist(slot.twist_handle, a, b, *at, bad)
        : has_covariance     ? graph.SetTwist(slot.twist_handle, a, b, covariance, bad)
                             : graph.SetTwist(slot.twist_handle, a, b, bad);
    // A twist (a stamped sample: its sample) clears the acceleration; one given comes with it
    // (checked before), a stamped one on the sample just set.
    if (code != base::ErrorCode::kOk || acc == nullptr) return code;
    const Eigen::Vector3d lin(acc[0], acc[1], acc[2]), ang(acc[3], acc[4], acc[5]);
    return at ? graph.SetAcceleration(slot.twist_handle, lin, ang, *at, bad)
              : graph.SetAcceleration(slot.twist_handle, lin, ang, bad);
  }
  return at && has_covariance ? graph.SetPose(slot.pose, q, p, *at, covariance, bad)
         : at                 ? graph.SetPose(slot.pose, q, p, *at, bad)
         : has_covariance     ? graph.SetPose(slot.pose, q, p, covariance, bad)
                              : graph.SetPose(slot.pose, q, p, bad);
}

// What a value may carry beside its numbers, checked before anything is set: the reason it is
// malformed (empty: fine). A covariance goes with edges only; an acceleration with a twist
// edge's value or sample, or a joint's state (qddot; its setter checks the numbers).
std::string Mirror::Impl::Malformed(const Slot& slot, bool has_covariance,
                                    const double* acc) const {
  if (has_covariance && (slot.joint || slot.wrench)) {
    return std::string("a covariance with a ") + (slot.joint ? "joint state" : "wrench") +
           " (not carried in this version)";
  }
  if (acc != nullptr && !(slot.twist || slot.joint))
    return "an acceleration with a value that is neither a twist nor a joint state";
  return {};
}

bool Mirror::Impl::ApplyValue(Slot& slot, std::uint64_t seq, std::int64_t stamp, const double* n,
                              const double* cov, const double* acc, const std::string& what,
                              std::optional<std::int64_t> time, const In* from) {
  if (time.has_value() != slot.stamped) {
    Reject(slot.owner, what +
                           (time ? ": a stamped sample for the unstamped "
                                 : ": an unstamped value for the stamped ") +
                           (slot.joint    ? "joint '"
                            : slot.wrench ? "wrench on '"
                                          : "edge into '") +
                           slot.head + "' (stamp_mismatch)");
    return false;
  }
  if (!slot.settable) {
    Reject(slot.owner, what +
                           (slot.joint ? ": a state for the fixed or mimic joint '"
                                       : ": a value for the constant edge into '") +
                           slot.head + "'");
    return false;
  }
  // The covariance (docs/uncertainty.md): none or zero is an exact value (a timeless edge's
  // covariance becomes zero, a stamped sample carries none); the setter checks it
  // (invalid_number, invalid_covariance).
  const bool has_covariance = cov != nullptr && internal::HasCovariance(cov);
  if (std::string why = Malformed(slot, has_covariance, acc); !why.empty()) {
    Reject(slot.owner, what + " into '" + slot.head + "': " + why);
    return false;
  }
  base::ErrorCode code = base::ErrorCode::kOk;
  core::UpdateError bad;  // the setter's verdict on the numbers: which, and which limit
  if (acc != nullptr && slot.twist) {
    // The twist and its acceleration are two setter calls: the acceleration is checked first
    // (as SetAcceleration checks it), so a refused one leaves the twist as it was.
    auto a = coord::ValidateVector(Eigen::Vector3d(acc[0], acc[1], acc[2]),
                                   coord::ValueRole::kLinearAcceleration);
    auto alpha = coord::ValidateVector(Eigen::Vector3d(acc[3], acc[4], acc[5]),
                                       coord::ValueRole::kAngularAcceleration);
    if (!a || !alpha) code = core::internal::Report(&bad, !a ? a.error() : alpha.error());
  }
  if (code == base::ErrorCode::kOk) {
    const coord::Covariance6 S =
        has_covariance ? internal::UnpackCovariance(cov) : coord::Covariance6::Zero();
    const std::optional<core::Stamp> at =
        time ? std::optional<core::Stamp>(core::Stamp::Nanoseconds(*time)) : std::nullopt;
    code = SetSlot(slot, n, has_covariance ? &S : nullptr, acc, at, &bad);
  }
  if (code == base::ErrorCode::kStampTooOld || code == base::ErrorCode::kDuplicateStamp) {
    // The history's rules decide reordered and repeated samples (docs/time.md): not malformed.
    dropped.fetch_add(1, std::memory_order_relaxed);
    slot.seq = std::max(slot.seq, seq);
    return false;
  }
  if (code != base::ErrorCode::kOk) {
    const bool numbers =
        code == base::ErrorCode::kInvalidNumber || code == base::ErrorCode::kInvalidRotation ||
        code == base::ErrorCode::kInvalidCovariance || code == base::ErrorCode::kJointLimit;
    Reject(slot.owner, what + " into '" + slot.head + "': " + std::string(base::ToString(code)) +
                           (numbers ? ": " + core::Describe(bad) : std::string()) +
                           (from ? " (" + what + " of edge " + std::to_string(from->edge) +
                                       " from source " + std::to_string(from->source) + ")"
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
  // A stamped twist sample may carry its acceleration, a stamped wrench its sample (f, m): the
  // slot decides (ApplyValue: stamp_mismatch, Malformed).
  const char* why = v.kind > semgraph_wire_VALUE_WRENCH ? ": unknown kind"
                    : samples && !GoodStamp(v.time_ns)
                        ? ": the stamp is out of range (invalid_number)"
                        : nullptr;
  if (why != nullptr) {
    Reject("", std::string(samples ? "sample" : "value") + " of edge " + std::to_string(v.edge) +
                   " from source " + std::to_string(v.source) + why);
    return false;
  }
  const ValueKey key{v.source, v.edge, v.kind};
  auto it = slots.find(key);
  // A joint never set may become stamped by a structure still on the way: hold its samples.
  const bool hold = it != slots.end() && samples && it->second.joint && it->second.unset &&
                    it->second.received == 0;
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
    std::copy(v.covariance, v.covariance + internal::kPackedCovariance, got.cov);
    got.has_acc = v.acceleration != nullptr;
    if (got.has_acc) std::copy(v.acceleration, v.acceleration + 6, got.acc);
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
  return ApplyValue(it->second, v.seq, v.stamp_ns, v.numbers, v.covariance, v.acceleration,
                    samples ? "sample" : "value",
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
        const In in{v.source,  v.edge,       v.kind,
                    v.seq,     v.stamp_ns,   v.time_ns,
                    v.numbers, v.covariance, v.has_acceleration ? v.acceleration : nullptr};
        if (HandleValue(in, samples)) ++applied_now;
      }
    }
    CountApplied(applied_now);
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
        if (b.updates._length > internal::kMaxBatchUpdates ||
            (b.updates._length > 0 && b.updates._buffer == nullptr)) {
          Reject("", "batch " + std::to_string(b.serial) + " from source " +
                         std::to_string(b.source) + ": " + std::to_string(b.updates._length) +
                         " updates (at most " + std::to_string(internal::kMaxBatchUpdates) + ")");
          continue;
        }
        for (std::uint32_t k = 0; k < b.updates._length; ++k) {
          const semgraph_wire_Update& u = b.updates._buffer[k];
          const In in{b.source,  u.edge,       u.kind,
                      u.seq,     u.stamp_ns,   u.time_ns,
                      u.numbers, u.covariance, u.has_acceleration ? u.acceleration : nullptr};
          if (HandleValue(in, u.stamped)) ++applied_now;
        }
      }
    }
    dds_return_loan(batch_reader.get(), samples, n);
    CountApplied(applied_now);
    if (n < 16) break;
  }
}

void Mirror::Impl::CountApplied(std::uint64_t applied_now) {
  if (applied_now == 0) return;
  values.fetch_add(applied_now, std::memory_order_release);
  Changed();
}

}  // namespace semgraph::dds
