// File: python/src/ros.h
//
// The submodule semgraph.ros (docs/python.md, "ROS"; docs/ros.md): bags into a graph, the tf
// checker and `bag info` (ros_bag.cc), a streaming iterator over a bag's transforms and joint
// states (ros_records.cc), and, with Cyclone DDS, a live listener and a broadcaster
// (ros_live.cc). Every number comes from semgraph::ros / semgraph::ros_dds; this layer converts
// arguments and results and raises the library's errors (a bag that cannot be read:
// semgraph.ros.BagError with the file, the byte offset and what is wrong).
#pragma once

#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

#include "graph.h"
#include "semgraph/ros/bag_loader.h"
#include "semgraph/ros/findings.h"

namespace semgraph::python {

/// Raises semgraph.ros.BagError(code, file, offset, message).
[[noreturn]] void ThrowBag(const ros::BagError& error);

/// A path argument: str or os.PathLike of str (TypeError otherwise).
std::string PathArg(py::handle path, const char* function, const char* argument);
/// topics=: None -> the defaults (/tf, /tf_static, /joint_states), else a sequence of str.
std::vector<std::string> TopicsArg(py::handle topics, const char* function);
/// static= and bodies=: the lift's options (ValueError for an unknown mode or a bad map).
ros::LiftOptions LiftArgs(py::handle static_mode, py::handle bodies, const char* function);
/// pose_topics=: None -> none, else a dict {topic: frame} (LiftOptions::pose_topics; TypeError
/// for another type, ValueError for an empty topic or frame).
ros::PoseTopicsMap PoseTopicsArg(py::handle pose_topics, const char* function);

/// Seconds of a nanosecond time, for the float properties (the *_ns ones are exact).
inline double Seconds(std::int64_t ns) { return static_cast<double>(ns) * 1e-9; }

/// The Python object of a finding group (class Finding, registered by BindRosBags).
struct FindingObject {
  ros::FindingGroup group;
};

/// Finding, BagReport, BagTopic, BagFrame, BagInfo, BagError; load_bag, check_bag, bag_info.
void BindRosBags(py::module_& m);
/// TransformRecord, JointStateRecord, BagRecords; read_bag.
void BindRosRecords(py::module_& m);
/// Listener, Broadcaster (only when built with semgraph::ros_dds).
void BindRosLive(py::module_& m);

}  // namespace semgraph::python
