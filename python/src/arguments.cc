#include "arguments.h"

#include <string>

namespace semgraph::python {

std::string TypeName(py::handle value) { return Py_TYPE(value.ptr())->tp_name; }

std::string ShapeText(const py::array& array) {
  std::string text = "(";
  for (py::ssize_t i = 0; i < array.ndim(); ++i) {
    if (i > 0) text += ", ";
    text += std::to_string(array.shape(i));
  }
  if (array.ndim() == 1) text += ",";
  return text + ")";
}

namespace {

[[noreturn]] void ThrowType(const char* function, const char* argument, const std::string& what,
                            py::handle value) {
  throw py::type_error(std::string(function) + "(): " + argument + " must be " + what + ", not " +
                       TypeName(value));
}

std::string ShapeWords(int rows, int size) {
  if (rows == 1) return std::to_string(size) + " numbers";
  return "a " + std::to_string(rows) + "x" + std::to_string(size / rows) + " matrix";
}

bool IsNumericArray(py::handle value) {
  if (!py::isinstance<py::array>(value)) return false;
  const char kind = py::reinterpret_borrow<py::array>(value).dtype().kind();
  return kind == 'f' || kind == 'i' || kind == 'u' || kind == 'b';
}

// Reads a flat list/tuple of exactly n numbers. False (and no Python error set) when the length
// is wrong; TypeError when an element is not a number.
bool ReadSequence(py::handle seq, int n, double* out, const char* function, const char* argument,
                  const std::string& what) {
  PyObject* fast = seq.ptr();
  const Py_ssize_t len = PySequence_Fast_GET_SIZE(fast);
  if (len != n) return false;
  PyObject** items = PySequence_Fast_ITEMS(fast);
  for (int i = 0; i < n; ++i) {
    PyObject* item = items[i];
    if (PyFloat_CheckExact(item)) {
      out[i] = PyFloat_AS_DOUBLE(item);
      continue;
    }
    if (PyUnicode_Check(item) || PyBytes_Check(item) || !(PyNumber_Check(item))) {
      ThrowType(function, argument, what, seq);
    }
    out[i] = PyFloat_AsDouble(item);
    if (out[i] == -1.0 && PyErr_Occurred()) {
      PyErr_Clear();
      ThrowType(function, argument, what, seq);
    }
  }
  return true;
}

}  // namespace

std::string_view NameArg(py::handle value, const char* function, const char* argument) {
  if (value.is_none()) return {};
  if (!PyUnicode_Check(value.ptr())) ThrowType(function, argument, "a str or None", value);
  Py_ssize_t size = 0;
  const char* text = PyUnicode_AsUTF8AndSize(value.ptr(), &size);
  if (text == nullptr) {  // lone surrogates cannot be encoded as UTF-8
    PyErr_Clear();
    throw py::value_error(std::string(function) + "(): " + argument + " is not encodable as UTF-8");
  }
  return {text, static_cast<std::size_t>(size)};
}

void NumbersArg(py::handle value, int rows, int size, double* out, const char* function,
                const char* argument) {
  const std::string what = ShapeWords(rows, size) + " (a list, tuple or numpy array)";
  const bool is_list = PyList_Check(value.ptr()) || PyTuple_Check(value.ptr());
  if (is_list) {
    const Py_ssize_t len = PySequence_Fast_GET_SIZE(value.ptr());
    if (rows == 1) {
      if (ReadSequence(value, size, out, function, argument, what)) return;
      throw py::value_error(std::string(function) + "(): " + argument + " must have " +
                            std::to_string(size) + " elements, got " + std::to_string(len));
    }
    const int cols = size / rows;
    if (len == rows) {
      PyObject** items = PySequence_Fast_ITEMS(value.ptr());
      bool ok = true;
      for (int r = 0; r < rows && ok; ++r) {
        py::handle row(items[r]);
        ok = (PyList_Check(row.ptr()) || PyTuple_Check(row.ptr())) &&
             ReadSequence(row, cols, out + r * cols, function, argument, what);
      }
      if (ok) return;
    }
    // Fall through to numpy for the message (it reports the shape it sees).
  } else if (py::array_t<double, py::array::c_style>::check_(value)) {
    // Fast path: already float64 and contiguous, read in place.
    const auto array = py::reinterpret_borrow<py::array_t<double, py::array::c_style>>(value);
    const bool shape_ok =
        rows == 1 ? (array.ndim() == 1 && array.shape(0) == size)
                  : (array.ndim() == 2 && array.shape(0) == rows && array.shape(1) == size / rows);
    if (shape_ok) {
      const double* data = array.data();
      for (int i = 0; i < size; ++i) out[i] = data[i];
      return;
    }
  } else if (!IsNumericArray(value)) {
    ThrowType(function, argument, what, value);
  }
  auto array = FloatArrayArg(value, function, argument);
  const bool shape_ok =
      rows == 1 ? (array.ndim() == 1 && array.shape(0) == size)
                : (array.ndim() == 2 && array.shape(0) == rows && array.shape(1) == size / rows);
  if (!shape_ok) {
    throw py::value_error(std::string(function) + "(): " + argument + " must be " +
                          ShapeWords(rows, size) + ", got shape " + ShapeText(array));
  }
  const double* data = array.data();
  for (int i = 0; i < size; ++i) out[i] = data[i];
}

Eigen::Vector3d Vector3Arg(py::handle value, const char* function, const char* argument) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  if (!value.is_none()) NumbersArg(value, 1, 3, v.data(), function, argument);
  return v;
}

