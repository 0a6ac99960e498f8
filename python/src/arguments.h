// File: python/src/arguments.h
//
// Conversion of Python arguments to the C++ API's types, with errors that name the function and
// the argument: TypeError for a wrong Python type ("pose(): of must be a str or None, not int"),
// ValueError for a wrong shape or a bad choice of keywords' values ("add_pose(): position must
// have 3 elements, got shape (2,)"). Whether the *numbers* are acceptable (finite, unit
// quaternion, proper rotation) is the scene graph's rule, checked by the C++ library and
// reported as RejectedError, as for every other caller of the library.
//
// Numbers are accepted as lists/tuples of int/float (read element by element, no numpy round
// trip) or as numpy arrays of a numeric dtype (converted to float64 when needed).
// Cost: O(elements); no allocation for lists, tuples and float64 arrays.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string_view>

namespace semgraph::python {

namespace py = pybind11;

/// A name: None -> "" (not given), str -> its UTF-8 text. The view is valid while `value` lives.
std::string_view NameArg(py::handle value, const char* function, const char* argument);

/// Reads exactly `size` numbers laid out with `rows` rows (rows == 1: a flat sequence of `size`;
/// rows > 1: `rows` sequences of size / rows) into out, row-major.
void NumbersArg(py::handle value, int rows, int size, double* out, const char* function,
                const char* argument);

/// A 3-vector; None -> zero.
Eigen::Vector3d Vector3Arg(py::handle value, const char* function, const char* argument);

/// A rotation given by at most one of four keywords (identity when none is given):
///   rotation=         a quaternion (w, x, y, z) (4 numbers) or a 3x3 matrix, told apart by shape
///   quaternion=       (w, x, y, z), Hamilton convention
///   rotation_matrix=  3x3, rows as written (columns: the axes of the frame in its reference)
///   rpy=              (roll, pitch, yaw) in radians, R = Rz(yaw) Ry(pitch) Rx(roll)
/// Two or more given: TypeError naming them.
struct RotationArg {
  bool is_matrix = false;
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
};
RotationArg RotationArgs(py::handle rotation, py::handle quaternion, py::handle rotation_matrix,
                         py::handle rpy, const char* function);

/// R = Rz(yaw) Ry(pitch) Rx(roll) as a quaternion (the scene script's rpy convention).
Eigen::Quaterniond QuaternionFromRpy(double roll, double pitch, double yaw);

/// `value` as a float64, C-contiguous array (a copy only when it is not one already): a numpy
/// array of a numeric dtype, or nested lists/tuples of numbers. The caller checks the shape.
py::array_t<double, py::array::c_style> FloatArrayArg(py::handle value, const char* function,
                                                      const char* argument);

/// "(2, 3)": a shape for messages.
std::string ShapeText(const py::array& array);

/// "int", "str", ...: the Python type name of `value`, for messages.
std::string TypeName(py::handle value);

}  // namespace semgraph::python
