// File: semgraph/semantics/primitives.h
//
// The geometric primitives of the geometric relations semantics (paper §III, Fig. 1), as
// strong ids over interned names:
//   Point             e      a point (origin of a frame, in the scene graph)
//   OrientationFrame  [a]    three orthonormal right-handed axes, no origin
//   Frame             {a}    point a plus orientation frame [a]: same name, same id
//   Body              C      a rigid body; frames, points and orientation frames are fixed to one
// A coordinate frame [r] is an OrientationFrame (it carries no body).
//
// Invariants: each primitive is one NameId; comparing two primitives of one kind compares ids
// (names are interned once, so equal names <=> equal ids). A Frame's point and orientation
// frame have the frame's id, which is how "point = origin of orientation frame" is checked.
// Cost: every operation is O(1), constexpr, noexcept; trivially copyable (4 bytes).
#pragma once

#include "semgraph/semantics/names.h"

namespace semgraph::semantics {

namespace internal {
template <class Tag>
class Primitive {
 public:
  constexpr Primitive() noexcept = default;
  constexpr explicit Primitive(NameId id) noexcept : id_(id) {}
  [[nodiscard]] constexpr NameId id() const noexcept { return id_; }
  [[nodiscard]] constexpr bool is_valid() const noexcept { return id_.is_valid(); }
  friend constexpr bool operator==(Primitive, Primitive) noexcept = default;

 private:
  NameId id_;
};
struct PointTag {};
struct OrientationFrameTag {};
struct BodyTag {};
}  // namespace internal

using Point = internal::Primitive<internal::PointTag>;
using OrientationFrame = internal::Primitive<internal::OrientationFrameTag>;
using Body = internal::Primitive<internal::BodyTag>;

/// Frame {a}: origin point a and orientation frame [a], both named a.
class Frame {
 public:
  constexpr Frame() noexcept = default;
  constexpr explicit Frame(NameId id) noexcept : id_(id) {}
  [[nodiscard]] constexpr NameId id() const noexcept { return id_; }
  [[nodiscard]] constexpr Point origin() const noexcept { return Point(id_); }
  [[nodiscard]] constexpr OrientationFrame axes() const noexcept { return OrientationFrame(id_); }
  [[nodiscard]] constexpr bool is_valid() const noexcept { return id_.is_valid(); }
  friend constexpr bool operator==(Frame, Frame) noexcept = default;

 private:
  NameId id_;
};

/// True when point e is the origin of orientation frame [a] (same name).
[[nodiscard]] constexpr bool IsOriginOf(Point e, OrientationFrame a) noexcept {
  return e.id() == a.id();
}

}  // namespace semgraph::semantics