Eigen::Quaterniond QuaternionFromRpy(double roll, double pitch, double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

RotationArg RotationArgs(py::handle rotation, py::handle quaternion, py::handle rotation_matrix,
                         py::handle rpy, const char* function) {
  const char* given[4];
  int n = 0;
  if (!rotation.is_none()) given[n++] = "rotation";
  if (!quaternion.is_none()) given[n++] = "quaternion";
  if (!rotation_matrix.is_none()) given[n++] = "rotation_matrix";
  if (!rpy.is_none()) given[n++] = "rpy";
  RotationArg out;
  if (n == 0) return out;
  if (n > 1) {
    std::string names;
    for (int i = 0; i < n; ++i) names += std::string(i ? ", " : "") + given[i] + "=";
    throw py::type_error(std::string(function) +
                         "(): give at most one of rotation=, quaternion=, rotation_matrix=, "
                         "rpy=; got " +
                         names);
  }
  double wxyz[4];
  if (!quaternion.is_none()) {
    NumbersArg(quaternion, 1, 4, wxyz, function, "quaternion");
    out.q = Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
  } else if (!rotation_matrix.is_none()) {
    double m[9];
    NumbersArg(rotation_matrix, 3, 9, m, function, "rotation_matrix");
    out.is_matrix = true;
    out.R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(m);
  } else if (!rpy.is_none()) {
    double angles[3];
    NumbersArg(rpy, 1, 3, angles, function, "rpy");
    out.q = QuaternionFromRpy(angles[0], angles[1], angles[2]);
  } else {
    // rotation=: 4 numbers are a quaternion, 3 rows of 3 a matrix.
    const bool is_list = PyList_Check(rotation.ptr()) || PyTuple_Check(rotation.ptr());
    bool matrix = false;
    if (is_list) {
      const Py_ssize_t len = PySequence_Fast_GET_SIZE(rotation.ptr());
      matrix = len == 3;
    } else if (IsNumericArray(rotation)) {
      matrix = py::reinterpret_borrow<py::array>(rotation).ndim() == 2;
    } else {
      ThrowType(function, "rotation",
                "a quaternion (w, x, y, z) or a 3x3 rotation matrix (a list, tuple or numpy "
                "array)",
                rotation);
    }
    if (matrix) {
      double m[9];
      NumbersArg(rotation, 3, 9, m, function, "rotation");
      out.is_matrix = true;
      out.R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(m);
    } else {
      NumbersArg(rotation, 1, 4, wxyz, function, "rotation");
      out.q = Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
    }
  }
  return out;
}

py::array_t<double, py::array::c_style> FloatArrayArg(py::handle value, const char* function,
                                                      const char* argument) {
  const char* what = "numeric (a numpy array of numbers, or lists of numbers)";
  py::object object = py::reinterpret_borrow<py::object>(value);
  if (!py::isinstance<py::array>(value)) {
    if (PyUnicode_Check(value.ptr()) || PyBytes_Check(value.ptr())) {
      ThrowType(function, argument, what, value);
    }
    try {
      object = py::module_::import("numpy").attr("asarray")(value);
    } catch (py::error_already_set& e) {  // ragged nesting
      throw py::value_error(std::string(function) + "(): " + argument +
                            " is not a regular array of numbers: " + e.what());
    }
  }
  // Checked before converting: numpy would turn strings such as "1" into numbers.
  if (!IsNumericArray(object)) ThrowType(function, argument, what, value);
  auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!array) {
    PyErr_Clear();
    ThrowType(function, argument, what, value);
  }
  return array;
}

}  // namespace semgraph::python
