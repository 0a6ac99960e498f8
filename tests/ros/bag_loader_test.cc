// Bags into a graph (ros/bag_loader.h), on bags written by other tools: MCAP by Foxglove's
// @mcap/core, ROS 1 bags by Debian's python3-rosbag, rosbag2 sqlite3 by Python's sqlite3. The
// transforms each writer put in (its expected.json) are read back through semgraph's queries,
// single edges exactly and chains against Eigen's composition of the written values.
#include "semgraph/ros/bag_loader.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "semgraph/core/scene_graph_debug.h"

namespace semgraph::ros {
namespace {

using core::PoseSpec;
using Graph = core::SceneGraph<>;

/// One transform as its writer wrote it.
struct Written {
  std::string topic, parent, child;
  std::int64_t stamp_ns = 0;
  Eigen::Isometry3d X_PC = Eigen::Isometry3d::Identity();
};

struct WrittenBag {
  std::string path;
  std::vector<Written> transforms;
  std::uint64_t messages_on_default_topics = 0, records = 0;
};

Eigen::Isometry3d Iso(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q.normalized().toRotationMatrix();
  X.translation() = p;
  return X;
}

bool DefaultTopic(const std::string& t) {
  return t == "/tf" || t == "/tf_static" || t == "/joint_states";
}

/// Foxglove's fixtures: expected.json "bag_messages" (one list for all its MCAP files).
std::vector<WrittenBag> FoxgloveBags() {
  const std::string dir = SEMGRAPH_ROS_FIXTURES;
  if (!std::filesystem::exists(dir + "/expected.json")) return {};
  const YAML::Node root = YAML::LoadFile(dir + "/expected.json");
  WrittenBag model;
  for (const YAML::Node& m : root["bag_messages"]) {
    const auto topic = m["topic"].as<std::string>();
    ++model.records;
    if (DefaultTopic(topic)) ++model.messages_on_default_topics;
    if (topic != "/tf" && topic != "/tf_static") continue;
    for (const YAML::Node& t : m["value"]["transforms"]) {
      const YAML::Node h = t["header"], tr = t["transform"]["translation"],
                       r = t["transform"]["rotation"];
      model.transforms.push_back(
          {topic, std::string(LiftFrameName(h["frame_id"].as<std::string>())),
           std::string(LiftFrameName(t["child_frame_id"].as<std::string>())),
           h["stamp"]["sec"].as<std::int64_t>() * 1'000'000'000 +
               h["stamp"]["nanosec"].as<std::int64_t>(),
           Iso({tr["x"].as<double>(), tr["y"].as<double>(), tr["z"].as<double>()},
               {r["w"].as<double>(), r["x"].as<double>(), r["y"].as<double>(),
                r["z"].as<double>()})});
    }
  }
  std::vector<WrittenBag> bags;
  for (const YAML::Node& b : root["bags"]) {
    WrittenBag bag = model;
    bag.path = dir + "/" + b["file"].as<std::string>();
    bags.push_back(std::move(bag));
  }
  return bags;
}

/// python3-rosbag's and sqlite3's fixtures: expected.json "bags" {file: {messages: [...]}}.
std::vector<WrittenBag> RosbagBags() {
  const std::string dir = SEMGRAPH_ROS_BAG_FIXTURES;
  if (!std::filesystem::exists(dir + "/expected.json")) return {};
  const YAML::Node root = YAML::LoadFile(dir + "/expected.json");
  std::vector<WrittenBag> bags;
  for (const auto& entry : root["bags"]) {
    WrittenBag bag;
    bag.path = dir + "/" + entry.first.as<std::string>();
    for (const YAML::Node& m : entry.second["messages"]) {
      const auto topic = m["topic"].as<std::string>();
      ++bag.records;
      if (DefaultTopic(topic)) ++bag.messages_on_default_topics;
      if (m["kind"].as<std::string>() != "tf") continue;
      for (const YAML::Node& t : m["value"]["transforms"]) {
        const YAML::Node p = t["translation"], q = t["rotation"];  // q: x, y, z, w
        bag.transforms.push_back(
            {topic, std::string(LiftFrameName(t["frame_id"].as<std::string>())),
             std::string(LiftFrameName(t["child_frame_id"].as<std::string>())),
             t["stamp"][0].as<std::int64_t>() * 1'000'000'000 + t["stamp"][1].as<std::int64_t>(),
             Iso({p[0].as<double>(), p[1].as<double>(), p[2].as<double>()},
                 {q[3].as<double>(), q[0].as<double>(), q[1].as<double>(), q[2].as<double>()})});
      }
    }
    bags.push_back(std::move(bag));
  }
  return bags;
}

std::vector<WrittenBag> AllBags() {
  std::vector<WrittenBag> bags = FoxgloveBags();
  for (WrittenBag& b : RosbagBags()) bags.push_back(std::move(b));
  return bags;
}

Graph LinearGraph() {
  core::TimeOptions time;
  time.window = core::Duration::Seconds(1'000'000);
  time.interpolation = core::Interpolation::kLinear;
  time.sample_capacity = 4096;  // every sample of the bags (1,200 on one edge)
  return std::move(*Graph::Create(time));
}

double Distance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff();
}

TEST(LoadBag, EveryWrittenTransformReadsBackAndChainsCompose) {
  const std::vector<WrittenBag> bags = AllBags();
  ASSERT_GE(bags.size(), 10u) << "the fixture writers did not run";
  for (const WrittenBag& bag : bags) {
    SCOPED_TRACE(bag.path);
    Graph graph = LinearGraph();
    auto report = LoadBag(graph, bag.path, {});
    ASSERT_TRUE(report) << Describe(report.error());
    EXPECT_TRUE(report->findings.empty()) << report->findings.groups()[0].message;
    EXPECT_EQ(report->counts.transforms, bag.transforms.size());
    EXPECT_EQ(report->counts.applied, bag.transforms.size());
    EXPECT_EQ(report->messages, bag.messages_on_default_topics);
    EXPECT_EQ(report->messages + report->skipped, bag.records);
    std::map<std::string, Eigen::Isometry3d> static_of_child;
    for (const Written& w : bag.transforms) {
      const bool is_static = w.topic == "/tf_static";
      if (is_static) static_of_child[w.child] = w.X_PC;
      const PoseSpec spec = PoseSpec::Of(w.child).RelativeTo(w.parent);
      const auto X = is_static
                         ? graph.GetPose(spec, core::Latest())
                         : graph.GetPose(spec, core::At(core::Stamp::Nanoseconds(w.stamp_ns)));
      ASSERT_TRUE(X) << graph.Describe(X.error(), spec);
      EXPECT_LT(Distance(X->value.ToIsometry(), w.X_PC), 1e-12) << w.parent << " -> " << w.child;
      // A chain: every static child of w.child, wrt w.parent at the stamp (Eigen composes the
      // written values).
      if (is_static) continue;
      for (const Written& s : bag.transforms) {
        if (s.topic != "/tf_static" || s.parent != w.child) continue;
        const PoseSpec chain = PoseSpec::Of(s.child).RelativeTo(w.parent);
        const auto X_chain = graph.GetPose(chain, core::At(core::Stamp::Nanoseconds(w.stamp_ns)));
        ASSERT_TRUE(X_chain) << graph.Describe(X_chain.error(), chain);
        EXPECT_LT(Distance(X_chain->value.ToIsometry(), w.X_PC * s.X_PC), 1e-12);
      }
    }
  }
}

TEST(LoadBag, ATimeWindowAppliesStaticTransformsWhateverTheirLogTime) {
  for (const WrittenBag& bag : AllBags()) {
    SCOPED_TRACE(bag.path);
    auto scan = ScanBag(bag.path, {});
    ASSERT_TRUE(scan);
    BagLoadOptions options;
    options.start_ns = scan->last_log_time_ns + 1;  // after every message
    Graph graph = LinearGraph();
    auto report = ApplyBag(graph, bag.path, *scan, options);
    ASSERT_TRUE(report);
    std::size_t statics = 0;
    for (const Written& w : bag.transforms) statics += w.topic == "/tf_static" ? 1 : 0;
    EXPECT_EQ(report->counts.applied, statics);
    EXPECT_EQ(report->counts.transforms, statics);
    for (const Written& w : bag.transforms) {
      if (w.topic != "/tf_static") continue;
      EXPECT_TRUE(graph.GetPose(PoseSpec::Of(w.child).RelativeTo(w.parent))) << w.child;
    }
  }
}

TEST(LoadBag, ACorruptBagIsAnErrorNamingTheFileAndChangesNothing) {
  for (const WrittenBag& bag : AllBags()) {
    if (std::filesystem::is_directory(bag.path)) continue;
    SCOPED_TRACE(bag.path);
    std::ifstream in(bag.path, std::ios::binary);
    std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    // Cut at 90 %: the scan fails before the first transform is applied.
    const std::string cut =
        ::testing::TempDir() + "/cut_" + std::filesystem::path(bag.path).filename().string();
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() * 9 / 10);
    Graph graph = LinearGraph();
    ASSERT_TRUE(graph.AddPose(PoseSpec::Of("x", "X").RelativeTo("odom", "odom"),
                              Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero()));
    const std::string before = core::Dump(graph);
    auto report = LoadBag(graph, cut, {});
    ASSERT_FALSE(report) << "a truncated bag loaded";
    EXPECT_EQ(report.error().file, cut);
    EXPECT_NE(Describe(report.error()).find(cut), std::string::npos);
    EXPECT_EQ(core::Dump(graph), before);
  }
}

