// Internal to semgraph_dds and semgraph_ros_dds (and their tests): what both DDS layers need
// of Cyclone DDS alike, with no semgraph dependency, so that neither layer depends on the
// other (CMake target semgraph_dds_shared, header-only, never installed).
//   Entity  owns one DDS entity (participant, topic, reader, writer, waitset, condition) and
//           deletes it, with its children, on destruction.
#pragma once

#include <dds/dds.h>

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

}  // namespace semgraph::dds_shared
