// File: python/src/docstrings.h
//
// Docstring parts shared by several binding files (the name keywords of poses, the rotation
// keywords), so that every method documents them in the same words.
#pragma once

#include <string>

namespace semgraph::python {

inline constexpr const char* kPoseNamesDoc = R"(
Names, by role (all keyword-only; a body may be omitted when its frame exists, and is checked
when given):
  of            the frame whose pose is meant: point = origin of `of`, orientation = [of]
  body          the body `of` (and point/orientation) are fixed to
  wrt           the reference frame: ref point = origin of `wrt`, ref orientation = [wrt],
                and the coordinate frame [wrt] unless expressed_in is given
  ref_body      the body `wrt` is fixed to
  point, orientation, ref_point, ref_orientation
                override the point / orientation frame / reference point / reference
                orientation frame set by `of` and `wrt` (the paper's non-frame forms)
  expressed_in  the coordinate frame [r] the result is expressed in)";

inline constexpr const char* kRotationDoc = R"(
Rotation, at most one of (identity when none is given):
  rotation         a quaternion (w, x, y, z) or a 3x3 rotation matrix, told apart by shape
  quaternion       (w, x, y, z), Hamilton convention, unit within 1e-6
  rotation_matrix  3x3, rows as written; its columns are the axes of [orientation] in
                   [ref_orientation]
  rpy              (roll, pitch, yaw) in radians, R = Rz(yaw) Ry(pitch) Rx(roll)
Numbers: lists, tuples or numpy arrays (converted to float64).)";

inline std::string Doc(const char* head, const char* tail = "") { return std::string(head) + tail; }

}  // namespace semgraph::python
