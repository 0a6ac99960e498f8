// Wrench names and terms, shared by the wrench adds (wrenches.cc) and queries
// (wrench_query.cc): name checks and resolution in the rules' order, the storage frame of a new
// pair, and the enumeration of the stored wrenches a query sums. Contract: wrenches.h.
// Cost: O(names) + O(W) per enumeration; noexcept, allocation-free.
#pragma once

#include <optional>

#include "semgraph/core/query_plan.h"
#include "semgraph/core/wrenches.h"

namespace semgraph::core::internal {

/// A wrench's names resolved: e, [r], C, D (D invalid: none given).
struct WrenchNodes {
  FrameIndex point, frame;
  BodyIndex on, by;
};

inline QueryError WrenchError(ErrorCode code, semantics::Field field, NameId name = {}) noexcept {
  QueryError e;
  e.code = code;
  e.field = field;
  e.name = name;
  return e;
}

/// invalid_name: every required name valid (point, coordinate frame, on; by when required or
/// given). An interned name is valid by the table's invariant.
inline std::optional<QueryError> CheckWrenchNames(const topology::SceneTopology& t,
                                                  const WrenchSpec& spec,
                                                  bool by_required) noexcept {
  using semantics::Field;
  const struct {
    std::string_view name;
    Field field;
    bool required;
  } fields[] = {{spec.on, Field::kBody, true},
                {spec.by, Field::kRefBody, by_required},
                {spec.point, Field::kPoint, true},
                {spec.coordinate_frame, Field::kCoordinateFrame, true}};
  for (const auto& f : fields) {
    if (f.name.empty() && !f.required) continue;
    if (t.names().Find(f.name).is_valid()) continue;
    if (!semantics::ValidateName(f.name)) return WrenchError(ErrorCode::kInvalidName, f.field);
  }
  return std::nullopt;
}

/// unknown_frame (point, then coordinate frame) -> unknown_body (on, then by) -> self_wrench.
/// Names valid (CheckWrenchNames passed).
inline std::optional<QueryError> ResolveWrenchNodes(const topology::SceneTopology& t,
                                                    const WrenchSpec& spec,
                                                    WrenchNodes& out) noexcept {
  using semantics::Field;
  const NameId e = t.names().Find(spec.point), r = t.names().Find(spec.coordinate_frame);
  out.point = t.FrameOfName(e);
  if (!out.point.is_valid()) return WrenchError(ErrorCode::kUnknownFrame, Field::kPoint, e);
  out.frame = t.FrameOfName(r);
  if (!out.frame.is_valid()) {
    return WrenchError(ErrorCode::kUnknownFrame, Field::kCoordinateFrame, r);
  }
  const NameId C = t.names().Find(spec.on);
  out.on = t.BodyOfName(C);
  if (!out.on.is_valid()) return WrenchError(ErrorCode::kUnknownBody, Field::kBody, C);
  out.by = BodyIndex();
  if (!spec.by.empty()) {
    const NameId D = t.names().Find(spec.by);
    out.by = t.BodyOfName(D);
    if (!out.by.is_valid()) return WrenchError(ErrorCode::kUnknownBody, Field::kRefBody, D);
    if (out.by == out.on) return WrenchError(ErrorCode::kSelfWrench, Field::kRefBody, D);
  }
  return std::nullopt;
}

/// The storage frame of a new pair (wrenches.h): the point if a frame of C, else [r] if a frame
/// of C, else C's frame made last in the point's pose tree (invalid: none).
inline FrameIndex ChooseWrenchFrame(const topology::SceneTopology& t,
                                    const WrenchNodes& n) noexcept {
  if (t.body_of(n.point) == n.on) return n.point;
  if (t.body_of(n.frame) == n.on) return n.frame;
  return t.SomeFrameOfBodyInTree(n.on, n.point);
}

/// The stored wrenches a query on C (by D, or by any body when D is invalid) sums, each passed
/// to f(slot index, sign, the other body): +1 for a wrench on C, -1 for the reaction of a
/// wrench by C. Returns how many. O(W).
template <class F>
std::size_t ForEachWrenchTerm(const WrenchStore& store, BodyIndex on, BodyIndex by, F&& f) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < store.slots.size(); ++i) {
    const WrenchSlot& s = store.slots[i];
    if (!s.live) continue;
    if (s.on == on && (!by.is_valid() || s.by == by)) {
      ++n;
      if (!f(static_cast<std::uint32_t>(i), 1.0, s.by)) return n;
    } else if (s.by == on && (!by.is_valid() || s.on == by)) {
      ++n;
      if (!f(static_cast<std::uint32_t>(i), -1.0, s.on)) return n;
    }
  }
  return n;
}

}  // namespace semgraph::core::internal
