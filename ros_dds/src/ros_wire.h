// Internal to semgraph_ros_dds: the idlc-generated ROS 2 types, topics and QoS
// (ros_topics.h), an owning wrapper for DDS entities, and the conversions between the generated
// C structs and semgraph::ros's message structs. Not installed.
#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <string>
#include <vector>

#include "ros2_messages.h"
#include "semgraph/base/expected.h"
#include "semgraph/ros/messages.h"
#include "semgraph/ros_dds/ros_topics.h"
#include "semgraph_dds_shared/entity.h"

namespace semgraph::ros_dds::internal {

/// Owns one DDS entity (semgraph_dds_shared/entity.h).
using Entity = dds_shared::Entity;

/// "what: <DDS's text for rc>".
[[nodiscard]] std::string DdsError(const char* what, dds_return_t rc);

/// The domain: `requested` when given, else ROS_DOMAIN_ID's, else 0.
[[nodiscard]] base::Expected<std::uint32_t, std::string> ResolveDomain(
    const std::uint32_t* requested);

/// Creates the topic of `topic` on `participant` (a negative return is DDS's error).
[[nodiscard]] dds_entity_t CreateTopic(dds_entity_t participant, RosTopic topic);
/// The same under `dds_name` (a user-named topic: DdsTopicName).
[[nodiscard]] dds_entity_t CreateTopic(dds_entity_t participant, RosTopic topic,
                                       const std::string& dds_name);
/// A writer / reader of `topic` with tf2_ros's QoS (ros_topics.h).
[[nodiscard]] dds_entity_t CreateWriter(dds_entity_t participant, dds_entity_t topic_entity,
                                        RosTopic topic);
[[nodiscard]] dds_entity_t CreateReader(dds_entity_t participant, dds_entity_t topic_entity,
                                        RosTopic topic);

/// Generated struct -> semgraph's message (reusing `out`'s capacity).
void FromWire(const tf2_msgs_msg_dds__TFMessage_& in, ros::TFMessage& out);
void FromWire(const sensor_msgs_msg_dds__JointState_& in, ros::JointState& out);
void FromWire(const geometry_msgs_msg_dds__PoseWithCovarianceStamped_& in,
              ros::PoseWithCovarianceStamped& out);
void FromWire(const nav_msgs_msg_dds__Odometry_& in, ros::Odometry& out);

/// A TFMessage as the generated struct, pointing into the strings of the ros::TFMessage it was
/// made from (which must outlive it and stay unchanged). Fails when a stamp's seconds do not
/// fit ROS 2's int32.
class WireTf {
 public:
  [[nodiscard]] base::Expected<base::Ok, std::string> Set(const ros::TFMessage& message);
  [[nodiscard]] const tf2_msgs_msg_dds__TFMessage_& sample() const noexcept { return sample_; }

 private:
  std::vector<geometry_msgs_msg_dds__TransformStamped_> rows_;
  tf2_msgs_msg_dds__TFMessage_ sample_{};
};

/// ns since the epoch -> ROS Time (sec = floor(ns / 1e9), 0 <= nanosec < 1e9).
[[nodiscard]] ros::Time TimeFromNanoseconds(std::int64_t ns) noexcept;

}  // namespace semgraph::ros_dds::internal
