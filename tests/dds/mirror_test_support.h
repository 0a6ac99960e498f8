// Test support shared by the mirror tests (mirror_test.cc, mirror_dynamics_test.cc): a raw DDS
// writer on one of semgraph's topics (what a hostile or buggy peer could send) and the options
// of a mirror whose log lines the test reads.
#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <mutex>
#include <string>

#include "semgraph/dds/mirror.h"

namespace semgraph::dds_test {

// A raw DDS writer with the topic's QoS (keep-last 1, as the publishers' value writers).
struct RawWriter {
  dds_entity_t participant = 0, writer = 0;
  RawWriter(std::uint32_t domain, const dds_topic_descriptor_t* desc, const char* name) {
    participant = dds_create_participant(domain, nullptr, nullptr);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
    dds_qset_destination_order(qos, DDS_DESTINATIONORDER_BY_RECEPTION_TIMESTAMP);
    const dds_entity_t topic = dds_create_topic(participant, desc, name, qos, nullptr);
    writer = dds_create_writer(participant, topic, qos, nullptr);
    dds_delete_qos(qos);
  }
  ~RawWriter() { dds_delete(participant); }
  RawWriter(const RawWriter&) = delete;
  RawWriter& operator=(const RawWriter&) = delete;
};

// The options of a mirror "m" on `domain` whose log lines are appended to `logs` (each with
// "\n"), under `mutex` (the mirror logs from its receive thread).
inline dds::MirrorOptions LoggingOptions(std::uint32_t domain, std::mutex& mutex,
                                         std::string& logs) {
  dds::MirrorOptions options;
  options.name = "m";
  options.domain = domain;
  options.log = [&mutex, &logs](const std::string& line) {
    std::lock_guard<std::mutex> lock(mutex);
    logs += line + "\n";
  };
  return options;
}

}  // namespace semgraph::dds_test
