// semgraph.ros: bags into a graph (load_bag, check_bag), `bag info` (bag_info), the findings
// (Finding) and BagError (ros.h). The semantics are those of semgraph::ros::ScanBag / ApplyBag,
// as the tool's `semgraph bag check` and the `bag` script op use them (docs/ros.md).
#include <pybind11/stl.h>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common.h"
#include "docstrings.h"
#include "ros.h"
#include "semgraph/models/urdf.h"
#include "timed.h"

namespace semgraph::python {

void ThrowBag(const ros::BagError& error) {
  py::object cls = py::module_::import("semgraph._errors").attr("BagError");
  py::object exc = cls(py::str(std::string(ros::ToString(error.code))), py::str(error.file),
                       py::int_(error.offset), py::str(error.message));
  PyErr_SetObject(cls.ptr(), exc.ptr());
  throw py::error_already_set();
}

std::string PathArg(py::handle path, const char* function, const char* argument) {
  if (!py::isinstance<py::str>(path)) {
    py::object text;
    try {
      text = py::module_::import("os").attr("fspath")(path);
    } catch (py::error_already_set&) {
      text = py::none();
    }
    if (!py::isinstance<py::str>(text)) {
      throw py::type_error(std::string(function) + "(): " + argument +
                           " must be a str or os.PathLike of str, not " + TypeName(path));
    }
    return text.cast<std::string>();
  }
  return path.cast<std::string>();
}

std::vector<std::string> TopicsArg(py::handle topics, const char* function) {
  if (topics.is_none()) return ros::DefaultBagTopics();
  if (py::isinstance<py::str>(topics) || !py::isinstance<py::sequence>(topics)) {
    throw py::type_error(std::string(function) + "(): topics must be a sequence of str, not " +
                         TypeName(topics));
  }
  std::vector<std::string> out;
  for (py::handle t : topics) out.emplace_back(NameArg(t, function, "topics"));
  return out;
}

ros::LiftOptions LiftArgs(py::handle static_mode, py::handle bodies, const char* function) {
  ros::LiftOptions lift;
  const std::string_view mode = NameArg(static_mode, function, "static");
  if (!mode.empty()) {
    const auto parsed = ros::StaticModeFromString(mode);
    if (!parsed) {
      throw py::value_error(std::string(function) +
                            "(): static must be 'same_body' or 'own_body', not '" +
                            std::string(mode) + "'");
    }
    lift.static_mode = *parsed;
  }
  if (!bodies.is_none()) {
    if (!py::isinstance<py::dict>(bodies)) {
      throw py::type_error(std::string(function) +
                           "(): bodies must be a dict {body: [frame, ...]}, not " +
                           TypeName(bodies));
    }
    for (auto [body, frames] : py::reinterpret_borrow<py::dict>(bodies)) {
      std::vector<std::string>& list = lift.bodies[std::string(NameArg(body, function, "bodies"))];
      if (py::isinstance<py::str>(frames) || !py::isinstance<py::sequence>(frames)) {
        throw py::type_error(std::string(function) +
                             "(): each body of bodies must map to a list of frame names");
      }
      for (py::handle f : frames) list.emplace_back(NameArg(f, function, "bodies"));
    }
  }
  if (auto plan = ros::BodyPlan::Make(lift); !plan) {
    throw py::value_error(std::string(function) + "(): bodies: " + plan.error());
  }
  return lift;
}

ros::PoseTopicsMap PoseTopicsArg(py::handle pose_topics, const char* function) {
  ros::PoseTopicsMap out;
  if (pose_topics.is_none()) return out;
  if (!py::isinstance<py::dict>(pose_topics)) {
    throw py::type_error(std::string(function) +
                         "(): pose_topics must be a dict {topic: frame}, not " +
                         TypeName(pose_topics));
  }
  for (auto [topic, frame] : py::reinterpret_borrow<py::dict>(pose_topics)) {
    const std::string_view t = NameArg(topic, function, "pose_topics");
    const std::string_view f = NameArg(frame, function, "pose_topics");
    if (t.empty() || f.empty()) {
      throw py::value_error(std::string(function) + "(): pose_topics: an empty " +
                            (t.empty() ? "topic" : "frame for '" + std::string(t) + "'"));
    }
    out.emplace(std::string(t), std::string(f));
  }
  return out;
}

namespace {

struct BagReportObject {
  GraphPtr graph;
  ros::BagLoadReport report;
};

struct BagFrame {
  std::string name;
  std::optional<std::string> parent;
  bool is_static = false;
  std::string body;
  int depth = 0;
};

struct BagInfoObject {
  std::string path;
  ros::BagScan scan;
  std::vector<BagFrame> frames;
};

py::object OptionalSeconds(bool present, std::int64_t ns) {
  return present ? py::object(py::float_(Seconds(ns))) : py::object(py::none());
}
py::object OptionalNs(bool present, std::int64_t ns) {
  return present ? py::object(py::int_(ns)) : py::object(py::none());
}

/// The time options of a new graph for a bag (as `semgraph bag check`): linear interpolation
/// (tf2's), a window over all of the bag's stamps unless window= is given.
core::TimeOptions NewGraphTime(const ros::BagScan& scan, const std::optional<std::int64_t>& window,
                               const std::optional<std::size_t>& capacity) {
  core::TimeOptions time;
  const std::int64_t span = scan.has_stamps ? scan.last_stamp_ns - scan.first_stamp_ns : 0;
  time.window = core::Duration::Nanoseconds(window ? *window : span + 1'000'000'000);
  time.interpolation = core::Interpolation::kLinear;
  if (capacity) time.sample_capacity = *capacity;
  return time;
}

BagReportObject LoadBag(py::handle path, py::handle graph, py::handle topics,
                        py::handle static_mode, py::handle bodies, py::handle pose_topics,
                        py::handle urdf, py::handle start, py::handle end, py::handle window,
                        py::handle sample_capacity, const char* fn) {
  const std::string file = PathArg(path, fn, "path");
  ros::BagLoadOptions options;
  options.topics = TopicsArg(topics, fn);
  options.lift = LiftArgs(static_mode, bodies, fn);
  options.lift.pose_topics = PoseTopicsArg(pose_topics, fn);
  if (!start.is_none()) options.start_ns = NanosecondsArg(start, fn, "start", false);
  if (!end.is_none()) options.end_ns = NanosecondsArg(end, fn, "end", false);
  const std::string urdf_file = urdf.is_none() ? std::string() : PathArg(urdf, fn, "urdf");
  std::optional<std::int64_t> window_ns;
  std::optional<std::size_t> capacity;
  GraphPtr box;
  if (!graph.is_none()) {
    if (!window.is_none() || !sample_capacity.is_none()) {
      throw py::value_error(std::string(fn) +
                            "(): window= and sample_capacity= are the time options of a new "
                            "graph; graph= has its own");
    }
    if (!py::isinstance<GraphBox>(graph)) {
      throw py::type_error(std::string(fn) + "(): graph must be a SceneGraph or None, not " +
                           TypeName(graph));
    }
    box = graph.cast<GraphPtr>();
  }
  if (!window.is_none()) window_ns = NanosecondsArg(window, fn, "window", false);
  if (!sample_capacity.is_none()) {
    if (PyBool_Check(sample_capacity.ptr()) || !PyIndex_Check(sample_capacity.ptr())) {
      throw py::type_error(std::string(fn) + "(): sample_capacity must be an int, not " +
                           TypeName(sample_capacity));
    }
    const auto n = sample_capacity.cast<long long>();
    capacity = n < 0 ? 0 : static_cast<std::size_t>(n);  // below 2: the core refuses it
  }
  std::optional<ros::BagError> bag_error;
  std::optional<core::BuildError> build_error;
  BagReportObject out;
  {
    py::gil_scoped_release release;
    auto scan = ros::ScanBag(file, options);  // a corrupt bag fails here: nothing applied
    if (!scan) {
      bag_error = scan.error();
    } else if (!box) {
      auto made = QuaternionGraph::Create(NewGraphTime(*scan, window_ns, capacity));
      if (made) {
        box = std::make_shared<GraphBox>(false, std::move(*made));
      } else {
        build_error = made.error();
      }
    }
    if (box && scan) {
      std::lock_guard<WriterMutex> lock(box->writer);
      box->Visit([&](auto& g) {
        std::optional<models::Robot> robot;
        if (!urdf_file.empty()) {
          auto loaded = models::LoadUrdfFile(g, urdf_file);
          if (!loaded) {
            build_error = loaded.error();
            return;
          }
          robot = std::move(*loaded);
        }
        auto report = ros::ApplyBag(g, file, *scan, options, robot ? &*robot : nullptr);
        if (report) {
          out.report = std::move(*report);
        } else {
          bag_error = report.error();
        }
      });
    }
  }
  if (bag_error) ThrowBag(*bag_error);
  if (build_error) ThrowRejected(*build_error);
  out.graph = box;
  return out;
}

/// The frame tree of a scan, in the order `semgraph bag info` prints it: each root (in name
/// order), then its children depth first; a frame's first parent only (a second one is a
/// finding of check_bag).
std::vector<BagFrame> FrameTree(const ros::BagScan& scan) {
  std::map<std::string, std::vector<std::pair<std::string, bool>>> children;
  std::map<std::string, bool> has_parent;
  for (const auto& [edges, is_static] : {std::pair{&scan.statics, true}, {&scan.dynamics, false}}) {
    for (const ros::StaticEdge& e : *edges) {
      if (has_parent[e.child]) continue;
      has_parent[e.child] = true;
      children[e.parent].emplace_back(e.child, is_static);
      has_parent.try_emplace(e.parent, false);
    }
  }
  auto plan = ros::BodyPlan::Make({});
  for (const ros::StaticEdge& e : scan.statics) plan->AddStatic(e.parent, e.child);
  const ros::BodyPlan::ExistingBody none;
  std::vector<BagFrame> out;
  std::function<void(const std::string&, const std::string*, bool, int)> visit =
      [&](const std::string& f, const std::string* parent, bool is_static, int depth) {
        out.push_back(BagFrame{f, parent ? std::optional<std::string>(*parent) : std::nullopt,
                               is_static, plan->BodyOf(f, none), depth});
        if (depth > 1000) return;  // a loop below a root cannot be reached (one parent each)
        for (const auto& [c, s] : children[f]) visit(c, &f, s, depth + 1);
      };
  for (const auto& [f, parent] : has_parent) {
    if (!parent) visit(f, nullptr, false, 0);
  }
  return out;
}

BagInfoObject BagInfo(py::handle path) {
  BagInfoObject out;
  out.path = PathArg(path, "bag_info", "path");
  std::optional<ros::BagError> error;
  {
    py::gil_scoped_release release;
    auto scan = ros::ScanBag(out.path, ros::BagLoadOptions{});
    if (scan) {
      out.scan = std::move(*scan);
      out.frames = FrameTree(out.scan);
    } else {
      error = scan.error();
    }
  }
  if (error) ThrowBag(*error);
  return out;
}

constexpr const char* kLoadOptionsDoc = R"(
path             an MCAP file, a rosbag2 sqlite3 .db3 file or bag folder, or a ROS 1 bag (the
                 format is told by content, as `semgraph bag` does); str or os.PathLike
topics           the topics read [('/tf', '/tf_static', '/joint_states')]; add
                 '/robot_description' to load the bag's URDF (it then covers the joints' tf)
static           'same_body' [default]: frames joined by /tf_static are one rigid body
                 (constant poses); 'own_body': every frame its own body, a static transform a
                 timeless inter-body pose (docs/ros.md, "Frames and bodies")
bodies           {body: [frame, ...]}: frames listed lie on the listed body
pose_topics      {topic: frame}: read these topics too; their PoseWithCovarianceStamped
                 messages give the pose of `frame` wrt the header frame, a stamped sample with
                 its covariance (an Odometry topic needs only topics=: it names its child frame);
                 a bad covariance (NaN, not symmetric, not PSD) is a finding
urdf             a URDF file loaded into the graph first: its joints cover the tf transforms
                 between their link frames, compared with its forward kinematics
                 (model_mismatch when they differ)
start, end       a log-time window (int ns or float s, inclusive); static transforms apply
                 whatever their log time
Errors: a bag that cannot be read or is corrupt raises BagError (file, byte offset, what is
wrong) before anything is applied: the bag is read to its end once (decoding every selected
message) before the first transform is applied. A bad URDF raises RejectedError (nothing of
the bag applied). Runs without the GIL.)";

void BindFinding(py::module_& m) {
  py::class_<FindingObject>(m, "Finding", R"(One finding group of the tf checker (docs/ros.md,
"Findings"): transforms refused by the graph, or covered by the robot model and different from
it, grouped by (code, parent, child). Times: float seconds; *_ns: exact int nanoseconds.)")
      .def_property_readonly(
          "code", [](const FindingObject& f) { return std::string(f.group.code.name()); },
          "The snake_case code, e.g. 'multiple_pose_parents', 'model_mismatch'.")
      .def_property_readonly(
          "topic", [](const FindingObject& f) { return f.group.topic; },
          "The topic of the first occurrence.")
      .def_property_readonly(
          "parent", [](const FindingObject& f) { return f.group.parent; },
          "The parent frame (header.frame_id, lifted); '' for a joint state.")
      .def_property_readonly(
          "child", [](const FindingObject& f) { return f.group.child; },
          "The child frame (child_frame_id, lifted); '' for a joint state.")
      .def_property_readonly(
          "count", [](const FindingObject& f) { return f.group.count; }, "Occurrences.")
      .def_property_readonly(
          "first_log_time",
          [](const FindingObject& f) { return Seconds(f.group.first_log_time_ns); },
          "Log (or receive) time of the first occurrence, s.")
      .def_property_readonly("first_log_time_ns",
                             [](const FindingObject& f) { return f.group.first_log_time_ns; })
      .def_property_readonly(
          "last_log_time", [](const FindingObject& f) { return Seconds(f.group.last_log_time_ns); },
          "Log (or receive) time of the last occurrence, s.")
      .def_property_readonly("last_log_time_ns",
                             [](const FindingObject& f) { return f.group.last_log_time_ns; })
      .def_property_readonly(
          "first_stamp", [](const FindingObject& f) { return Seconds(f.group.first_stamp_ns); },
          "Header stamp of the first occurrence, s.")
      .def_property_readonly("first_stamp_ns",
                             [](const FindingObject& f) { return f.group.first_stamp_ns; })
      .def_property_readonly(
          "last_stamp", [](const FindingObject& f) { return Seconds(f.group.last_stamp_ns); },
          "Header stamp of the last occurrence, s.")
      .def_property_readonly("last_stamp_ns",
                             [](const FindingObject& f) { return f.group.last_stamp_ns; })
      .def_property_readonly(
          "message", [](const FindingObject& f) { return f.group.message; },
          "What was refused and why (the first occurrence).")
      .def(
          "to_json", [](const FindingObject& f) { return ros::ToJsonLine(f.group); },
          "The JSON line `semgraph bag check` prints for this group.")
      .def("__repr__", [](const FindingObject& f) {
        return "Finding(code='" + std::string(f.group.code.name()) + "', parent='" +
               f.group.parent + "', child='" + f.group.child +
               "', count=" + std::to_string(f.group.count) + ")";
      });
}

