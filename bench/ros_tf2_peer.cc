// tf2 behind ros_tf2_peer.h (C++17 translation unit).
#include "ros_tf2_peer.h"

#include <geometry_msgs/TransformStamped.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>

namespace semgraph_bench::rostf2 {
namespace {
ros::Time Time(std::int64_t ns) {
  return ros::Time(static_cast<std::uint32_t>(ns / 1000000000),
                   static_cast<std::uint32_t>(ns % 1000000000));
}
}  // namespace

struct Messages::Impl {
  std::vector<geometry_msgs::TransformStamped> messages;
  std::vector<bool> is_static;
};

Messages::Messages(const std::vector<Transform>& transforms) : impl_(std::make_unique<Impl>()) {
  for (const Transform& t : transforms) {
    geometry_msgs::TransformStamped m;
    m.header.stamp = Time(t.stamp_ns);
    m.header.frame_id = t.parent;
    m.child_frame_id = t.child;
    m.transform.translation.x = t.X_PC.x;
    m.transform.translation.y = t.X_PC.y;
    m.transform.translation.z = t.X_PC.z;
    m.transform.rotation.w = t.X_PC.qw;
    m.transform.rotation.x = t.X_PC.qx;
    m.transform.rotation.y = t.X_PC.qy;
    m.transform.rotation.z = t.X_PC.qz;
    impl_->messages.push_back(m);
    impl_->is_static.push_back(t.is_static);
  }
}
Messages::~Messages() = default;
std::size_t Messages::size() const { return impl_->messages.size(); }

struct Buffer::Impl {
  explicit Impl(double cache_s) : buffer(ros::Duration(cache_s)) {}
  tf2::BufferCore buffer;
  const std::string authority = "bag";
};

Buffer::Buffer(double cache_s) : impl_(std::make_unique<Impl>(cache_s)) {}
Buffer::~Buffer() = default;

std::size_t Buffer::Ingest(const Messages& messages) {
  std::size_t accepted = 0;
  const auto& m = messages.impl_->messages;
  for (std::size_t i = 0; i < m.size(); ++i) {
    accepted += impl_->buffer.setTransform(m[i], impl_->authority, messages.impl_->is_static[i]);
  }
  return accepted;
}

bool Buffer::Lookup(const std::string& relative_to, const std::string& of, std::int64_t t_ns,
                    Pose7& out) const {
  try {
    const auto m = impl_->buffer.lookupTransform(relative_to, of, Time(t_ns));
    const auto& r = m.transform.rotation;
    const auto& p = m.transform.translation;
    out = {r.w, r.x, r.y, r.z, p.x, p.y, p.z};
    return true;
  } catch (const tf2::TransformException&) {
    return false;
  }
}

}  // namespace semgraph_bench::rostf2