TEST(LoadBag, TheRobotDescriptionTopicLoadsTheModelAndJointStatesDriveIt) {
  // Foxglove's MCAP: /robot_description holds a two-link URDF (shoulder: revolute about z), and
  // /joint_states sets the shoulder; the model's pose of arm wrt base_link is then the rotation
  // by the written position, at each joint state's stamp.
  const std::string dir = SEMGRAPH_ROS_FIXTURES;
  if (!std::filesystem::exists(dir + "/expected.json")) GTEST_SKIP() << "no Foxglove fixtures";
  const YAML::Node root = YAML::LoadFile(dir + "/expected.json");
  BagLoadOptions options;
  options.topics.push_back("/robot_description");
  Graph graph = LinearGraph();
  auto report = LoadBag(graph, dir + "/tf_zstd.mcap", options);
  ASSERT_TRUE(report) << Describe(report.error());
  ASSERT_TRUE(report->loaded_robot_description);
  EXPECT_TRUE(report->findings.empty()) << report->findings.groups()[0].message;
  int checked = 0;
  for (const YAML::Node& m : root["bag_messages"]) {
    if (m["topic"].as<std::string>() != "/joint_states") continue;
    const YAML::Node v = m["value"];
    const std::int64_t t = v["header"]["stamp"]["sec"].as<std::int64_t>() * 1'000'000'000 +
                           v["header"]["stamp"]["nanosec"].as<std::int64_t>();
    for (std::size_t i = 0; i < v["name"].size(); ++i) {
      if (v["name"][i].as<std::string>() != "shoulder") continue;
      const double q = v["position"][i].as<double>();
      const auto X = graph.GetPose(PoseSpec::Of("arm").RelativeTo("base_link"),
                                   core::At(core::Stamp::Nanoseconds(t)));
      ASSERT_TRUE(X) << graph.Describe(X.error());
      const Eigen::Matrix3d R = Eigen::AngleAxisd(q, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      EXPECT_LT((X->value.ToIsometry().linear() - R).cwiseAbs().maxCoeff(), 1e-12);
      ++checked;
    }
  }
  EXPECT_GT(checked, 0);
  EXPECT_EQ(report->counts.joint_states, static_cast<std::uint64_t>(checked));
}

// covariance.mcap (written by @mcap/core), ros1_covariance.bag (python3-rosbag) and
// ros2_covariance.db3 (Python's sqlite3, rows of @foxglove/rosmsg2-serialization's CDR): /amcl_pose
// (PoseWithCovarianceStamped, its frame named by pose_topics) and /odom (Odometry). Each good
// message reads back at its stamp: the value and the message's 6x6 exactly (a pose of the child wrt
// the header frame in [header]; the odometry twist in [child] at the child's origin); each bad one
// is a finding naming its topic and stamp, with nothing added at that stamp.
Eigen::Matrix<double, 6, 6> Covariance(const YAML::Node& c) {
  Eigen::Matrix<double, 6, 6> S;
  for (int k = 0; k < 36; ++k) S(k / 6, k % 6) = c[k].as<double>();
  return S;
}

std::int64_t StampOf(const YAML::Node& header) {
  return header["stamp"]["sec"].as<std::int64_t>() * 1'000'000'000 +
         header["stamp"]["nanosec"].as<std::int64_t>();
}

/// Loads `dir`'s covariance bag (expected.json's `key`) and checks it message by message.
void CheckCovarianceBag(const std::string& dir, const char* key = "covariance_bag") {
  if (!std::filesystem::exists(dir + "/expected.json")) GTEST_SKIP() << "no fixtures in " << dir;
  const YAML::Node root = YAML::LoadFile(dir + "/expected.json");
  ASSERT_TRUE(root[key]) << "fixtures written before " << key;
  const YAML::Node bag = root[key];
  Graph graph = LinearGraph();
  BagLoadOptions options;
  options.topics = {"/odom"};
  options.lift.pose_topics = {{"/amcl_pose", "base_footprint"}};
  const auto report = LoadBag(graph, dir + "/" + bag["file"].as<std::string>(), options);
  ASSERT_TRUE(report) << Describe(report.error());
  EXPECT_EQ(report->messages, 6u);
  EXPECT_EQ(report->counts.poses_with_covariance, 2u);
  EXPECT_EQ(report->counts.odometry, 2u);
  EXPECT_EQ(report->counts.covariance_refused, 2u);
  std::size_t bad = 0;
  for (const YAML::Node& m : bag["messages"]) {
    const auto topic = m["topic"].as<std::string>();
    const YAML::Node v = m["value"];
    const std::int64_t stamp_ns = StampOf(v["header"]);
    const auto at = core::At(core::Stamp::Nanoseconds(stamp_ns));
    const std::string parent = v["header"]["frame_id"].as<std::string>();
    const std::string child =
        topic == "/odom" ? v["child_frame_id"].as<std::string>() : std::string("base_footprint");
    const PoseSpec spec = PoseSpec::Of(child).RelativeTo(parent).ExpressedIn(parent);
    if (!m["bad"].IsNull()) {  // a finding naming the topic and the stamp; no sample there
      ASSERT_LT(bad, report->findings.groups().size());
      const FindingGroup& g = report->findings.groups()[bad++];
      EXPECT_EQ(g.topic, topic);
      EXPECT_EQ(g.first_stamp_ns, stamp_ns);
      EXPECT_EQ(g.parent, parent);
      EXPECT_EQ(g.child, child);
      EXPECT_EQ(g.code.name(), topic == "/odom" ? "invalid_number" : "invalid_covariance")
          << g.message;
      const auto explained = graph.ExplainPose(spec, core::Latest());
      ASSERT_TRUE(explained);
      for (const core::EdgeUse& use : *explained) {  // the newest sample is an earlier one's
        ASSERT_TRUE(use.last);
        EXPECT_LT(use.last->nanoseconds(), stamp_ns);
      }
      continue;
    }
    const auto pose = graph.GetPoseWithCovariance(spec, at);
    ASSERT_TRUE(pose) << graph.Describe(pose.error(), spec);
    const YAML::Node p = v["pose"]["pose"]["position"], q = v["pose"]["pose"]["orientation"];
    EXPECT_LE(Distance(pose->value.value.ToIsometry(),
                       Iso({p["x"].as<double>(), p["y"].as<double>(), p["z"].as<double>()},
                           {q["w"].as<double>(), q["x"].as<double>(), q["y"].as<double>(),
                            q["z"].as<double>()})),
              1e-12);
    EXPECT_LE((pose->value.covariance - Covariance(v["pose"]["covariance"])).cwiseAbs().maxCoeff(),
              1e-15);
    if (topic != "/odom") continue;
    const auto body = [&](const std::string& f) {
      return std::string(graph.body_name(graph.body_of(graph.FindFrame(f))));
    };
    const std::string child_body = body(child), parent_body = body(parent);  // the spec views them
    const auto twist_spec =
        core::TwistSpec::Of(child, child_body).RelativeTo(parent_body).ExpressedIn(child);
    const auto twist = graph.GetTwistWithCovariance(twist_spec, at);
    ASSERT_TRUE(twist) << graph.Describe(twist.error(), twist_spec);
    const YAML::Node l = v["twist"]["twist"]["linear"], w = v["twist"]["twist"]["angular"];
    EXPECT_LE((twist->value.value.linear -
               Eigen::Vector3d(l["x"].as<double>(), l["y"].as<double>(), l["z"].as<double>()))
                  .norm(),
              1e-15);
    EXPECT_LE((twist->value.value.angular -
               Eigen::Vector3d(w["x"].as<double>(), w["y"].as<double>(), w["z"].as<double>()))
                  .norm(),
              1e-15);
    EXPECT_LE(
        (twist->value.covariance - Covariance(v["twist"]["covariance"])).cwiseAbs().maxCoeff(),
        1e-15);
  }
  EXPECT_EQ(bad, 2u);
  // /amcl_pose selected by `topics` only: no frame to give its poses, so skipped.
  Graph other = LinearGraph();
  BagLoadOptions frameless;
  frameless.topics = {"/amcl_pose", "/odom"};
  const auto skipped = LoadBag(other, dir + "/" + bag["file"].as<std::string>(), frameless);
  ASSERT_TRUE(skipped) << Describe(skipped.error());
  EXPECT_EQ(skipped->messages, 3u);
  EXPECT_EQ(skipped->skipped, 3u);
  EXPECT_EQ(skipped->counts.poses_with_covariance, 0u);
  EXPECT_EQ(skipped->counts.odometry, 2u);
  EXPECT_FALSE(other.FindFrame("map").is_valid());
}

TEST(LoadBag, PoseAndOdometryMessagesBecomeStampedEdgesWithTheirCovariancesMcap) {
  CheckCovarianceBag(SEMGRAPH_ROS_FIXTURES);  // covariance.mcap, by @mcap/core
}

TEST(LoadBag, PoseAndOdometryMessagesBecomeStampedEdgesWithTheirCovariancesRos1) {
  CheckCovarianceBag(SEMGRAPH_ROS_BAG_FIXTURES);  // ros1_covariance.bag, by python3-rosbag
}

TEST(LoadBag, PoseAndOdometryMessagesBecomeStampedEdgesWithTheirCovariancesSqlite3) {
  // ros2_covariance.db3: Foxglove's CDR bytes of covariance.mcap's messages in rosbag2's schema
  CheckCovarianceBag(SEMGRAPH_ROS_BAG_FIXTURES, "sqlite3_covariance_bag");
}

}  // namespace
}  // namespace semgraph::ros