/// The lift's counts of a BagReport (ros::LiftCounts), one property each.
struct CountProperty {
  const char* name;
  std::uint64_t ros::LiftCounts::*field;
  const char* doc;
};
constexpr CountProperty kCountProperties[] = {
    {"transforms", &ros::LiftCounts::transforms, "Transforms seen (applied + refused + covered)."},
    {"applied", &ros::LiftCounts::applied, "Transforms added or updated."},
    {"refused", &ros::LiftCounts::refused, "Transforms the graph refused (each a finding)."},
    {"covered", &ros::LiftCounts::covered, "Transforms covered by the robot model (equal or not)."},
    {"mismatched", &ros::LiftCounts::mismatched,
     "Covered transforms that differ from the model (model_mismatch)."},
    {"normalized", &ros::LiftCounts::normalized,
     "Quaternions off unit by more than 1e-6 (within tf2's 0.01), normalized."},
    {"joint_states", &ros::LiftCounts::joint_states, "Joint state messages applied."},
    {"joint_states_refused", &ros::LiftCounts::joint_states_refused,
     "Joint state messages refused (each a finding)."},
    {"joint_states_skipped", &ros::LiftCounts::joint_states_skipped,
     "Joint state messages skipped: the graph has no joints."},
    {"poses_with_covariance", &ros::LiftCounts::poses_with_covariance,
     "PoseWithCovarianceStamped messages applied (pose_topics)."},
    {"odometry", &ros::LiftCounts::odometry, "Odometry messages applied (pose and twist)."},
    {"covariance_refused", &ros::LiftCounts::covariance_refused,
     "PoseWithCovarianceStamped and Odometry messages refused (each a finding)."},
};

