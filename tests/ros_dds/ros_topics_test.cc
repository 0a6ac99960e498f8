// ros_topics.h: ROS topic -> DDS topic and type names (rosidl's), and ROS_DOMAIN_ID.
#include "semgraph/ros_dds/ros_topics.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "dds_isolation.h"
#include "semgraph/ros_dds/listener.h"

namespace semgraph::ros_dds {
namespace {

TEST(RosTopicsTest, TopicAndTypeNamesAreRos2s) {
  EXPECT_EQ(DdsName(RosTopic::kTf), "rt/tf");
  EXPECT_EQ(DdsName(RosTopic::kTfStatic), "rt/tf_static");
  EXPECT_EQ(DdsName(RosTopic::kJointStates), "rt/joint_states");
  EXPECT_EQ(DdsName(RosTopic::kRobotDescription), "rt/robot_description");
  EXPECT_EQ(RosName(RosTopic::kTfStatic), "/tf_static");
  EXPECT_EQ(DdsTypeName(RosTopic::kTf), "tf2_msgs::msg::dds_::TFMessage_");
  EXPECT_EQ(DdsTypeName(RosTopic::kTfStatic), "tf2_msgs::msg::dds_::TFMessage_");
  EXPECT_EQ(DdsTypeName(RosTopic::kJointStates), "sensor_msgs::msg::dds_::JointState_");
  EXPECT_EQ(DdsTypeName(RosTopic::kRobotDescription), "std_msgs::msg::dds_::String_");
  EXPECT_EQ(DdsTypeName(RosTopic::kPoseWithCovariance),
            "geometry_msgs::msg::dds_::PoseWithCovarianceStamped_");
  EXPECT_EQ(DdsTypeName(RosTopic::kOdometry), "nav_msgs::msg::dds_::Odometry_");
  EXPECT_EQ(DdsName(RosTopic::kOdometry), "");  // named by the user
}

TEST(RosTopicsTest, UserTopicNamesMapToRtAndBadNamesAreRefused) {
  EXPECT_EQ(DdsTopicName("/odom").value(), "rt/odom");
  EXPECT_EQ(DdsTopicName("/robot_1/odometry/filtered").value(), "rt/robot_1/odometry/filtered");
  EXPECT_EQ(DdsTopicName("/AMCL_pose2").value(), "rt/AMCL_pose2");
  for (const char* bad : {"", "/", "odom", "/odom/", "//odom", "/a//b", "/1odom", "/a/2b", "/od-om",
                          "/odom ", "/~odom"}) {
    const auto name = DdsTopicName(bad);
    ASSERT_FALSE(name) << bad;
    EXPECT_NE(name.error().find(std::string("'") + bad + "' is not a ROS 2 topic name"),
              std::string::npos)
        << name.error();
  }
}

TEST(RosTopicsTest, DomainFromRosDomainId) {
  ::unsetenv("ROS_DOMAIN_ID");
  EXPECT_EQ(RosDomainFromEnvironment().value(), 0u);
  ::setenv("ROS_DOMAIN_ID", "42", 1);
  EXPECT_EQ(RosDomainFromEnvironment().value(), 42u);
  for (const char* bad : {"x", "-1", "233", "7 ", "99999999999"}) {
    ::setenv("ROS_DOMAIN_ID", bad, 1);
    const auto d = RosDomainFromEnvironment();
    ASSERT_FALSE(d) << bad;
    EXPECT_NE(d.error().find(std::string("'") + bad + "'"), std::string::npos) << d.error();
  }
  // A listener without an explicit domain refuses to start on a bad ROS_DOMAIN_ID.
  ::setenv("ROS_DOMAIN_ID", "abc", 1);
  core::SceneGraph<> g;
  auto l = Listener::Create(g);
  ASSERT_FALSE(l);
  EXPECT_NE(l.error().find("ROS_DOMAIN_ID='abc'"), std::string::npos) << l.error();
  ::unsetenv("ROS_DOMAIN_ID");
}

TEST(RosTopicsTest, AnInvalidBodiesMapIsRefused) {
  ListenerOptions o;
  o.domain = 148;
  o.lift.bodies = {{"A", {"f"}}, {"B", {"f"}}};
  core::SceneGraph<> g;
  auto l = Listener::Create(g, o);
  ASSERT_FALSE(l);
  EXPECT_NE(l.error().find("invalid bodies map"), std::string::npos) << l.error();
}

TEST(RosTopicsTest, AListenersPoseAndOdometryTopicsMustBeRos2NamesWithAFrame) {
  core::SceneGraph<> g;
  const auto refused = [&](ListenerOptions o) {
    auto l = Listener::Create(g, std::move(o));
    return l ? std::string() : l.error();
  };
  ListenerOptions o;
  o.domain = 148;
  o.lift.pose_topics = {{"amcl_pose", "base"}};
  EXPECT_NE(refused(o).find("'amcl_pose' is not a ROS 2 topic name"), std::string::npos)
      << refused(o);
  o.lift.pose_topics = {{"/amcl_pose", ""}};
  EXPECT_NE(refused(o).find("/amcl_pose has no frame"), std::string::npos) << refused(o);
  o.lift.pose_topics = {{"/a", "base"}};
  o.odometry_topics = {"/a"};
  EXPECT_NE(refused(o).find("/a is also a pose topic"), std::string::npos) << refused(o);
  o.lift.pose_topics.clear();
  o.odometry_topics = {"/odom//x"};
  EXPECT_NE(refused(o).find("\"//\""), std::string::npos) << refused(o);
  EXPECT_EQ(g.num_frames(), 0u);
}

}  // namespace
}  // namespace semgraph::ros_dds
