// semgraph.ros.read_bag: a streaming iterator over a bag's transforms and joint states (ros.h).
// One record at a time from semgraph::ros's BagReader (memory: the reader's chunk plus one
// decoded message), decoded with messages.h's codecs; nothing is applied to any graph.
#include <pybind11/stl.h>

#include <atomic>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "common.h"
#include "docstrings.h"
#include "ros.h"
#include "semgraph/ros/messages.h"

namespace semgraph::python {

namespace {

struct TransformRecord {
  std::string topic;
  std::int64_t log_time_ns = 0;
  bool is_static = false;
  ros::TransformStamped transform;
};

struct JointStateRecord {
  std::string topic;
  std::int64_t log_time_ns = 0;
  ros::JointState state;
};

/// The iterator's state. `busy` refuses a second thread while one reads without the GIL (as a
/// generator does: "already executing").
struct BagRecords {
  std::string path;
  std::vector<std::string> topics;
  ros::BagReaderPtr reader;
  ros::BagRecord record;
  ros::TFMessage tf;  // the message being yielded, transform by transform
  std::string tf_topic;
  std::int64_t tf_log_time_ns = 0;
  std::size_t next_transform = 0;
  bool ended = false;  // the reader returned its end: later next() calls stop at once
  std::atomic<bool> busy{false};
};

bool Selected(const BagRecords& r, std::string_view topic) {
  for (const std::string& t : r.topics) {
    if (t == topic) return true;
  }
  return false;
}

std::string SecondsText(std::int64_t ns) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9f", Seconds(ns));
  return buf;
}

/// A record that does not decode: the loader's error (bag_loader.cc), code malformed.
template <class M>
std::optional<ros::BagError> Decode(const BagRecords& r, M& out) {
  const ros::BagRecord& rec = r.record;
  const auto decoded = rec.encoding == ros::MessageEncoding::kCdr ? ros::DecodeCdr(rec.data, out)
                                                                  : ros::DecodeRos1(rec.data, out);
  if (decoded) return std::nullopt;
  return ros::BagError{ros::BagErrorCode::kMalformed, r.path, 0,
                       "the " + std::string(rec.type_name) + " message on " +
                           std::string(rec.topic) + " at log time " + SecondsText(rec.log_time_ns) +
                           " s does not decode: " + ros::Describe(decoded.error())};
}

using Next = std::variant<std::monostate, TransformRecord, JointStateRecord, ros::BagError>;

/// The next record to yield (monostate: the end), read without the GIL.
Next ReadNext(BagRecords& r) {
  while (true) {
    if (r.next_transform < r.tf.transforms.size()) {
      return TransformRecord{r.tf_topic, r.tf_log_time_ns, r.tf_topic == "/tf_static",
                             std::move(r.tf.transforms[r.next_transform++])};
    }
    if (r.ended) return std::monostate{};
    const auto more = r.reader->Next(r.record);
    if (!more) return more.error();
    if (!*more) {
      r.ended = true;
      return std::monostate{};
    }
    const ros::BagRecord& rec = r.record;
    if (!Selected(r, rec.topic) || rec.encoding == ros::MessageEncoding::kOther) continue;
    if (rec.kind == ros::MessageKind::kTfMessage) {
      if (auto e = Decode(r, r.tf)) return *e;
      r.tf_topic.assign(rec.topic);
      r.tf_log_time_ns = rec.log_time_ns;
      r.next_transform = 0;
    } else if (rec.kind == ros::MessageKind::kJointState) {
      JointStateRecord js{std::string(rec.topic), rec.log_time_ns, {}};
      if (auto e = Decode(r, js.state)) return *e;
      return js;
    }
  }
}

py::object NextRecord(BagRecords& r) {
  if (r.busy.exchange(true)) throw py::value_error("read_bag(): already reading in another thread");
  Next next;
  {
    py::gil_scoped_release release;
    next = ReadNext(r);
  }
  r.busy.store(false);
  if (auto* t = std::get_if<TransformRecord>(&next)) return py::cast(std::move(*t));
  if (auto* j = std::get_if<JointStateRecord>(&next)) return py::cast(std::move(*j));
  if (auto* e = std::get_if<ros::BagError>(&next)) ThrowBag(*e);
  throw py::stop_iteration();
}

py::array_t<double> Doubles(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(double));
  return a;
}