void BindBagReport(py::module_& m) {
  py::class_<BagReportObject> report(m, "BagReport",
                                     R"(What load_bag / check_bag did: the graph, the
findings and the counts (those of the `bag` script op and `semgraph bag check`).)");
  report
      .def_property_readonly(
          "graph", [](const BagReportObject& r) { return r.graph; },
          "The SceneGraph the bag was applied to (all queries work, time queries included).")
      .def_property_readonly(
          "findings",
          [](const BagReportObject& r) {
            std::vector<FindingObject> out;
            for (const auto& g : r.report.findings.groups()) out.push_back({g});
            return out;
          },
          "The finding groups, in the order of their first occurrence (a list of Finding).")
      .def_property_readonly(
          "ok", [](const BagReportObject& r) { return r.report.findings.empty(); }, "No finding.")
      .def_property_readonly(
          "exit_status", [](const BagReportObject& r) { return r.report.findings.empty() ? 0 : 1; },
          "`semgraph bag check`'s exit status: 0 clean, 1 findings (2, an unreadable bag, is "
          "BagError).")
      .def_property_readonly(
          "findings_total", [](const BagReportObject& r) { return r.report.findings.total(); },
          "Occurrences over all groups.")
      .def_property_readonly(
          "messages", [](const BagReportObject& r) { return r.report.messages; },
          "Messages read on the selected topics within the window.")
      .def_property_readonly(
          "skipped", [](const BagReportObject& r) { return r.report.skipped; },
          "The bag's other messages.")
      .def_property_readonly(
          "start",
          [](const BagReportObject& r) {
            return OptionalSeconds(r.report.messages > 0, r.report.first_log_time_ns);
          },
          "The first log time read, s (None: no message).")
      .def_property_readonly("start_ns",
                             [](const BagReportObject& r) {
                               return OptionalNs(r.report.messages > 0, r.report.first_log_time_ns);
                             })
      .def_property_readonly(
          "end",
          [](const BagReportObject& r) {
            return OptionalSeconds(r.report.messages > 0, r.report.last_log_time_ns);
          },
          "The last log time read, s (None: no message).")
      .def_property_readonly("end_ns",
                             [](const BagReportObject& r) {
                               return OptionalNs(r.report.messages > 0, r.report.last_log_time_ns);
                             })
      .def_property_readonly(
          "loaded_robot_description",
          [](const BagReportObject& r) { return r.report.loaded_robot_description; },
          "The bag's /robot_description was loaded and covers the joints' transforms.")
      .def_property_readonly(
          "summary",
          [](const BagReportObject& r) {
            py::dict d;
            d["summary"] = true;
            d["messages"] = r.report.messages;
            d["transforms"] = r.report.counts.transforms;
            d["findings"] = r.report.findings.total();
            d["groups"] = r.report.findings.groups().size();
            return d;
          },
          "The summary line of `semgraph bag check`, as a dict.")
      .def("__repr__", [](const BagReportObject& r) {
        return "BagReport(messages=" + std::to_string(r.report.messages) +
               ", transforms=" + std::to_string(r.report.counts.transforms) +
               ", findings=" + std::to_string(r.report.findings.groups().size()) + ")";
      });

  for (const CountProperty& c : kCountProperties) {
    report.def_property_readonly(
        c.name, [field = c.field](const BagReportObject& r) { return r.report.counts.*field; },
        c.doc);
  }
}

