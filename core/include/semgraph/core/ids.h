// File: semgraph/core/ids.h
//
// Strong index types of the core layer: FrameIndex (a node of the pose forest) and BodyIndex
// (a body node). Both wrap a dense std::uint32_t index and are distinct types, so a frame index
// cannot be passed where a body index is expected (the mix-up Drake's TypeSafeIndex exists for).
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

namespace semgraph::core {

namespace internal {

/// A dense uint32 index, made a distinct type by Tag. Default-constructed indices are invalid.
template <class Tag>
class Index {
 public:
  static constexpr std::uint32_t kInvalid = std::numeric_limits<std::uint32_t>::max();

  constexpr Index() noexcept = default;
  constexpr explicit Index(std::uint32_t value) noexcept : value_(value) {}

  [[nodiscard]] constexpr std::uint32_t value() const noexcept { return value_; }
  [[nodiscard]] constexpr bool is_valid() const noexcept { return value_ != kInvalid; }

  friend constexpr bool operator==(Index, Index) noexcept = default;
  friend constexpr auto operator<=>(Index, Index) noexcept = default;

 private:
  std::uint32_t value_ = kInvalid;
};

struct FrameTag {};
struct BodyTag {};

}  // namespace internal

/// A frame node of the pose forest.
using FrameIndex = internal::Index<internal::FrameTag>;
/// A body node.
using BodyIndex = internal::Index<internal::BodyTag>;

static_assert(sizeof(FrameIndex) == sizeof(std::uint32_t));
static_assert(sizeof(BodyIndex) == sizeof(std::uint32_t));

}  // namespace semgraph::core
