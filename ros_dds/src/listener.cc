// Listener (listener.h): rt/tf, rt/tf_static, rt/joint_states, rt/robot_description and the
// user's pose and odometry topics into a scene graph through TfLift, on one receive thread.
#include "semgraph/ros_dds/listener.h"

#include <atomic>
#include <cstdio>
#include <iterator>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "ros_wire.h"
#include "semgraph/models/urdf.h"

namespace semgraph::ros_dds {

using internal::Entity;

namespace {

constexpr RosTopic kTopics[] = {RosTopic::kRobotDescription, RosTopic::kTfStatic, RosTopic::kTf,
                                RosTopic::kJointStates};
constexpr std::uint32_t kTakeBatch = 16;
constexpr std::size_t kFixedTopics = std::size(kTopics);

}  // namespace

struct Listener::Impl {
  core::SceneGraph<>* graph = nullptr;
  ListenerOptions options;
  std::uint32_t domain = 0;

  mutable std::mutex mutex;  // the graph, the lift, the stats, the model
  std::optional<ros::TfLift<coord::QuaternionBackend>> lift;
  std::optional<models::Robot> robot;
  std::string robot_xml;
  ListenerStats stats;
  std::vector<std::uint64_t> reported;  // per finding group: the count reported so far

  // Receive thread only: decoded messages and the events to report after unlocking.
  ros::TFMessage tf;
  ros::JointState joint_state;
  ros::PoseWithCovarianceStamped pose_message;
  ros::Odometry odometry_message;
  struct FindingEvent {
    ros::FindingGroup group;
    bool first;
  };
  std::vector<FindingEvent> finding_events;
  std::vector<Arrival> arrivals;
  std::vector<std::string> log_lines;

  std::atomic<bool> stop{false};
  std::thread thread;

  // A reader of a topic the user named (LiftOptions::pose_topics, odometry_topics).
  struct UserReader {
    RosTopic kind = RosTopic::kPoseWithCovariance;
    std::string topic;  // the ROS name, e.g. "/amcl_pose"
    std::string frame;  // a pose topic's frame (pose_topics), empty for odometry
    Entity reader;
  };

  void Loop();
  // `user`: the user-named topic `reader` reads, else null.
  void Take(RosTopic topic, dds_entity_t reader, const UserReader* user);
  // Under the lock: one sample of `topic`.
  void Apply(RosTopic topic, const void* sample, std::int64_t log_time_ns, const UserReader* user);
  void ApplyWithCovariance(RosTopic topic, const void* sample, std::int64_t log_time_ns,
                           const UserReader& user);
  void ApplyTf(bool is_static, std::int64_t log_time_ns);
  void ApplyDescription(const char* xml);
  // Under the lock: the finding groups whose count changed since last reported.
  void CollectFindings();
  // Outside the lock: the callbacks.
  void Report();

  // Declared last, destroyed first (the thread is joined before, in ~Listener).
  Entity participant, waitset, guard;
  Entity readers[kFixedTopics];          // in kTopics order; absent topics stay empty
  std::vector<UserReader> user_readers;  // the pose topics (by name), then the odometry topics

