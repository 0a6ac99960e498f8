// Error translation shared by the binding files (common.h): the core's error values raised as
// the exception classes of semgraph/_errors.py, with messages that name the edge at fault.
#include "common.h"

#include <exception>
#include <string>
#include <string_view>

#include "semgraph/coord/validate.h"

namespace semgraph::python {

namespace {
py::handle g_rejected_error;
py::handle g_query_error;
}  // namespace

void InitErrors(py::module_ errors) {
  // Kept for the life of the process (never decref'd: the interpreter may be finalizing when
  // static destructors run).
  g_rejected_error = py::object(errors.attr("RejectedError")).release();
  g_query_error = py::object(errors.attr("QueryError")).release();
  // A write to a graph another component writes (a ROS listener's; graph.h, WriterMutex).
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const GraphReadOnly&) {
      py::object exc = g_rejected_error(
          py::str("read_only"),
          py::str("write rejected (read_only): the graph is filled by a ROS listener, which is "
                  "its one writer; it is read-only from Python"));
      PyErr_SetObject(g_rejected_error.ptr(), exc.ptr());
    }
  });
}

void ThrowRejected(ErrorCode code, const std::string& message) {
  py::object exc = g_rejected_error(py::str(std::string(ToString(code))), py::str(message));
  PyErr_SetObject(g_rejected_error.ptr(), exc.ptr());
  throw py::error_already_set();
}

void ThrowRejected(const core::BuildError& error) {
  if (!error.discrepancy) ThrowRejected(error.code, error.message);
  py::object d = py::make_tuple(error.discrepancy->position, error.discrepancy->angle);
  py::object exc =
      g_rejected_error(py::str(std::string(ToString(error.code))), py::str(error.message), d);
  PyErr_SetObject(g_rejected_error.ptr(), exc.ptr());
  throw py::error_already_set();
}

void ThrowQuery(ErrorCode code, const std::string& message, const char* field,
                const char* argument) {
  py::object f = field ? py::object(py::str(field)) : py::object(py::none());
  py::object a = argument ? py::object(py::str(argument)) : py::object(py::none());
  py::object exc = g_query_error(py::str(std::string(ToString(code))), py::str(message), f, a);
  PyErr_SetObject(g_query_error.ptr(), exc.ptr());
  throw py::error_already_set();
}

void ThrowValue(const char* what, const std::string& context, const coord::Error& e,
                const semantics::NameTable& names) {
  ThrowRejected(e.code, std::string(what) + " " + context + " rejected (" +
                            std::string(ToString(e.code)) + "): " + coord::Describe(e, names));
}

std::string EdgeText(std::string_view wrt, std::string_view of) {
  return "of the pose edge {" + std::string(wrt) + "} -> {" + std::string(of) + "}";
}
std::string TwistEdgeText(std::string_view ref_body, std::string_view point) {
  return "of the twist edge " + std::string(ref_body) + " -> {" + std::string(point) + "}";
}

void ThrowRemoved(const char* what, const std::string& context) {
  ThrowRejected(ErrorCode::kNoSuchEdge, std::string(what) + " " + context +
                                            " rejected (no_such_edge): the edge was removed "
                                            "after the handle was made");
}

}  // namespace semgraph::python
