// ROS 2 topics, QoS and conversions (ros_topics.h, ros_wire.h).
#include "ros_wire.h"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <limits>

namespace semgraph::ros_dds {

std::string_view RosName(RosTopic topic) noexcept {
  switch (topic) {
    case RosTopic::kTf:
      return "/tf";
    case RosTopic::kTfStatic:
      return "/tf_static";
    case RosTopic::kJointStates:
      return "/joint_states";
    case RosTopic::kRobotDescription:
      return "/robot_description";
    case RosTopic::kPoseWithCovariance:
    case RosTopic::kOdometry:
      return "";  // named by the user
  }
  return "";
}

std::string_view DdsName(RosTopic topic) noexcept {
  switch (topic) {
    case RosTopic::kTf:
      return "rt/tf";
    case RosTopic::kTfStatic:
      return "rt/tf_static";
    case RosTopic::kJointStates:
      return "rt/joint_states";
    case RosTopic::kRobotDescription:
      return "rt/robot_description";
    case RosTopic::kPoseWithCovariance:
    case RosTopic::kOdometry:
      return "";  // DdsTopicName of the user's name
  }
  return "";
}

base::Expected<std::string, std::string> DdsTopicName(std::string_view ros_topic) {
  const auto refuse = [&](const char* why) {
    return base::Unexpected{"'" + std::string(ros_topic) + "' is not a ROS 2 topic name: " + why};
  };
  if (ros_topic.size() < 2 || ros_topic.front() != '/')
    return refuse("it must start with '/' and hold a name");
  if (ros_topic.back() == '/') return refuse("it ends with '/'");
  for (std::size_t i = 0; i < ros_topic.size(); ++i) {
    const char c = ros_topic[i];
    const bool token_start = ros_topic[i - (i > 0 ? 1 : 0)] == '/';
    if (c == '/') {
      if (i > 0 && token_start) return refuse("it holds \"//\"");
    } else if (c >= '0' && c <= '9') {
      if (token_start) return refuse("a name token starts with a digit");
    } else if (!(c == '_' || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'))) {
      return refuse("only letters, digits, '_' and '/' are allowed");
    }
  }
  return "rt" + std::string(ros_topic);
}

namespace {

const dds_topic_descriptor_t* Descriptor(RosTopic topic) noexcept {
  switch (topic) {
    case RosTopic::kTf:
    case RosTopic::kTfStatic:
      return &tf2_msgs_msg_dds__TFMessage__desc;
    case RosTopic::kJointStates:
      return &sensor_msgs_msg_dds__JointState__desc;
    case RosTopic::kRobotDescription:
      return &std_msgs_msg_dds__String__desc;
    case RosTopic::kPoseWithCovariance:
      return &geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc;
    case RosTopic::kOdometry:
      return &nav_msgs_msg_dds__Odometry__desc;
  }
  return nullptr;
}

bool UserNamed(RosTopic topic) noexcept {
  return topic == RosTopic::kPoseWithCovariance || topic == RosTopic::kOdometry;
}

// tf2_ros's QoS (ros_topics.h); `reader` selects the reader's side where it differs.
dds_qos_t* MakeQos(RosTopic topic, bool reader) {
  dds_qos_t* qos = dds_create_qos();
  const bool best_effort = reader && (topic == RosTopic::kJointStates || UserNamed(topic));
  dds_qset_reliability(qos, best_effort ? DDS_RELIABILITY_BEST_EFFORT : DDS_RELIABILITY_RELIABLE,
                       DDS_MSECS(100));
  const bool durable = topic == RosTopic::kTfStatic || topic == RosTopic::kRobotDescription;
  dds_qset_durability(qos, durable ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  int depth = 100;
  if (topic == RosTopic::kTfStatic && !reader) depth = 1;
  if (topic == RosTopic::kRobotDescription) depth = 1;
  if (topic == RosTopic::kJointStates || UserNamed(topic)) depth = 10;
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, depth);
  const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
  dds_qset_data_representation(qos, 1, &xcdr1);
  if (topic == RosTopic::kTf || topic == RosTopic::kTfStatic) {
    const std::string user_data = "typehash=" + std::string(kTfMessageTypeHash) + ";";
    dds_qset_userdata(qos, user_data.data(), user_data.size());
  }
  return qos;
}

}  // namespace

std::string_view DdsTypeName(RosTopic topic) noexcept {
  const dds_topic_descriptor_t* d = Descriptor(topic);
  return d != nullptr ? std::string_view(d->m_typename) : std::string_view();
}

base::Expected<std::uint32_t, std::string> RosDomainFromEnvironment() {
  const char* text = std::getenv("ROS_DOMAIN_ID");
  if (text == nullptr || *text == '\0') return std::uint32_t{0};
  std::uint32_t id = 0;
  const char* end = text + std::strlen(text);
  const auto [ptr, ec] = std::from_chars(text, end, id);
  if (ec != std::errc() || ptr != end || id > 232) {
    return base::Unexpected{"ROS_DOMAIN_ID='" + std::string(text) +
                            "' is not a domain id (an integer from 0 to 232)"};
  }
  return id;
}

namespace internal {

std::string DdsError(const char* what, dds_return_t rc) {
  return std::string(what) + ": " + dds_strretcode(rc);
}

base::Expected<std::uint32_t, std::string> ResolveDomain(const std::uint32_t* requested) {
  if (requested != nullptr) return *requested;
  return RosDomainFromEnvironment();
}

dds_entity_t CreateTopic(dds_entity_t participant, RosTopic topic) {
  return CreateTopic(participant, topic, std::string(DdsName(topic)));
}

dds_entity_t CreateTopic(dds_entity_t participant, RosTopic topic, const std::string& dds_name) {
  dds_qos_t* qos = MakeQos(topic, false);
  const dds_entity_t t =
      dds_create_topic(participant, Descriptor(topic), dds_name.c_str(), qos, nullptr);
  dds_delete_qos(qos);
  return t;
}

dds_entity_t CreateWriter(dds_entity_t participant, dds_entity_t topic_entity, RosTopic topic) {
  dds_qos_t* qos = MakeQos(topic, false);
  const dds_entity_t w = dds_create_writer(participant, topic_entity, qos, nullptr);
  dds_delete_qos(qos);
  return w;
}

dds_entity_t CreateReader(dds_entity_t participant, dds_entity_t topic_entity, RosTopic topic) {
  dds_qos_t* qos = MakeQos(topic, true);
  const dds_entity_t r = dds_create_reader(participant, topic_entity, qos, nullptr);
  dds_delete_qos(qos);
  return r;
}

namespace {

void FromWire(const std_msgs_msg_dds__Header_& in, ros::Header& out) {
  out.seq = 0;
  out.stamp.sec = in.stamp_.sec_;
  out.stamp.nanosec = in.stamp_.nanosec_;
  out.frame_id.assign(in.frame_id_ != nullptr ? in.frame_id_ : "");
}

void FromWire(const dds_sequence_double& in, std::vector<double>& out) {
  out.assign(in._buffer, in._buffer + in._length);
}

void FromWire(const geometry_msgs_msg_dds__PoseWithCovariance_& in, ros::PoseWithCovariance& out) {
  const auto& p = in.pose_.position_;
  const auto& q = in.pose_.orientation_;
  out.pose.position = {p.x_, p.y_, p.z_};
  out.pose.orientation = {q.x_, q.y_, q.z_, q.w_};
  std::copy(std::begin(in.covariance_), std::end(in.covariance_), out.covariance.begin());
}

void FromWire(const geometry_msgs_msg_dds__TwistWithCovariance_& in,
              ros::TwistWithCovariance& out) {
  const auto& v = in.twist_.linear_;
  const auto& w = in.twist_.angular_;
  out.twist.linear = {v.x_, v.y_, v.z_};
  out.twist.angular = {w.x_, w.y_, w.z_};
  std::copy(std::begin(in.covariance_), std::end(in.covariance_), out.covariance.begin());
}

}  // namespace

void FromWire(const tf2_msgs_msg_dds__TFMessage_& in, ros::TFMessage& out) {
  out.transforms.resize(in.transforms_._length);
  for (std::uint32_t i = 0; i < in.transforms_._length; ++i) {
    const geometry_msgs_msg_dds__TransformStamped_& w = in.transforms_._buffer[i];
    ros::TransformStamped& t = out.transforms[i];
    FromWire(w.header_, t.header);
    t.child_frame_id.assign(w.child_frame_id_ != nullptr ? w.child_frame_id_ : "");
    const auto& p = w.transform_.translation_;
    const auto& q = w.transform_.rotation_;
    t.transform.translation = {p.x_, p.y_, p.z_};
    t.transform.rotation = {q.x_, q.y_, q.z_, q.w_};
  }
}

void FromWire(const sensor_msgs_msg_dds__JointState_& in, ros::JointState& out) {
  FromWire(in.header_, out.header);
  out.name.resize(in.name_._length);
  for (std::uint32_t i = 0; i < in.name_._length; ++i) {
    out.name[i].assign(in.name_._buffer[i] != nullptr ? in.name_._buffer[i] : "");
  }
  FromWire(in.position_, out.position);
  FromWire(in.velocity_, out.velocity);
  FromWire(in.effort_, out.effort);
}

void FromWire(const geometry_msgs_msg_dds__PoseWithCovarianceStamped_& in,
              ros::PoseWithCovarianceStamped& out) {
  FromWire(in.header_, out.header);
  FromWire(in.pose_, out.pose);
}

void FromWire(const nav_msgs_msg_dds__Odometry_& in, ros::Odometry& out) {
  FromWire(in.header_, out.header);
  out.child_frame_id.assign(in.child_frame_id_ != nullptr ? in.child_frame_id_ : "");
  FromWire(in.pose_, out.pose);
  FromWire(in.twist_, out.twist);
}

ros::Time TimeFromNanoseconds(std::int64_t ns) noexcept {
  std::int64_t sec = ns / 1'000'000'000;
  std::int64_t rem = ns % 1'000'000'000;
  if (rem < 0) {
    rem += 1'000'000'000;
    --sec;
  }
  return {sec, static_cast<std::uint32_t>(rem)};
}

base::Expected<base::Ok, std::string> WireTf::Set(const ros::TFMessage& message) {
  rows_.resize(message.transforms.size());
  for (std::size_t i = 0; i < message.transforms.size(); ++i) {
    const ros::TransformStamped& t = message.transforms[i];
    if (t.header.stamp.sec < std::numeric_limits<std::int32_t>::min() ||
        t.header.stamp.sec > std::numeric_limits<std::int32_t>::max()) {
      return base::Unexpected{"the stamp of {" + t.child_frame_id + "} wrt {" + t.header.frame_id +
                              "} (" + std::to_string(t.header.stamp.sec) +
                              " s) does not fit ROS 2's int32 seconds"};
    }
    geometry_msgs_msg_dds__TransformStamped_& w = rows_[i];
    w.header_.stamp_.sec_ = static_cast<std::int32_t>(t.header.stamp.sec);
    w.header_.stamp_.nanosec_ = t.header.stamp.nanosec;
    // The generated struct is C: non-const pointers; Cyclone only reads them when writing.
    w.header_.frame_id_ = const_cast<char*>(t.header.frame_id.c_str());
    w.child_frame_id_ = const_cast<char*>(t.child_frame_id.c_str());
    const auto& p = t.transform.translation;
    const auto& q = t.transform.rotation;
    w.transform_.translation_ = {p.x, p.y, p.z};
    w.transform_.rotation_ = {q.x, q.y, q.z, q.w};
  }
  sample_.transforms_._length = sample_.transforms_._maximum =
      static_cast<std::uint32_t>(rows_.size());
  sample_.transforms_._buffer = rows_.data();
  sample_.transforms_._release = false;
  return base::Ok{};
}

}  // namespace internal
}  // namespace semgraph::ros_dds