void BindBagInfo(py::module_& m) {
  py::class_<ros::TopicSummary>(m, "BagTopic", "A topic of a bag, as bag_info counted it.")
      .def_property_readonly(
          "name", [](const ros::TopicSummary& t) { return t.topic.name; }, "e.g. '/tf'.")
      .def_property_readonly(
          "type", [](const ros::TopicSummary& t) { return t.topic.type_name; },
          "The type as the bag spells it, e.g. 'tf2_msgs/msg/TFMessage'.")
      .def_property_readonly(
          "encoding",
          [](const ros::TopicSummary& t) { return std::string(ros::ToString(t.topic.encoding)); },
          "'cdr', 'ros1' or 'other'.")
      .def_property_readonly(
          "messages", [](const ros::TopicSummary& t) { return t.messages; }, "Messages read.")
      .def("__repr__", [](const ros::TopicSummary& t) {
        return "BagTopic(name='" + t.topic.name + "', type='" + t.topic.type_name +
               "', messages=" + std::to_string(t.messages) + ")";
      });

  py::class_<BagFrame>(m, "BagFrame", "A frame of a bag's tf tree, as bag_info lists it.")
      .def_readonly("name", &BagFrame::name, "The frame (lifted: no leading '/').")
      .def_readonly("parent", &BagFrame::parent, "Its first tf parent (None: a root).")
      .def_readonly("static", &BagFrame::is_static,
                    "Its parent's transform came on /tf_static ('=' in `bag info`).")
      .def_readonly("body", &BagFrame::body,
                    "The body check_bag puts it on (mode same_body, no bodies map).")
      .def_readonly("depth", &BagFrame::depth, "0 for a root.")
      .def("__repr__", [](const BagFrame& f) {
        return "BagFrame(name='" + f.name +
               "', parent=" + (f.parent ? "'" + *f.parent + "'" : "None") +
               ", static=" + (f.is_static ? "True" : "False") + ", body='" + f.body + "')";
      });

  py::class_<BagInfoObject>(m, "BagInfo", R"(What `semgraph bag info` prints: the format, the
topics, the time ranges and the tf frame tree with each frame's body. Times: float s; *_ns: int
ns; None when the bag has no message (log times) or no transform or joint state (stamps).)")
      .def_readonly("path", &BagInfoObject::path)
      .def_property_readonly(
          "format",
          [](const BagInfoObject& i) { return std::string(ros::ToString(i.scan.format)); },
          "'mcap', 'rosbag2_sqlite3' or 'ros1'.")
      .def_property_readonly(
          "messages", [](const BagInfoObject& i) { return i.scan.records; },
          "Every message of the bag.")
      .def_property_readonly(
          "topics", [](const BagInfoObject& i) { return i.scan.topics; },
          "The topics (a list of BagTopic), in the order first seen.")
      .def_property_readonly(
          "frames", [](const BagInfoObject& i) { return i.frames; },
          "The tf tree (a list of BagFrame): each root in name order, then its children depth "
          "first.")
      .def_property_readonly("first_log_time",
                             [](const BagInfoObject& i) {
                               return OptionalSeconds(i.scan.records > 0, i.scan.first_log_time_ns);
                             })
      .def_property_readonly("first_log_time_ns",
                             [](const BagInfoObject& i) {
                               return OptionalNs(i.scan.records > 0, i.scan.first_log_time_ns);
                             })
      .def_property_readonly("last_log_time",
                             [](const BagInfoObject& i) {
                               return OptionalSeconds(i.scan.records > 0, i.scan.last_log_time_ns);
                             })
      .def_property_readonly("last_log_time_ns",
                             [](const BagInfoObject& i) {
                               return OptionalNs(i.scan.records > 0, i.scan.last_log_time_ns);
                             })
      .def_property_readonly(
          "first_stamp",
          [](const BagInfoObject& i) {
            return OptionalSeconds(i.scan.has_stamps, i.scan.first_stamp_ns);
          },
          "The oldest header stamp of /tf and /joint_states.")
      .def_property_readonly("first_stamp_ns",
                             [](const BagInfoObject& i) {
                               return OptionalNs(i.scan.has_stamps, i.scan.first_stamp_ns);
                             })
      .def_property_readonly(
          "last_stamp",
          [](const BagInfoObject& i) {
            return OptionalSeconds(i.scan.has_stamps, i.scan.last_stamp_ns);
          },
          "The newest header stamp of /tf and /joint_states.")
      .def_property_readonly("last_stamp_ns",
                             [](const BagInfoObject& i) {
                               return OptionalNs(i.scan.has_stamps, i.scan.last_stamp_ns);
                             })
      .def("__repr__", [](const BagInfoObject& i) {
        return "BagInfo(format='" + std::string(ros::ToString(i.scan.format)) +
               "', messages=" + std::to_string(i.scan.records) +
               ", frames=" + std::to_string(i.frames.size()) + ")";
      });
}