Eigen::Quaterniond QuaternionOf(const ros::Quaternion& q) {
  return Eigen::Quaterniond(q.w, q.x, q.y, q.z);
}

constexpr const char* kTimesDoc = R"(
log_time      when the recorder received it, s (log_time_ns: exact int ns)
stamp         header.stamp, s (stamp_ns: exact int ns, sec * 10**9 + nanosec))";

void BindTransformRecord(py::module_& m) {
  py::class_<TransformRecord>(m, "TransformRecord",
                              Doc(R"(One transform of a TFMessage on /tf or /tf_static, as recorded
(not normalized, not checked: load_bag applies and checks).

topic         '/tf', '/tf_static' (or another selected topic of type TFMessage)
static        it came on /tf_static
parent        header.frame_id without its leading '/' (tf2's rule; the graph's name)
child         child_frame_id without its leading '/'
frame_id, child_frame_id   as the message spells them
translation   numpy (3,): the position of child's origin in parent
quaternion    numpy (4,) (w, x, y, z), semgraph's order; xyzw: ROS's order
rotation_matrix  numpy (3, 3) of the normalized quaternion)",
                                  kTimesDoc)
                                  .c_str())
      .def_readonly("topic", &TransformRecord::topic)
      .def_readonly("static", &TransformRecord::is_static)
      .def_readonly("log_time_ns", &TransformRecord::log_time_ns)
      .def_property_readonly("log_time",
                             [](const TransformRecord& r) { return Seconds(r.log_time_ns); })
      .def_property_readonly(
          "stamp_ns",
          [](const TransformRecord& r) { return ros::ToNanoseconds(r.transform.header.stamp); })
      .def_property_readonly("stamp",
                             [](const TransformRecord& r) {
                               return Seconds(ros::ToNanoseconds(r.transform.header.stamp));
                             })
      .def_property_readonly("frame_id",
                             [](const TransformRecord& r) { return r.transform.header.frame_id; })
      .def_property_readonly("child_frame_id",
                             [](const TransformRecord& r) { return r.transform.child_frame_id; })
      .def_property_readonly("parent",
                             [](const TransformRecord& r) {
                               return std::string(ros::LiftFrameName(r.transform.header.frame_id));
                             })
      .def_property_readonly("child",
                             [](const TransformRecord& r) {
                               return std::string(ros::LiftFrameName(r.transform.child_frame_id));
                             })
      .def_property_readonly("translation",
                             [](const TransformRecord& r) {
                               const ros::Vector3& t = r.transform.transform.translation;
                               return VectorArray(Eigen::Vector3d(t.x, t.y, t.z));
                             })
      .def_property_readonly("quaternion",
                             [](const TransformRecord& r) {
                               const ros::Quaternion& q = r.transform.transform.rotation;
                               const double wxyz[4] = {q.w, q.x, q.y, q.z};
                               return Array(wxyz, {4});
                             })
      .def_property_readonly("xyzw",
                             [](const TransformRecord& r) {
                               const ros::Quaternion& q = r.transform.transform.rotation;
                               const double xyzw[4] = {q.x, q.y, q.z, q.w};
                               return Array(xyzw, {4});
                             })
      .def_property_readonly(
          "rotation_matrix",
          [](const TransformRecord& r) {
            return MatrixArray(QuaternionOf(r.transform.transform.rotation).normalized());
          })
      .def("__repr__", [](const TransformRecord& r) {
        return "TransformRecord(topic='" + r.topic + "', parent='" +
               std::string(ros::LiftFrameName(r.transform.header.frame_id)) + "', child='" +
               std::string(ros::LiftFrameName(r.transform.child_frame_id)) +
               "', stamp_ns=" + std::to_string(ros::ToNanoseconds(r.transform.header.stamp)) + ")";
      });
}

}  // namespace

