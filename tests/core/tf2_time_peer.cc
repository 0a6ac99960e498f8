// tf2 behind tf2_time_peer.h (C++17 translation unit).
#include "tf2_time_peer.h"

#include <geometry_msgs/TransformStamped.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>

namespace semgraph_test::tf2time {
namespace {
ros::Time Time(std::int64_t ns) {
  return ros::Time(static_cast<std::uint32_t>(ns / 1000000000),
                   static_cast<std::uint32_t>(ns % 1000000000));
}
void Fill(const geometry_msgs::TransformStamped& m, Pose7& out) {
  const auto& r = m.transform.rotation;
  const auto& p = m.transform.translation;
  out = {r.w, r.x, r.y, r.z, p.x, p.y, p.z};
}
}  // namespace

struct Buffer::Impl {
  tf2::BufferCore buffer{ros::Duration(100.0)};
};

Buffer::Buffer() : impl_(std::make_unique<Impl>()) {}
Buffer::~Buffer() = default;

bool Buffer::Set(const std::string& parent, const std::string& child, const Pose7& x,
                 std::int64_t t_ns, bool is_static) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = Time(t_ns);
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.transform.translation.x = x.x;
  m.transform.translation.y = x.y;
  m.transform.translation.z = x.z;
  m.transform.rotation.w = x.qw;
  m.transform.rotation.x = x.qx;
  m.transform.rotation.y = x.qy;
  m.transform.rotation.z = x.qz;
  return impl_->buffer.setTransform(m, "test", is_static);
}

bool Buffer::Lookup(const std::string& target, const std::string& source, std::int64_t t_ns,
                    Pose7& out, std::int64_t* stamp_ns) const {
  try {
    const auto m =
        impl_->buffer.lookupTransform(target, source, t_ns == 0 ? ros::Time(0) : Time(t_ns));
    Fill(m, out);
    if (stamp_ns) *stamp_ns = static_cast<std::int64_t>(m.header.stamp.toNSec());
    return true;
  } catch (const tf2::TransformException&) {
    return false;
  }
}

bool Buffer::LookupFixed(const std::string& target, std::int64_t t_target,
                         const std::string& source, std::int64_t t_source, const std::string& fixed,
                         Pose7& out) const {
  try {
    Fill(impl_->buffer.lookupTransform(target, Time(t_target), source, Time(t_source), fixed), out);
    return true;
  } catch (const tf2::TransformException&) {
    return false;
  }
}

}  // namespace semgraph_test::tf2time