  // Subscribes to the user-named topics (in Create).
  base::Expected<base::Ok, std::string> AddUserReader(RosTopic kind, const std::string& topic,
                                                      const std::string& frame);
};

Listener::Listener(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Listener::~Listener() {
  impl_->stop.store(true);
  if (impl_->guard.ok()) (void)dds_set_guardcondition(impl_->guard.get(), true);
  if (impl_->thread.joinable()) impl_->thread.join();
}

base::Expected<std::unique_ptr<Listener>, std::string> Listener::Create(core::SceneGraph<>& graph,
                                                                        ListenerOptions options) {
  auto domain = internal::ResolveDomain(options.domain ? &*options.domain : nullptr);
  if (!domain) return base::Unexpected{domain.error()};
  auto plan = ros::BodyPlan::Make(options.lift);
  if (!plan) return base::Unexpected{"invalid bodies map: " + plan.error()};
  auto impl = std::make_unique<Impl>();
  Impl& m = *impl;
  m.graph = &graph;
  m.options = std::move(options);
  m.domain = *domain;
  if (!m.options.log) {
    m.options.log = [](const std::string& line) {
      std::fprintf(stderr, "semgraph-ros: %s\n", line.c_str());
    };
  }
  m.lift.emplace(graph, std::move(*plan));
  m.participant = Entity(dds_create_participant(m.domain, nullptr, nullptr));
  if (!m.participant.ok()) {
    return base::Unexpected{internal::DdsError("cannot join the DDS domain", m.participant.get())};
  }
  const dds_entity_t p = m.participant.get();
  m.waitset = Entity(dds_create_waitset(p));
  m.guard = Entity(dds_create_guardcondition(p));
  if (!m.waitset.ok() || !m.guard.ok() ||
      dds_waitset_attach(m.waitset.get(), m.guard.get(), 0) < 0) {
    return base::Unexpected{std::string("cannot create the DDS waitset")};
  }
  for (std::size_t i = 0; i < 4; ++i) {
    const RosTopic topic = kTopics[i];
    if ((topic == RosTopic::kJointStates && !m.options.joint_states) ||
        (topic == RosTopic::kRobotDescription && !m.options.robot_description)) {
      continue;
    }
    const dds_entity_t t = internal::CreateTopic(p, topic);
    if (t < 0) {
      return base::Unexpected{internal::DdsError(
          ("cannot create the topic " + std::string(DdsName(topic))).c_str(), t)};
    }
    m.readers[i] = Entity(internal::CreateReader(p, t, topic));
    if (!m.readers[i].ok()) {
      return base::Unexpected{
          internal::DdsError(("cannot create the reader of " + std::string(DdsName(topic))).c_str(),
                             m.readers[i].get())};
    }
    const dds_entity_t c = dds_create_readcondition(m.readers[i].get(), DDS_ANY_STATE);
    if (c < 0 || dds_waitset_attach(m.waitset.get(), c, static_cast<dds_attach_t>(i + 1)) < 0) {
      return base::Unexpected{std::string("cannot attach the DDS read conditions")};
    }
  }
  for (const auto& [topic, frame] : m.options.lift.pose_topics) {
    if (auto added = m.AddUserReader(RosTopic::kPoseWithCovariance, topic, frame); !added) {
      return base::Unexpected{added.error()};
    }
  }
  for (const std::string& topic : m.options.odometry_topics) {
    if (auto added = m.AddUserReader(RosTopic::kOdometry, topic, {}); !added) {
      return base::Unexpected{added.error()};
    }
  }
  m.thread = std::thread([&m] { m.Loop(); });
  return std::unique_ptr<Listener>(new Listener(std::move(impl)));
}

base::Expected<base::Ok, std::string> Listener::Impl::AddUserReader(RosTopic kind,
                                                                    const std::string& topic,
                                                                    const std::string& frame) {
  const char* what = kind == RosTopic::kOdometry ? "odometry topic" : "pose topic";
  for (const UserReader& u : user_readers) {
    if (u.topic == topic) {
      return base::Unexpected{std::string(what) + " " + topic + " is also a " +
                              (u.kind == RosTopic::kOdometry ? "odometry" : "pose") + " topic"};
    }
  }
  auto dds_name = DdsTopicName(topic);
  if (!dds_name) return base::Unexpected{std::string(what) + ": " + dds_name.error()};
  if (kind == RosTopic::kPoseWithCovariance && ros::LiftFrameName(frame).empty()) {
    return base::Unexpected{std::string(what) + " " + topic + " has no frame"};
  }
  const dds_entity_t t = internal::CreateTopic(participant.get(), kind, *dds_name);
  if (t < 0) {
    return base::Unexpected{
        internal::DdsError(("cannot create the topic " + *dds_name).c_str(), t)};
  }
  Entity reader(internal::CreateReader(participant.get(), t, kind));
  if (!reader.ok()) {
    return base::Unexpected{
        internal::DdsError(("cannot create the reader of " + *dds_name).c_str(), reader.get())};
  }
  const dds_entity_t c = dds_create_readcondition(reader.get(), DDS_ANY_STATE);
  const auto attach = static_cast<dds_attach_t>(kFixedTopics + 1 + user_readers.size());
  if (c < 0 || dds_waitset_attach(waitset.get(), c, attach) < 0) {
    return base::Unexpected{std::string("cannot attach the DDS read conditions")};
  }
  user_readers.push_back({kind, topic, frame, std::move(reader)});
  return base::Ok{};
}

void Listener::Impl::Loop() {
  while (!stop.load()) {
    (void)dds_waitset_wait(waitset.get(), nullptr, 0, DDS_MSECS(100));
    if (stop.load()) break;
    for (std::size_t i = 0; i < kFixedTopics; ++i) {
      if (readers[i].ok()) Take(kTopics[i], readers[i].get(), nullptr);
    }
    for (const UserReader& u : user_readers) Take(u.kind, u.reader.get(), &u);
  }
}

void Listener::Impl::Take(RosTopic topic, dds_entity_t reader, const UserReader* user) {
  for (;;) {
    void* samples[kTakeBatch] = {nullptr};  // null: Cyclone lends its buffers
    dds_sample_info_t infos[kTakeBatch];
    const dds_return_t n = dds_take(reader, samples, infos, kTakeBatch, kTakeBatch);
    if (n <= 0) return;
    {
      std::lock_guard<std::mutex> lock(mutex);
      for (dds_return_t i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        Apply(topic, samples[i], dds_time(), user);
        Arrival a;
        a.topic = topic;
        a.source_timestamp_ns = infos[i].source_timestamp;
        a.applied_ns = dds_time();
        a.transforms =
            topic == RosTopic::kTf || topic == RosTopic::kTfStatic ? tf.transforms.size() : 0;
        arrivals.push_back(a);
      }
    }
    (void)dds_return_loan(reader, samples, n);
    Report();
  }
}

void Listener::Impl::Apply(RosTopic topic, const void* sample, std::int64_t log_time_ns,
                           const UserReader* user) {
  switch (topic) {
    case RosTopic::kTf:
    case RosTopic::kTfStatic:
      internal::FromWire(*static_cast<const tf2_msgs_msg_dds__TFMessage_*>(sample), tf);
      ++(topic == RosTopic::kTf ? stats.tf : stats.tf_static);
      ApplyTf(topic == RosTopic::kTfStatic, log_time_ns);
      break;
    case RosTopic::kJointStates: {
      internal::FromWire(*static_cast<const sensor_msgs_msg_dds__JointState_*>(sample),
                         joint_state);
      ++stats.joint_states;
      const std::uint64_t before = lift->findings().total();
      lift->Apply(joint_state, RosName(topic), log_time_ns);
      if (lift->findings().total() != before) CollectFindings();
      break;
    }
    case RosTopic::kRobotDescription:
      ++stats.robot_descriptions;
      ApplyDescription(static_cast<const std_msgs_msg_dds__String_*>(sample)->data_);
      break;
    case RosTopic::kPoseWithCovariance:
    case RosTopic::kOdometry:
      ApplyWithCovariance(topic, sample, log_time_ns, *user);
      break;
  }
  stats.counts = lift->counts();
}

void Listener::Impl::ApplyWithCovariance(RosTopic topic, const void* sample,
                                         std::int64_t log_time_ns, const UserReader& user) {
  // The same lift as a bag's (TfLift::Apply): checked before the graph is touched.
  const std::uint64_t before = lift->findings().total();
  if (topic == RosTopic::kOdometry) {
    internal::FromWire(*static_cast<const nav_msgs_msg_dds__Odometry_*>(sample), odometry_message);
    ++stats.odometry;
    (void)lift->Apply(odometry_message, user.topic, log_time_ns);
  } else {
    internal::FromWire(
        *static_cast<const geometry_msgs_msg_dds__PoseWithCovarianceStamped_*>(sample),
        pose_message);
    ++stats.poses_with_covariance;
    (void)lift->Apply(pose_message, ros::LiftFrameName(user.frame), user.topic, log_time_ns);
  }
  if (lift->findings().total() != before) CollectFindings();
}

void Listener::Impl::ApplyTf(bool is_static, std::int64_t log_time_ns) {
  const std::string_view topic = RosName(is_static ? RosTopic::kTfStatic : RosTopic::kTf);
  for (const ros::TransformStamped& t : tf.transforms) {
    // Live, the plan learns each static link as it arrives (a bag's plan knows them all first).
    if (is_static) {
      lift->plan().AddStatic(ros::LiftFrameName(t.header.frame_id),
                             ros::LiftFrameName(t.child_frame_id));
    }
    const std::uint64_t before = lift->findings().total();
    (void)lift->Apply(t, is_static, topic, log_time_ns);
    if (lift->findings().total() != before) CollectFindings();
  }
}

void Listener::Impl::ApplyDescription(const char* xml) {
  const std::string_view text = xml != nullptr ? xml : "";
  if (robot) {
    if (text != robot_xml) {
      log_lines.push_back(
          "a changed /robot_description is not applied: the graph keeps the model of robot '" +
          robot->name + "'");
    }
    return;
  }
  auto model = models::LoadUrdfString(*graph, text);
  if (!model) {
    log_lines.push_back("the URDF on /robot_description does not load: " + model.error().message);
    return;
  }
  robot = std::move(*model);
  robot_xml.assign(text);
  lift->CoverModel(*robot);
  stats.robot_loaded = true;
}

void Listener::Impl::CollectFindings() {
  const std::vector<ros::FindingGroup>& groups = lift->findings().groups();
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const bool first = i >= reported.size();
    if (first) reported.push_back(0);
    if (groups[i].count == reported[i]) continue;
    reported[i] = groups[i].count;
    if (options.on_finding) finding_events.push_back({groups[i], first});
  }
}

void Listener::Impl::Report() {
  for (const FindingEvent& e : finding_events) options.on_finding(e.group, e.first);
  finding_events.clear();
  if (options.on_arrival) {
    for (const Arrival& a : arrivals) options.on_arrival(a);
  }
  arrivals.clear();
  for (const std::string& line : log_lines) options.log(line);
  log_lines.clear();
}

void Listener::WithGraph(const std::function<void(const core::SceneGraph<>&)>& fn) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  fn(*impl_->graph);
}

ListenerStats Listener::stats() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->stats;
}

std::vector<ros::FindingGroup> Listener::findings() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->lift->findings().groups();
}

bool Listener::WaitUntil(const std::function<bool()>& pred,
                         std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!pred()) {
    if (std::chrono::steady_clock::now() >= deadline) return pred();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

std::uint32_t Listener::publishers(std::string_view ros_topic) const noexcept {
  for (const Impl::UserReader& u : impl_->user_readers) {  // fixed after Create: no lock
    if (u.topic != ros_topic) continue;
    dds_subscription_matched_status_t status{};
    if (dds_get_subscription_matched_status(u.reader.get(), &status) != DDS_RETCODE_OK) return 0;
    return status.current_count;
  }
  return 0;
}

std::uint32_t Listener::domain() const noexcept { return impl_->domain; }

std::uint32_t Listener::tf_publishers() const noexcept {
  dds_subscription_matched_status_t status{};
  const dds_entity_t reader = impl_->readers[2].get();  // kTopics[2] is rt/tf
  if (dds_get_subscription_matched_status(reader, &status) != DDS_RETCODE_OK) return 0;
  return status.current_count;
}

}  // namespace semgraph::ros_dds
