// File: semgraph/ros_dds/ros_topics.h
//
// The ROS 2 wire facts the live layer uses (docs/ros.md, "Live ROS 2"): the DDS topic of each
// ROS topic (ROS topic /X is DDS topic rt/X), its type name, and the domain a ROS 2 node joins.
// QoS per topic (tf2_ros's):
//   rt/tf                 writer and reader RELIABLE, VOLATILE, KEEP_LAST 100
//   rt/tf_static          writer RELIABLE, TRANSIENT_LOCAL, KEEP_LAST 1 (one message holds all
//                         of a writer's static transforms); reader the same with KEEP_LAST 100
//   rt/robot_description  RELIABLE, TRANSIENT_LOCAL, KEEP_LAST 1
//   rt/joint_states       writer RELIABLE, VOLATILE, KEEP_LAST 10; reader BEST_EFFORT (it then
//                         matches reliable and best-effort publishers alike)
//   pose and odometry     topics the user names (geometry_msgs/PoseWithCovarianceStamped,
//                         nav_msgs/Odometry): ROS 2's default QoS, RELIABLE, VOLATILE,
//                         KEEP_LAST 10; the reader BEST_EFFORT (as rt/joint_states)
// Every type is @final and keyless, written as XCDR1 (plain CDR), the data representation set
// explicitly on each reader and writer. tf endpoints carry USER_DATA "typehash=RIHS01_<hex>;"
// (what rmw_cyclonedds of ROS 2 Iron and later announces; older ROS ignores it).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "semgraph/base/expected.h"
#include "semgraph/ros_dds/export.h"

namespace semgraph::ros_dds {

/// The ROS topics of the live layer: four with fixed names, and two kinds of topics the user
/// names (ListenerOptions: LiftOptions::pose_topics, odometry_topics).
enum class RosTopic : std::uint8_t {
  kTf,
  kTfStatic,
  kJointStates,
  kRobotDescription,
  kPoseWithCovariance,  ///< a geometry_msgs/PoseWithCovarianceStamped topic the user names
  kOdometry,            ///< a nav_msgs/Odometry topic the user names
};

/// "/tf", "/tf_static", "/joint_states", "/robot_description"; "" for the user-named kinds.
[[nodiscard]] SEMGRAPH_ROS_DDS_EXPORT std::string_view RosName(RosTopic topic) noexcept;
/// "rt/tf", ...: the DDS topic name; "" for the user-named kinds (DdsTopicName).
[[nodiscard]] SEMGRAPH_ROS_DDS_EXPORT std::string_view DdsName(RosTopic topic) noexcept;
/// "tf2_msgs::msg::dds_::TFMessage_", "sensor_msgs::msg::dds_::JointState_",
/// "std_msgs::msg::dds_::String_", "geometry_msgs::msg::dds_::PoseWithCovarianceStamped_",
/// "nav_msgs::msg::dds_::Odometry_".
[[nodiscard]] SEMGRAPH_ROS_DDS_EXPORT std::string_view DdsTypeName(RosTopic topic) noexcept;

/// The DDS topic of a fully qualified ROS 2 topic name ("/amcl_pose" -> "rt/amcl_pose"). An
/// error naming the topic when it is not one: it must start with '/', not end with '/', hold
/// only letters, digits, '_' and '/', no "//", and no name token may start with a digit.
[[nodiscard]] SEMGRAPH_ROS_DDS_EXPORT base::Expected<std::string, std::string> DdsTopicName(
    std::string_view ros_topic);

/// The RIHS01 type hash of tf2_msgs/msg/TFMessage (ROS 2 Iron and later).
inline constexpr std::string_view kTfMessageTypeHash =
    "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087";

/// ROS 2's domain: ROS_DOMAIN_ID when set (a decimal integer 0..232), else 0. An unparsable
/// or out-of-range value is an error naming it (ROS 2 refuses it too).
[[nodiscard]] SEMGRAPH_ROS_DDS_EXPORT base::Expected<std::uint32_t, std::string>
RosDomainFromEnvironment();

}  // namespace semgraph::ros_dds
