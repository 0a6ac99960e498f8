// File: semgraph/semantics/describe.h
//
// Text for people, formatted off the hot path (allocates): semantics in the paper's notation
// and Mismatch messages. Names come from the NameTable that interned them.
#pragma once

#include <string>

#include "semgraph/semantics/export.h"
#include "semgraph/semantics/mismatch.h"
#include "semgraph/semantics/names.h"
#include "semgraph/semantics/relations.h"

namespace semgraph::semantics {

/// "PositionCoord(e|C, f|D, [r])"
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string Describe(const PositionSemantics& s,
                                                             const NameTable& names);
/// "OrientationCoord([a]|C, [b]|D, [r])"
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string Describe(const OrientationSemantics& s,
                                                             const NameTable& names);
/// "PoseCoord((e,[a])|C, (f,[b])|D, [r])", or "PoseCoord({a}|C, {b}|D, [r])" in frame form.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string Describe(const PoseSemantics& s,
                                                             const NameTable& names);
/// "LinearVelocityCoord(e|C, D, [r])"
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string Describe(const LinearVelocitySemantics& s,
                                                             const NameTable& names);
/// "AngularVelocityCoord(C, D, [r])"
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string Describe(const AngularVelocitySemantics& s,
                                                             const NameTable& names);
/// "TwistCoord(e|C, D, [r])"
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string Describe(const TwistSemantics& s,
                                                             const NameTable& names);
/// "AccelerationCoord(e|C, D, [r])"
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string Describe(const AccelerationSemantics& s,
                                                             const NameTable& names);
/// "WrenchCoord(e|C, D, [r])" (on C by D), or "WrenchCoord(e|C, several, [r])" for a sum of
/// wrenches by several bodies.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string Describe(const WrenchSemantics& s,
                                                             const NameTable& names);
/// "Power(C, D)": the power delivered to C by D.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string Describe(const PowerSemantics& s,
                                                             const NameTable& names);
/// "compose: reference point f|D of the first does not match point g|D of the second"
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string Describe(const Mismatch& m,
                                                             const NameTable& names);

/// One side of a mismatch: "reference point f|D of the first". A wrench's body fields read
/// "on body C" and "by body D" ("by several bodies" for a sum).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string Describe(const MismatchSide& side,
                                                             const NameTable& names);

/// "compose", "change_point", ...
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string_view ToString(Operation op) noexcept;
/// The role name of a field, e.g. "reference orientation frame": the one table of role names,
/// used by every message that names an argument.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT std::string_view FieldName(Field f) noexcept;

}  // namespace semgraph::semantics
