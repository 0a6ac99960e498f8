// semgraph.ros.Listener and Broadcaster: live ROS 2 tf over Cyclone DDS (ros.h; docs/ros.md,
// "Live ROS 2"). The Listener owns a Python SceneGraph that its receive thread fills; the graph
// is read-only from Python (its WriterMutex refuses writes) while the listener runs.
//
// Locks and the GIL (why nothing deadlocks): the receive thread never touches Python (findings
// go to a queue that Python polls); every call that may wait for the listener's lock
// (with_graph, findings, stats, wait, close) releases the GIL first, and with_graph's callback
// takes the GIL back only once it holds the listener's lock.
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <chrono>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common.h"
#include "ros.h"
#include "semgraph/ros_dds/broadcaster.h"
#include "semgraph/ros_dds/listener.h"
#include "timed.h"

namespace semgraph::python {

namespace {

/// Finding events kept for poll_findings() (beyond, the oldest are dropped and counted).
constexpr std::size_t kMaxFindingEvents = 65536;

struct FindingQueue {
  std::mutex mutex;
  std::deque<std::pair<ros::FindingGroup, bool>> events;
  std::uint64_t dropped = 0;
};

struct ListenerObject {
  GraphPtr graph;  // declared first: destroyed after the listener
  std::shared_ptr<FindingQueue> queue = std::make_shared<FindingQueue>();
  std::unique_ptr<ros_dds::Listener> listener;