void BindBagFunctions(py::module_& m) {
  m.def(
      "load_bag",
      [](py::handle path, py::handle graph, py::handle topics, py::handle static_mode,
         py::handle bodies, py::handle pose_topics, py::handle urdf, py::handle start,
         py::handle end, py::handle window, py::handle sample_capacity) {
        return LoadBag(path, graph, topics, static_mode, bodies, pose_topics, urdf, start, end,
                       window, sample_capacity, "load_bag");
      },
      py::arg("path"), py::arg("graph") = py::none(), py::kw_only(), py::arg("topics") = py::none(),
      py::arg("static") = py::none(), py::arg("bodies") = py::none(),
      py::arg("pose_topics") = py::none(), py::arg("urdf") = py::none(),
      py::arg("start") = py::none(), py::arg("end") = py::none(), py::arg("window") = py::none(),
      py::arg("sample_capacity") = py::none(),
      Doc(R"(Applies a bag's tf and joint states to a scene graph (the `bag` script op); returns a
BagReport (the graph, the findings, the counts).

graph            a SceneGraph to apply to (its own time options); None [default]: a new graph,
                 as `semgraph bag check` makes it: linear interpolation (tf2's) and a window
                 over all of the bag's header stamps
window           with graph=None: the history window instead (a time: int ns, float s), e.g.
                 10.0 for tf2's buffer
sample_capacity  with graph=None: samples kept per stamped edge [1024]: raise it to query
                 anywhere in a long bag)",
          kLoadOptionsDoc)
          .c_str());
  m.def(
      "check_bag",
      [](py::handle path, py::handle topics, py::handle static_mode, py::handle bodies,
         py::handle pose_topics, py::handle urdf, py::handle start, py::handle end,
         py::handle window) {
        return LoadBag(path, py::none(), topics, static_mode, bodies, pose_topics, urdf, start, end,
                       window, py::none(), "check_bag");
      },
      py::arg("path"), py::kw_only(), py::arg("topics") = py::none(),
      py::arg("static") = py::none(), py::arg("bodies") = py::none(),
      py::arg("pose_topics") = py::none(), py::arg("urdf") = py::none(),
      py::arg("start") = py::none(), py::arg("end") = py::none(), py::arg("window") = py::none(),
      Doc(R"(`semgraph bag check`: applies a bag to a new graph and returns the BagReport; its
findings are the tool's JSON lines (Finding.to_json), its summary the summary line, its
exit_status the tool's (0 clean, 1 findings; an unreadable bag raises BagError, the tool's 2).

window           a tf2 buffer of that length (int ns, float s) instead of a window over the
                 whole bag (then stamp_too_old finds samples older than it))",
          kLoadOptionsDoc)
          .c_str());
  m.def("bag_info", &BagInfo, py::arg("path"),
        R"(`semgraph bag info`: reads the whole bag once and returns a BagInfo (format, topics
with types and counts, log-time and stamp ranges, the tf tree with the body of each frame).
A bag that cannot be read or is corrupt raises BagError. Runs without the GIL.)");
}

}  // namespace

void BindRosBags(py::module_& m) {
  BindFinding(m);
  BindBagReport(m);
  BindBagInfo(m);
  BindBagFunctions(m);
}

}  // namespace semgraph::python
