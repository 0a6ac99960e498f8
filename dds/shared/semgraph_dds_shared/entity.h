// Internal to semgraph_dds and semgraph_ros_dds (and their tests): what both DDS layers need
// of Cyclone DDS alike, with no semgraph dependency, so that neither layer depends on the
// other (CMake target semgraph_dds_shared, header-only, never installed).
//   Entity  owns one DDS entity (participant, topic, reader, writer, waitset, condition) and
//           deletes it, with its children, on destruction.
//   WaitForMatches   waits until a writer has matched readers (the writer's side).
//   SyncWithReaders  waits until a writer has matched readers and each of them is in sync with
//           it (every later sample reaches it).
#pragma once

#include <dds/dds.h>

#include <cstdint>

namespace semgraph::dds_shared {

class Entity {
 public:
  Entity() = default;
  explicit Entity(dds_entity_t e) : e_(e) {}
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;
  Entity(Entity&& o) noexcept : e_(o.e_) { o.e_ = 0; }
  Entity& operator=(Entity&& o) noexcept {
    if (this != &o) {
      Reset();
      e_ = o.e_;
      o.e_ = 0;
    }
    return *this;
  }
  ~Entity() { Reset(); }
  void Reset() {
    if (e_ > 0) dds_delete(e_);
    e_ = 0;
  }
  [[nodiscard]] dds_entity_t get() const noexcept { return e_; }
  [[nodiscard]] bool ok() const noexcept { return e_ > 0; }

 private:
  dds_entity_t e_ = 0;
};

/// Waits until `writer` has matched at least `count` readers (the writer's side: from then on
/// it keeps every sample for them until acknowledged), or until `deadline`. Woken by the
/// writer's publication-matched status on a waitset, and rechecked every 10 ms (a listener on
/// the writer may consume the status); sets the writer's status mask to that status alone.
/// `*matched`: the count last seen. Returns
/// DDS_RETCODE_OK, DDS_RETCODE_TIMEOUT, or DDS's error. Blocks: not for real-time code.
inline dds_return_t WaitForMatches(dds_entity_t writer, std::uint32_t count, dds_time_t deadline,
                                   std::uint32_t* matched) {
  dds_return_t rc = dds_set_status_mask(writer, DDS_PUBLICATION_MATCHED_STATUS);
  if (rc != DDS_RETCODE_OK) return rc;
  Entity waitset(dds_create_waitset(dds_get_participant(writer)));
  if (!waitset.ok()) return waitset.get();
  if ((rc = dds_waitset_attach(waitset.get(), writer, 0)) != DDS_RETCODE_OK) return rc;
  for (;;) {
    dds_publication_matched_status_t status{};
    if ((rc = dds_get_publication_matched_status(writer, &status)) != DDS_RETCODE_OK) return rc;
    *matched = status.current_count;
    if (status.current_count >= count) return DDS_RETCODE_OK;
    const dds_time_t now = dds_time();
    if (now >= deadline) return DDS_RETCODE_TIMEOUT;
    const dds_time_t wake = deadline - now < DDS_MSECS(10) ? deadline : now + DDS_MSECS(10);
    if ((rc = dds_waitset_wait_until(waitset.get(), nullptr, 0, wake)) < 0) return rc;
  }
}

/// Waits, at most `timeout`, until `writer` (of a keyless topic) has matched at least `count`
/// readers and each reader matched then has acknowledged it. Why both, on a volatile topic:
/// a sample written before the writer matched a reader never reaches it, and the reader's own
/// matched status may show the writer earlier than the writer's shows the reader; and a
/// reader drops a writer's data until it has had the writer's first heartbeat (Cyclone then
/// recovers it from the writer's history, other DDS readers may count it as missed). An
/// acknowledgement answers a heartbeat: once every matched reader acknowledged a message
/// written after the match, every later sample reaches it (reliable QoS).
/// The message is `key_sample` unregistered: no data, a sequence number only (readers take it
/// as an invalid sample, which ROS 2 and semgraph's listener skip; a later write registers the
/// instance again). `key_sample`: any sample of the topic (its key fields, none here).
/// Returns DDS_RETCODE_OK, DDS_RETCODE_TIMEOUT, or DDS's error. Blocks: not for real-time code.
inline dds_return_t SyncWithReaders(dds_entity_t writer, std::uint32_t count,
                                    dds_duration_t timeout, const void* key_sample) {
  const dds_time_t deadline = dds_time() + timeout;
  std::uint32_t matched = 0;
  dds_return_t rc = WaitForMatches(writer, count, deadline, &matched);
  if (rc != DDS_RETCODE_OK || matched == 0) return rc;  // matched == 0: no reader to sync
  if ((rc = dds_unregister_instance(writer, key_sample)) != DDS_RETCODE_OK) return rc;
  const dds_time_t now = dds_time();
  return dds_wait_for_acks(writer, deadline > now ? deadline - now : 0);
}

}  // namespace semgraph::dds_shared
