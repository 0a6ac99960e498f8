// Isolates the DDS traffic of one test process (and of the child processes it starts, which
// inherit its environment) from every other DDS application on the machine, e.g. the same
// tests run at the same time from another checkout, or ctest -j: before main, appends a
// discovery tag unique to this process to CYCLONEDDS_URI. Cyclone DDS ignores a remote
// participant whose tag differs (Discovery/Tag), so two processes on the same domain id only
// see each other when one started the other. The domain ids of the tests stay as they are:
// they keep the tests of one process apart when a binary runs them all.
// Include it in every test file that joins a DDS domain; it does its work when included.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

namespace semgraph::dds_test {

/// "semgraph-test-<pid>-<random hex>": unique among the processes of this machine (pid) and
/// across pid namespaces sharing its network (random, seeded from the device and the clock).
inline std::string UniqueDiscoveryTag() {
  std::random_device device;
  const auto now = std::chrono::steady_clock::now().time_since_epoch().count();
  std::mt19937_64 random((static_cast<std::uint64_t>(device()) << 32) ^
                         static_cast<std::uint64_t>(now));
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(random()));
  return "semgraph-test-" + std::to_string(getpid()) + "-" + hex;
}

/// Appends <Discovery><Tag>...</Tag></Discovery> to CYCLONEDDS_URI (a comma-separated list of
/// files and XML fragments); returns the tag.
inline std::string IsolateDds() {
  const std::string tag = UniqueDiscoveryTag();
  const char* uri = std::getenv("CYCLONEDDS_URI");
  std::string value = uri != nullptr && *uri != '\0' ? std::string(uri) + "," : std::string();
  value += "<Discovery><Tag>" + tag + "</Tag></Discovery>";
  setenv("CYCLONEDDS_URI", value.c_str(), 1);
  return tag;
}

/// This process's tag, set before main (before any DDS participant exists).
inline const std::string kDiscoveryTag = IsolateDds();

}  // namespace semgraph::dds_test