  ros_dds::Listener& Running() const {
    if (!listener) throw py::value_error("Listener: closed");
    return *listener;
  }
  void Close() {
    {
      py::gil_scoped_release release;
      listener.reset();  // joins the receive thread
    }
    graph->writer.read_only.store(false, std::memory_order_release);
  }
};

std::shared_ptr<ListenerObject> MakeListener(py::handle domain, py::handle static_mode,
                                             py::handle bodies, py::handle pose_topics,
                                             py::handle odometry_topics, bool joint_states,
                                             bool robot_description, py::handle window,
                                             py::handle interpolation, py::handle sample_capacity) {
  ros_dds::ListenerOptions options;
  if (!domain.is_none()) {
    if (PyBool_Check(domain.ptr()) || !PyIndex_Check(domain.ptr())) {
      throw py::type_error("Listener(): domain must be an int, not " + TypeName(domain));
    }
    const auto d = domain.cast<long long>();
    if (d < 0 || d > 232) {
      throw py::value_error("Listener(): domain must be 0 to 232 (ROS 2's), got " +
                            std::to_string(d));
    }
    options.domain = static_cast<std::uint32_t>(d);
  }
  options.lift = LiftArgs(static_mode, bodies, "Listener");
  options.lift.pose_topics = PoseTopicsArg(pose_topics, "Listener");
  if (!odometry_topics.is_none()) {
    if (py::isinstance<py::str>(odometry_topics) ||
        !py::isinstance<py::sequence>(odometry_topics)) {
      throw py::type_error("Listener(): odometry_topics must be a sequence of str, not " +
                           TypeName(odometry_topics));
    }
    for (py::handle t : odometry_topics) {
      options.odometry_topics.emplace_back(NameArg(t, "Listener", "odometry_topics"));
    }
  }
  options.joint_states = joint_states;
  options.robot_description = robot_description;
  core::TimeOptions time;  // tf2's buffer unless told: 10 s, linear
  time.window = core::Duration::Seconds(10);
  time.interpolation = core::Interpolation::kLinear;
  if (!window.is_none()) {
    time.window = core::Duration::Nanoseconds(NanosecondsArg(window, "Listener", "window", false));
  }
  const std::string_view interp = NameArg(interpolation, "Listener", "interpolation");
  if (interp == "screw") {
    time.interpolation = core::Interpolation::kScrew;
  } else if (!(interp.empty() || interp == "linear")) {
    throw py::value_error("Listener(): interpolation must be 'linear' or 'screw', not '" +
                          std::string(interp) + "'");
  }
  if (!sample_capacity.is_none()) {
    if (PyBool_Check(sample_capacity.ptr()) || !PyIndex_Check(sample_capacity.ptr())) {
      throw py::type_error("Listener(): sample_capacity must be an int, not " +
                           TypeName(sample_capacity));
    }
    const auto n = sample_capacity.cast<long long>();
    time.sample_capacity = n < 0 ? 0 : static_cast<std::size_t>(n);
  }
  auto made = QuaternionGraph::Create(time);
  if (!made) ThrowRejected(made.error());
  auto out = std::make_shared<ListenerObject>();
  out->graph = std::make_shared<GraphBox>(false, std::move(*made));
  out->graph->writer.read_only.store(true, std::memory_order_release);
  std::weak_ptr<FindingQueue> queue = out->queue;
  options.on_finding = [queue](const ros::FindingGroup& group, bool first) {
    auto q = queue.lock();
    if (!q) return;
    std::lock_guard<std::mutex> lock(q->mutex);
    if (q->events.size() >= kMaxFindingEvents) {
      q->events.pop_front();
      ++q->dropped;
    }
    q->events.emplace_back(group, first);
  };
  options.log = [](const std::string& line) {
    std::fprintf(stderr, "semgraph-ros: %s\n", line.c_str());
  };
  std::optional<std::string> error;
  {
    py::gil_scoped_release release;
    auto listener = ros_dds::Listener::Create(std::get<0>(out->graph->graph), std::move(options));
    if (listener) {
      out->listener = std::move(*listener);
    } else {
      error = listener.error();
    }
  }
  if (error) {
    out->graph->writer.read_only.store(false, std::memory_order_release);
    throw py::value_error("Listener(): " + *error);
  }
  return out;
}

/// fn(graph) under the listener's lock (no message applied meanwhile); returns fn's result.
py::object WithGraph(ListenerObject& self, const py::object& fn) {
  ros_dds::Listener& listener = self.Running();
  py::object graph = py::cast(self.graph);
  py::object result;
  std::exception_ptr error;
  {
    py::gil_scoped_release release;
    listener.WithGraph([&](const core::SceneGraph<>&) {
      py::gil_scoped_acquire acquire;
      try {
        result = fn(graph);
      } catch (...) {
        error = std::current_exception();
      }
    });
  }
  if (error) std::rethrow_exception(error);
  return result;
}

std::vector<FindingObject> Findings(const ListenerObject& self) {
  std::vector<ros::FindingGroup> groups;
  {
    py::gil_scoped_release release;
    groups = self.Running().findings();
  }
  std::vector<FindingObject> out;
  for (auto& g : groups) out.push_back({std::move(g)});
  return out;
}

py::list PollFindings(const ListenerObject& self) {
  std::deque<std::pair<ros::FindingGroup, bool>> events;
  {
    std::lock_guard<std::mutex> lock(self.queue->mutex);
    events.swap(self.queue->events);
  }
  py::list out;
  for (auto& [g, first] : events) out.append(py::make_tuple(FindingObject{std::move(g)}, first));
  return out;
}

py::dict Stats(const ListenerObject& self) {
  ros_dds::ListenerStats s;
  {
    py::gil_scoped_release release;
    s = self.Running().stats();
  }
  py::dict d;
  d["tf"] = s.tf;
  d["tf_static"] = s.tf_static;
  d["joint_states"] = s.joint_states;
  d["robot_descriptions"] = s.robot_descriptions;
  d["robot_loaded"] = s.robot_loaded;
  d["transforms"] = s.counts.transforms;
  d["applied"] = s.counts.applied;
  d["refused"] = s.counts.refused;
  d["covered"] = s.counts.covered;
  d["mismatched"] = s.counts.mismatched;
  d["normalized"] = s.counts.normalized;
  d["joint_states_applied"] = s.counts.joint_states;
  d["joint_states_refused"] = s.counts.joint_states_refused;
  d["joint_states_skipped"] = s.counts.joint_states_skipped;
  d["poses_with_covariance"] = s.poses_with_covariance;
  d["odometry"] = s.odometry;
  d["poses_with_covariance_applied"] = s.counts.poses_with_covariance;
  d["odometry_applied"] = s.counts.odometry;
  d["covariance_refused"] = s.counts.covariance_refused;
  return d;
}

/// Waits until every frame of `frames` is in the graph and at least `transforms` transforms
/// were seen, or the timeout; returns whether they are.
bool Wait(const ListenerObject& self, py::handle timeout, const std::vector<std::string>& frames,
          std::uint64_t transforms) {
  const ros_dds::Listener& listener = self.Running();
  const std::int64_t ns = NanosecondsArg(timeout, "wait", "timeout", false);
  py::gil_scoped_release release;
  return listener.WaitUntil(
      [&] {
        if (listener.stats().counts.transforms < transforms) return false;
        bool all = true;
        listener.WithGraph([&](const core::SceneGraph<>& g) {
          for (const std::string& f : frames) all = all && g.FindFrame(f).is_valid();
        });
        return all;
      },
      std::chrono::milliseconds(ns < 0 ? 0 : ns / 1'000'000));
}

struct BroadcasterObject {
  GraphPtr graph;  // declared first: destroyed after the broadcaster
  std::unique_ptr<ros_dds::Broadcaster> broadcaster;
};

std::shared_ptr<BroadcasterObject> MakeBroadcaster(const GraphPtr& graph, py::handle domain) {
  if (graph->graph.index() != 0) {
    throw py::value_error("Broadcaster(): the graph must have representation 'quaternion' (tf's)");
  }
  ros_dds::BroadcasterOptions options;
  if (!domain.is_none()) {
    if (PyBool_Check(domain.ptr()) || !PyIndex_Check(domain.ptr())) {
      throw py::type_error("Broadcaster(): domain must be an int, not " + TypeName(domain));
    }
    const auto d = domain.cast<long long>();
    if (d < 0 || d > 232) {
      throw py::value_error("Broadcaster(): domain must be 0 to 232 (ROS 2's), got " +
                            std::to_string(d));
    }
    options.domain = static_cast<std::uint32_t>(d);
  }
  auto out = std::make_shared<BroadcasterObject>();
  out->graph = graph;
  std::optional<std::string> error;
  {
    py::gil_scoped_release release;
    auto made = ros_dds::Broadcaster::Create(std::get<0>(graph->graph), std::move(options));
    if (made) {
      out->broadcaster = std::move(*made);
    } else {
      error = made.error();
    }
  }
  if (error) throw py::value_error("Broadcaster(): " + *error);
  return out;
}

py::tuple Broadcast(BroadcasterObject& self) {
  std::optional<std::string> error;
  ros_dds::BroadcastCounts counts;
  {
    py::gil_scoped_release release;
    // The graph's writer must not change it meanwhile: a listener's graph is read-only here
    // (lock() refuses), and Python's writes wait for this lock.
    std::lock_guard<WriterMutex> lock(self.graph->writer);
    auto sent = self.broadcaster->Broadcast();
    if (sent) {
      counts = *sent;
    } else {
      error = sent.error();
    }
  }
  if (error) throw py::value_error("Broadcaster.broadcast(): " + *error);
  return py::make_tuple(counts.tf_transforms, counts.static_transforms);
}

}  // namespace

void BindRosLive(py::module_& m) {
  py::class_<ListenerObject, std::shared_ptr<ListenerObject>>(m, "Listener",
                                                              R"(The semantic tf2 listener
(docs/ros.md, "Live ROS 2"): subscribes to /tf, /tf_static, /joint_states and /robot_description
over Cyclone DDS (no ROS installation) and applies what arrives, on its own receive thread, to a
SceneGraph it owns (`graph`), every rule checked; each refused transform is a finding.

Threads: the receive thread is the graph's one writer; the graph is read-only from Python
(writes raise RejectedError 'read_only') until close(). Compiled queries (compile them inside
with_graph) may be evaluated at any time; one-shot queries by name (graph.pose(...), ...) must
run inside with_graph(fn), which holds the listener's lock. Blocking calls release the GIL.
A context manager: `with Listener(...) as l:` closes it at the end.)")
      .def(py::init(&MakeListener), py::kw_only(), py::arg("domain") = py::none(),
           py::arg("static") = py::none(), py::arg("bodies") = py::none(),
           py::arg("pose_topics") = py::none(), py::arg("odometry_topics") = py::none(),
           py::arg("joint_states") = true, py::arg("robot_description") = true,
           py::arg("window") = py::none(), py::arg("interpolation") = py::none(),
           py::arg("sample_capacity") = py::none(),
           R"(Joins the DDS domain, subscribes and starts the receive thread.

domain            the DDS domain (ROS_DOMAIN_ID): None [default] reads ROS_DOMAIN_ID, else 0
static, bodies    as load_bag: 'same_body' [default] or 'own_body'; {body: [frame, ...]}
pose_topics       {topic: frame}: PoseWithCovarianceStamped topics, each message the pose of
                  `frame` wrt its header frame with its covariance (as load_bag)
odometry_topics   [topic, ...]: Odometry topics (pose and twist with their covariances);
                  a bad message is a finding, the graph unchanged
joint_states, robot_description   subscribe to them [True]
window            the graph's history window [10.0 s, tf2's buffer] (int ns, float s)
interpolation     'linear' [default, tf2's] or 'screw'
sample_capacity   samples kept per stamped edge [1024]
DDS is configured by CYCLONEDDS_URI. Raises ValueError when DDS refuses (with its message).)")
      .def_property_readonly(
          "graph", [](const ListenerObject& l) { return l.graph; },
          "The SceneGraph the listener fills (read-only from Python while it runs).")
      .def_property_readonly(
          "domain", [](const ListenerObject& l) { return l.Running().domain(); },
          "The DDS domain joined.")
      .def_property_readonly(
          "tf_publishers", [](const ListenerObject& l) { return l.Running().tf_publishers(); },
          "Writers matched on /tf now (a sample sent before the match never arrives).")
      .def(
          "publishers",
          [](const ListenerObject& l, py::handle topic) {
            return l.Running().publishers(NameArg(topic, "publishers", "topic"));
          },
          py::arg("topic"),
          "Writers matched now on one of the pose or odometry topics (0 for another topic).")
      .def("with_graph", &WithGraph, py::arg("fn"),
           R"(Calls fn(graph) while no message is applied (the listener's lock) and returns its
result: one-shot queries by name and compile_* belong here, e.g.
listener.with_graph(lambda g: g.pose(of='tool', wrt='world', at='latest_common')).
A long fn delays the messages behind it. Waits for the lock without the GIL.)")
      .def("findings", &Findings, "The finding groups so far (a list of Finding, as check_bag's).")
      .def("poll_findings", &PollFindings,
           R"(The finding events since the last call, oldest first: a list of (Finding, new), the
group as it was after the occurrence(s) reported, new = the group is new. At most 65536 are
kept between calls (the oldest dropped).)")
      .def_property_readonly("stats", &Stats,
                             R"(Counts (a dict): messages per topic (tf, tf_static, joint_states,
robot_descriptions, poses_with_covariance, odometry), robot_loaded, and the lift's transforms,
applied, refused, covered, mismatched, normalized, joint_states_applied, joint_states_refused,
joint_states_skipped, poses_with_covariance_applied, odometry_applied, covariance_refused.)")
      .def("wait", &Wait, py::arg("timeout"), py::kw_only(),
           py::arg("frames") = std::vector<std::string>{}, py::arg("transforms") = 0,
           R"(Waits (without the GIL) until every frame of `frames` is in the graph and at least
`transforms` transforms were received, or `timeout` (int ns, float s) passed; returns whether
they are.)")
      .def("close", &ListenerObject::Close,
           "Stops the receive thread and leaves the domain; the graph becomes writable.")
      .def_property_readonly(
          "closed", [](const ListenerObject& l) { return !l.listener; }, "close() was called.")
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](ListenerObject& l, py::args) { l.Close(); });

  py::class_<BroadcasterObject, std::shared_ptr<BroadcasterObject>>(m, "Broadcaster",
                                                                    R"(Publishes a SceneGraph's
pose edges as ROS 2 tf over Cyclone DDS (docs/ros.md, "The broadcaster"): stamped edges' samples
on /tf, timeless edges in one /tf_static message. Each broadcast() sends what changed.)")
      .def(py::init(&MakeBroadcaster), py::arg("graph"), py::kw_only(),
           py::arg("domain") = py::none(),
           R"(Joins the DDS domain (None: ROS_DOMAIN_ID, else 0) and creates the /tf and /tf_static
writers for `graph` (representation 'quaternion'). Raises ValueError when DDS refuses.)")
      .def("broadcast", &Broadcast,
           R"(Sends what changed since the last call: each stamped sample newer than the last
sent for its edge on /tf, and the whole /tf_static message when a timeless edge changed.
Returns (tf transforms sent, static transforms sent). Without the GIL, under the graph's
writer lock.)")
      .def(
          "rewind", [](BroadcasterObject& b) { b.broadcaster->Rewind(); },
          "The next broadcast() sends every stored sample again (for a late /tf subscriber).")
      .def_property_readonly(
          "subscribers", [](const BroadcasterObject& b) { return b.broadcaster->subscribers(); },
          "Readers matched on /tf now.")
      .def_property_readonly(
          "subscribers_matched",
          [](const BroadcasterObject& b) { return b.broadcaster->subscribers_matched(); },
          "Readers ever matched on /tf.")
      .def_property_readonly(
          "domain", [](const BroadcasterObject& b) { return b.broadcaster->domain(); },
          "The DDS domain joined.");
}

}  // namespace semgraph::python
