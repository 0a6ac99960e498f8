// File: semgraph/base/index.h
//
// StrongIndex<Tag>: a dense std::uint32_t index made a distinct type by Tag, so a frame index
// cannot be passed where a body index or a name id is expected (the mix-up Drake's
// TypeSafeIndex exists for). The one id wrapper of the project: NameId, FrameIndex, BodyIndex
// and TwistEdgeIndex are all StrongIndex instances.
//
// Invariants: the value is either a dense index 0 .. n-1 into the owning structure or the
// sentinel kInvalid (max uint32), which is also the default. Construction from an integer is
// explicit. Indices are ordered by value, so they can key sorted containers.
// Cost: every operation is O(1), constexpr, noexcept; trivially copyable (4 bytes).
// Thread safety: plain values.
#pragma once

#include <compare>
#include <cstdint>
#include <limits>

namespace semgraph::base {

template <class Tag>
class StrongIndex {
 public:
  static constexpr std::uint32_t kInvalid = std::numeric_limits<std::uint32_t>::max();

  constexpr StrongIndex() noexcept = default;
  constexpr explicit StrongIndex(std::uint32_t value) noexcept : value_(value) {}

  [[nodiscard]] constexpr std::uint32_t value() const noexcept { return value_; }
  [[nodiscard]] constexpr bool is_valid() const noexcept { return value_ != kInvalid; }

  friend constexpr bool operator==(StrongIndex, StrongIndex) noexcept = default;
  friend constexpr auto operator<=>(StrongIndex, StrongIndex) noexcept = default;

 private:
  std::uint32_t value_ = kInvalid;
};

}  // namespace semgraph::base