void BindRosRecords(py::module_& m) {
  BindTransformRecord(m);
  py::class_<JointStateRecord>(m, "JointStateRecord",
                               Doc(R"(One sensor_msgs/JointState message, as recorded.

topic         '/joint_states'
names         the joint names (list of str)
position, velocity, effort   numpy (n,) each, as many as the message has (may be empty))",
                                   kTimesDoc)
                                   .c_str())
      .def_readonly("topic", &JointStateRecord::topic)
      .def_readonly("log_time_ns", &JointStateRecord::log_time_ns)
      .def_property_readonly("log_time",
                             [](const JointStateRecord& r) { return Seconds(r.log_time_ns); })
      .def_property_readonly(
          "stamp_ns",
          [](const JointStateRecord& r) { return ros::ToNanoseconds(r.state.header.stamp); })
      .def_property_readonly("stamp",
                             [](const JointStateRecord& r) {
                               return Seconds(ros::ToNanoseconds(r.state.header.stamp));
                             })
      .def_property_readonly("names", [](const JointStateRecord& r) { return r.state.name; })
      .def_property_readonly("position",
                             [](const JointStateRecord& r) { return Doubles(r.state.position); })
      .def_property_readonly("velocity",
                             [](const JointStateRecord& r) { return Doubles(r.state.velocity); })
      .def_property_readonly("effort",
                             [](const JointStateRecord& r) { return Doubles(r.state.effort); })
      .def("__repr__", [](const JointStateRecord& r) {
        return "JointStateRecord(topic='" + r.topic +
               "', joints=" + std::to_string(r.state.name.size()) +
               ", stamp_ns=" + std::to_string(ros::ToNanoseconds(r.state.header.stamp)) + ")";
      });

  py::class_<BagRecords, std::shared_ptr<BagRecords>>(m, "BagRecords",
                                                      R"(The iterator read_bag returns: yields
TransformRecord (one per transform of each TFMessage) and JointStateRecord, in log-time order.)")
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__", &NextRecord)
      .def_property_readonly(
          "format",
          [](const BagRecords& r) { return std::string(ros::ToString(r.reader->format())); },
          "'mcap', 'rosbag2_sqlite3' or 'ros1'.")
      .def_readonly("path", &BagRecords::path);

  m.def(
      "read_bag",
      [](py::handle path, py::handle topics) {
        auto r = std::make_shared<BagRecords>();
        r->path = PathArg(path, "read_bag", "path");
        r->topics = TopicsArg(topics, "read_bag");
        std::optional<ros::BagError> error;
        {
          py::gil_scoped_release release;
          auto reader = ros::OpenBag(r->path);
          if (reader) {
            r->reader = std::move(*reader);
          } else {
            error = reader.error();
          }
        }
        if (error) ThrowBag(*error);
        return r;
      },
      py::arg("path"), py::kw_only(), py::arg("topics") = py::none(),
      R"(Iterates a bag's transforms and joint states, streaming (memory: one chunk of the bag and
one message, whatever the bag's size), in log-time order: one TransformRecord per transform of
each tf2_msgs/TFMessage, one JointStateRecord per sensor_msgs/JointState, on the selected topics
[('/tf', '/tf_static', '/joint_states')]; messages of other types are passed over.

path    an MCAP file, a rosbag2 sqlite3 .db3 file or bag folder, or a ROS 1 bag (by content)
Errors: BagError (file, byte offset, what is wrong) when the bag cannot be opened, and from
next() at the record that is corrupt (the records before it were yielded; later calls raise
the same error). Reads without the GIL.)");
}

}  // namespace semgraph::python
