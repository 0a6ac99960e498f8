// Internal to semgraph_dds: the generated wire types, topic names and QoS, and an owning
// wrapper for DDS entities. Not installed.
#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <string>

#include "semgraph/coord/covariance.h"
#include "semgraph_dds_shared/entity.h"
#include "semgraph_wire.h"

namespace semgraph::dds::internal {

inline constexpr const char* kStructureTopic = "semgraph_structure";
inline constexpr const char* kValueTopic = "semgraph_values";
inline constexpr const char* kStatusTopic = "semgraph_status";
inline constexpr const char* kSampleTopic = "semgraph_samples";
/// Stamped samples kept per edge by the sample topic's writers (and offered to late joiners).
inline constexpr int kSampleDepth = 1024;
inline constexpr const char* kBatchTopic = "semgraph_batches";
/// Batches kept per publisher by the batch topic's writers, and the updates of one batch.
inline constexpr int kBatchDepth = 64;
inline constexpr std::uint32_t kMaxBatchUpdates = 1024;

/// One structure element (semgraph_wire_Element) with its names owned: what a publisher puts
/// in a structure sample, and what a mirror keeps of one (checked).
struct Row {
  std::uint8_t kind = 0;
  std::uint32_t edge = 0;
  std::uint64_t seq = 0;
  std::string head, head_body, tail, tail_body;
  double n[7] = {0, 0, 0, 0, 0, 0, 0};
  bool stamped = false;
  std::int64_t time_ns = 0;
  double cov[21] = {};   // the packed covariance (semgraph_wire.idl; zero: exact)
  bool has_acc = false;  // a twist edge's acceleration is given (semgraph_wire.idl)
  double acc[6] = {};    // (a_DHo_H, alpha_DH_H) in [head]
};

/// The wire's packed covariance: the upper triangle of the symmetric 6x6 S, row by row.
inline constexpr int kPackedCovariance = 21;
inline void PackCovariance(const coord::Covariance6& S, double* out) noexcept {
  int k = 0;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) out[k++] = S(i, j);
  }
}
inline coord::Covariance6 UnpackCovariance(const double* in) noexcept {
  coord::Covariance6 S;
  int k = 0;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) S(i, j) = S(j, i) = in[k++];
  }
  return S;
}
/// True when a packed covariance is given (some entry nonzero; NaN counts as given).
inline bool HasCovariance(const double* packed) noexcept {
  for (int k = 0; k < kPackedCovariance; ++k) {
    if (!(packed[k] == 0.0)) return true;
  }
  return false;
}

/// Owns one DDS entity (semgraph_dds_shared/entity.h).
using Entity = dds_shared::Entity;

/// "what: <DDS's text for rc>".
inline std::string DdsError(const char* what, dds_return_t rc) {
  return std::string(what) + ": " + dds_strretcode(rc);
}

enum class TopicKind { kStructure, kValue, kStatus, kSample, kBatch };

/// The QoS of each topic, used by its writers and readers alike (docs/distributed.md):
///   structure  reliable, transient-local, keep-last 1 per owner (the whole structure)
///   values     reliable, transient-local, keep-last 1 per edge (the latest value)
///   status     reliable, transient-local, keep-last 64 per mirror
///   samples    reliable, transient-local, keep-last kSampleDepth per edge (stamped samples:
///              a history needs every one, not only the latest); the writer keeps all
///              until acknowledged (CreateWriter)
///   batches    reliable, transient-local, keep-last kBatchDepth per publisher (writer),
///              keep-all (reader): one control cycle's values in one sample
/// Liveliness automatic: a publisher is alive while its participant's lease is renewed (the
/// lease duration is the domain's configuration: Discovery/LeaseDuration).
inline dds_qos_t* MakeQos(TopicKind kind) {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
  const std::int32_t depth = kind == TopicKind::kStatus   ? 64
                             : kind == TopicKind::kSample ? kSampleDepth
                             : kind == TopicKind::kBatch  ? kBatchDepth
                                                          : 1;
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, depth);
  // What a late reader gets (transient-local): Cyclone keeps, per instance, the durability
  // service's history depth (default keep-last 1), not the writer's; the same depth.
  dds_qset_durability_service(qos, 0, DDS_HISTORY_KEEP_LAST, depth, DDS_LENGTH_UNLIMITED,
                              DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  dds_qset_destination_order(qos, DDS_DESTINATIONORDER_BY_RECEPTION_TIMESTAMP);
  return qos;
}

/// Creates a topic with its QoS; a negative return is DDS's error.
inline dds_entity_t CreateTopic(dds_entity_t participant, TopicKind kind) {
  const dds_topic_descriptor_t* desc = kind == TopicKind::kStructure ? &semgraph_wire_Structure_desc
                                       : kind == TopicKind::kStatus  ? &semgraph_wire_Status_desc
                                       : kind == TopicKind::kBatch   ? &semgraph_wire_Batch_desc
                                                                     : &semgraph_wire_Value_desc;
  const char* name = kind == TopicKind::kStructure ? kStructureTopic
                     : kind == TopicKind::kValue   ? kValueTopic
                     : kind == TopicKind::kSample  ? kSampleTopic
                     : kind == TopicKind::kBatch   ? kBatchTopic
                                                   : kStatusTopic;
  dds_qos_t* qos = MakeQos(kind);
  const dds_entity_t t = dds_create_topic(participant, desc, name, qos, nullptr);
  dds_delete_qos(qos);
  return t;
}

inline dds_entity_t CreateWriter(dds_entity_t participant, dds_entity_t topic, TopicKind kind) {
  dds_qos_t* qos = MakeQos(kind);
  if (kind == TopicKind::kSample) {
    // A reliable keep-last writer drops a sample its slow reader has not acknowledged once
    // kSampleDepth newer ones of the edge are written; every sample counts, so the writer keeps
    // all until acknowledged (write blocks, at most the reliability's 1 s, while its cache is
    // full). Late readers still get the durability service's last kSampleDepth.
    dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
  }
  const dds_entity_t w = dds_create_writer(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  return w;
}

inline dds_entity_t CreateReader(dds_entity_t participant, dds_entity_t topic, TopicKind kind) {
  dds_qos_t* qos = MakeQos(kind);
  if (kind == TopicKind::kValue) {
    // A mirror may fall behind under a burst; keep every edge's latest value, never block the
    // publisher for an old one (keep-last 1 per edge already drops superseded values).
    dds_qset_resource_limits(qos, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  } else if (kind == TopicKind::kSample || kind == TopicKind::kBatch) {
    // Every stamped sample counts (the history): the reader keeps all until taken.
    dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
    dds_qset_resource_limits(qos, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  }
  const dds_entity_t r = dds_create_reader(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  return r;
}

inline std::int64_t NowNs() noexcept { return dds_time(); }

}  // namespace semgraph::dds::internal
