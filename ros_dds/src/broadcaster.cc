// Broadcaster (broadcaster.h): a graph's pose edges as tf on rt/tf and rt/tf_static.
#include "semgraph/ros_dds/broadcaster.h"

#include <limits>
#include <vector>

#include "ros_wire.h"

namespace semgraph::ros_dds {

using internal::Entity;

struct Broadcaster::Impl {
  const core::SceneGraph<>* graph = nullptr;
  std::uint32_t domain = 0;
  std::function<std::int64_t()> clock;
  // Per frame (the pose edge into it): the newest stamp sent; kNone: none yet.
  static constexpr std::int64_t kNone = std::numeric_limits<std::int64_t>::min();
  std::vector<std::int64_t> sent_stamp;
  ros::TFMessage last_static;
  bool static_sent = false;
  // Reused between calls.
  ros::TFMessage tf, tf_static;
  internal::WireTf wire;

  // The new samples of every stamped edge (into `out`), and their newest stamps per frame
  // (into `newest`, when given).
  void CollectSamples(ros::TFMessage& out, std::vector<std::int64_t>* newest) const;
  // Every timeless edge, stamped `stamp_ns`.
  void CollectStatic(ros::TFMessage& out, std::int64_t stamp_ns) const;

  // Declared last, destroyed first.
  Entity participant, tf_writer, static_writer;
};

namespace {

ros::TransformStamped Row(std::string_view parent, std::string_view child, std::int64_t stamp_ns,
                          const Eigen::Quaterniond& q_TH, const Eigen::Vector3d& p_ToHo_T) {
  ros::TransformStamped t;
  t.header.stamp = internal::TimeFromNanoseconds(stamp_ns);
  t.header.frame_id.assign(parent);
  t.child_frame_id.assign(child);
  t.transform.translation = {p_ToHo_T.x(), p_ToHo_T.y(), p_ToHo_T.z()};
  t.transform.rotation = {q_TH.x(), q_TH.y(), q_TH.z(), q_TH.w()};
  return t;
}

// Equal transforms, stamps aside (a static message is re-sent only when its content changed).
bool SameContent(const ros::TFMessage& a, const ros::TFMessage& b) {
  if (a.transforms.size() != b.transforms.size()) return false;
  for (std::size_t i = 0; i < a.transforms.size(); ++i) {
    const ros::TransformStamped& x = a.transforms[i];
    const ros::TransformStamped& y = b.transforms[i];
    if (x.header.frame_id != y.header.frame_id || x.child_frame_id != y.child_frame_id ||
        !(x.transform == y.transform)) {
      return false;
    }
  }
  return true;
}

}  // namespace

void Broadcaster::Impl::CollectSamples(ros::TFMessage& out,
                                       std::vector<std::int64_t>* newest) const {
  const core::SceneGraph<>& g = *graph;
  out.transforms.clear();
  for (std::uint32_t i = 0; i < g.num_frames(); ++i) {
    const core::FrameIndex f(i);
    const core::FrameIndex t = g.pose_parent(f);
    const core::PoseHistory* h = t.is_valid() ? g.pose_history(f) : nullptr;
    if (h == nullptr) continue;
    const std::int64_t after = i < sent_stamp.size() ? sent_stamp[i] : kNone;
    if (after == std::numeric_limits<std::int64_t>::max()) continue;  // nothing can be newer
    const std::string_view parent = g.frame_name(t), child = g.frame_name(f);
    // Walk the history from the first stamp after `after`: Find's bracket names the next one.
    core::PoseHistory::Bracket b;
    std::int64_t at = after == kNone ? kNone : after + 1;
    std::int64_t last = after;
    while (true) {
      h->Find(at, b);
      if (b.where == core::PoseHistory::Bracket::Where::kAfter) break;
      const bool first = b.where == core::PoseHistory::Bracket::Where::kBefore || b.exact;
      const std::int64_t stamp = first ? b.s0 : b.s1;
      const double* v = first ? b.v0 : b.v1;  // x y z w, then p
      out.transforms.push_back(Row(parent, child, stamp, Eigen::Quaterniond(v[3], v[0], v[1], v[2]),
                                   Eigen::Vector3d(v[4], v[5], v[6])));
      last = stamp;
      if (stamp == std::numeric_limits<std::int64_t>::max()) break;
      at = stamp + 1;
    }
    if (newest != nullptr) (*newest)[i] = last;
  }
}

void Broadcaster::Impl::CollectStatic(ros::TFMessage& out, std::int64_t stamp_ns) const {
  const core::SceneGraph<>& g = *graph;
  out.transforms.clear();
  for (std::uint32_t i = 0; i < g.num_frames(); ++i) {
    const core::FrameIndex f(i);
    const core::FrameIndex t = g.pose_parent(f);
    if (!t.is_valid() || g.pose_history(f) != nullptr) continue;
    const auto X_TH = g.pose_value(f);
    out.transforms.push_back(
        Row(g.frame_name(t), g.frame_name(f), stamp_ns, X_TH.rotation, X_TH.translation));
  }
}

Broadcaster::Broadcaster(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Broadcaster::~Broadcaster() = default;

base::Expected<std::unique_ptr<Broadcaster>, std::string> Broadcaster::Create(
    const core::SceneGraph<>& graph, BroadcasterOptions options) {
  auto domain = internal::ResolveDomain(options.domain ? &*options.domain : nullptr);
  if (!domain) return base::Unexpected{domain.error()};
  auto impl = std::make_unique<Impl>();
  impl->graph = &graph;
  impl->domain = *domain;
  impl->clock = options.clock ? std::move(options.clock) : [] { return dds_time(); };
  impl->participant = Entity(dds_create_participant(*domain, nullptr, nullptr));
  if (!impl->participant.ok()) {
    return base::Unexpected{
        internal::DdsError("cannot join the DDS domain", impl->participant.get())};
  }
  const dds_entity_t p = impl->participant.get();
  const dds_entity_t tf = internal::CreateTopic(p, RosTopic::kTf);
  const dds_entity_t st = internal::CreateTopic(p, RosTopic::kTfStatic);
  if (tf < 0 || st < 0) {
    return base::Unexpected{
        internal::DdsError("cannot create rt/tf and rt/tf_static", tf < 0 ? tf : st)};
  }
  impl->tf_writer = Entity(internal::CreateWriter(p, tf, RosTopic::kTf));
  impl->static_writer = Entity(internal::CreateWriter(p, st, RosTopic::kTfStatic));
  if (!impl->tf_writer.ok() || !impl->static_writer.ok()) {
    return base::Unexpected{internal::DdsError(
        "cannot create the tf writers",
        impl->tf_writer.ok() ? impl->static_writer.get() : impl->tf_writer.get())};
  }
  return std::unique_ptr<Broadcaster>(new Broadcaster(std::move(impl)));
}

base::Expected<BroadcastCounts, std::string> Broadcaster::Broadcast() {
  Impl& m = *impl_;
  BroadcastCounts counts;
  std::vector<std::int64_t> newest(m.graph->num_frames(), Impl::kNone);
  for (std::size_t i = 0; i < newest.size() && i < m.sent_stamp.size(); ++i) {
    newest[i] = m.sent_stamp[i];
  }
  m.CollectSamples(m.tf, &newest);
  m.CollectStatic(m.tf_static, 0);
  // Nothing static to say yet: no message (a graph with stamped edges only).
  const bool static_changed =
      m.static_sent ? !SameContent(m.tf_static, m.last_static) : !m.tf_static.transforms.empty();
  if (static_changed) {
    const ros::Time stamp = internal::TimeFromNanoseconds(m.clock());
    for (ros::TransformStamped& t : m.tf_static.transforms) t.header.stamp = stamp;
    if (auto ok = m.wire.Set(m.tf_static); !ok) return base::Unexpected{ok.error()};
    const dds_return_t rc = dds_write(m.static_writer.get(), &m.wire.sample());
    if (rc != DDS_RETCODE_OK) {
      return base::Unexpected{internal::DdsError("cannot write rt/tf_static", rc)};
    }
    m.last_static = m.tf_static;
    m.static_sent = true;
    counts.static_transforms = m.tf_static.transforms.size();
  }
  if (!m.tf.transforms.empty()) {
    if (auto ok = m.wire.Set(m.tf); !ok) return base::Unexpected{ok.error()};
    const dds_return_t rc = dds_write(m.tf_writer.get(), &m.wire.sample());
    if (rc != DDS_RETCODE_OK) return base::Unexpected{internal::DdsError("cannot write rt/tf", rc)};
    counts.tf_transforms = m.tf.transforms.size();
  }
  m.sent_stamp = std::move(newest);
  return counts;
}

void Broadcaster::Rewind() noexcept { impl_->sent_stamp.clear(); }

void Broadcaster::Pending(ros::TFMessage& tf, ros::TFMessage& tf_static) const {
  impl_->CollectSamples(tf, nullptr);
  impl_->CollectStatic(tf_static, impl_->clock());
}

const ros::TFMessage& Broadcaster::last_static() const noexcept { return impl_->last_static; }
std::uint32_t Broadcaster::domain() const noexcept { return impl_->domain; }

base::Expected<base::Ok, std::string> Broadcaster::WaitForSubscribers(
    std::uint32_t count, std::chrono::milliseconds timeout) {
  const tf2_msgs_msg_dds__TFMessage_ key{};  // keyless: any sample names the one instance
  const dds_return_t rc =
      dds_shared::SyncWithReaders(impl_->tf_writer.get(), count, DDS_MSECS(timeout.count()), &key);
  if (rc == DDS_RETCODE_OK) return base::Ok{};
  if (rc != DDS_RETCODE_TIMEOUT) return base::Unexpected{internal::DdsError("rt/tf", rc)};
  return base::Unexpected{std::to_string(subscribers()) + " subscriber(s) matched on rt/tf of " +
                          std::to_string(count) + " expected, or not all in sync, within " +
                          std::to_string(timeout.count()) + " ms"};
}

std::uint32_t Broadcaster::subscribers_matched() const noexcept {
  dds_publication_matched_status_t status{};
  const dds_entity_t writer = impl_->tf_writer.get();
  if (dds_get_publication_matched_status(writer, &status) != DDS_RETCODE_OK) return 0;
  return status.total_count;
}

std::uint32_t Broadcaster::subscribers() const noexcept {
  dds_publication_matched_status_t status{};
  const dds_entity_t writer = impl_->tf_writer.get();
  if (dds_get_publication_matched_status(writer, &status) != DDS_RETCODE_OK) return 0;
  return status.current_count;
}

ros::BodiesMap BodiesOf(const core::SceneGraph<>& graph) {
  ros::BodiesMap map;
  for (std::uint32_t i = 0; i < graph.num_frames(); ++i) {
    const core::FrameIndex f(i);
    map[std::string(graph.body_name(graph.body_of(f)))].emplace_back(graph.frame_name(f));
  }
  return map;
}

}  // namespace semgraph::ros_dds
