// tf2 behind tf2_peer.h. Compiled as C++17 (see the header). Set-ups: bench/README.md.
#include "tf2_peer.h"

#include <benchmark/benchmark.h>
#include <geometry_msgs/TransformStamped.h>
#include <tf2/buffer_core.h>

namespace semgraph_bench::tf2peer {
namespace {

geometry_msgs::TransformStamped Message(const std::string& parent, const std::string& child,
                                        const Pose7& x, double t) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = ros::Time(t);
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.transform.translation.x = x.x;
  m.transform.translation.y = x.y;
  m.transform.translation.z = x.z;
  m.transform.rotation.w = x.qw;
  m.transform.rotation.x = x.qx;
  m.transform.rotation.y = x.qy;
  m.transform.rotation.z = x.qz;
  return m;
}

}  // namespace

struct Chain::Impl {
  tf2::BufferCore buffer;
  std::string target = "f0", source;
  ros::Time time;
};

Chain::Chain(const std::vector<Pose7>& links, const std::vector<Pose7>* links_at_2s)
    : impl_(std::make_unique<Impl>()) {
  const std::size_t d = links.size();
  impl_->source = "f" + std::to_string(d);
  impl_->time = links_at_2s ? ros::Time(1.5) : ros::Time(0);
  for (std::size_t i = 1; i <= d; ++i) {
    const std::string parent = "f" + std::to_string(i - 1), child = "f" + std::to_string(i);
    if (!links_at_2s) {
      impl_->buffer.setTransform(Message(parent, child, links[i - 1], 0.0), "bench", true);
    } else {
      impl_->buffer.setTransform(Message(parent, child, links[i - 1], 1.0), "bench", false);
      impl_->buffer.setTransform(Message(parent, child, (*links_at_2s)[i - 1], 2.0), "bench",
                                 false);
    }
  }
}

Chain::~Chain() = default;

Pose7 Chain::Lookup() const {
  const geometry_msgs::TransformStamped out =
      impl_->buffer.lookupTransform(impl_->target, impl_->source, impl_->time);
  const auto& r = out.transform.rotation;
  const auto& p = out.transform.translation;
  return {r.w, r.x, r.y, r.z, p.x, p.y, p.z};
}

void Chain::LookupOnce() const {
  const geometry_msgs::TransformStamped out =
      impl_->buffer.lookupTransform(impl_->target, impl_->source, impl_->time);
  benchmark::DoNotOptimize(out);  // out is const: the input-only overload
}

struct TreeMessages::Impl {
  std::vector<geometry_msgs::TransformStamped> messages;
};

TreeMessages::TreeMessages(const std::vector<std::string>& frames,
                           const std::vector<std::uint32_t>& parent,
                           const std::vector<Pose7>& poses)
    : impl_(std::make_unique<Impl>()) {
  impl_->messages.reserve(frames.size());
  for (std::size_t i = 1; i < frames.size(); ++i) {
    impl_->messages.push_back(Message(frames[parent[i]], frames[i], poses[i], 0.0));
  }
}

TreeMessages::~TreeMessages() = default;

std::size_t TreeMessages::size() const { return impl_->messages.size(); }

struct Buffer::Impl {
  tf2::BufferCore buffer;
};

Buffer::Buffer() : impl_(std::make_unique<Impl>()) {}

Buffer::~Buffer() = default;

bool Buffer::InsertAllStatic(const TreeMessages& messages) {
  bool ok = true;
  for (const auto& m : messages.impl_->messages) ok &= impl_->buffer.setTransform(m, "bench", true);
  return ok;
}

void Buffer::LookupOnce(const std::string& target, const std::string& source) const {
  const geometry_msgs::TransformStamped out =
      impl_->buffer.lookupTransform(target, source, ros::Time(0));
  benchmark::DoNotOptimize(out);
}

Pose7 Buffer::Lookup(const std::string& target, const std::string& source) const {
  const geometry_msgs::TransformStamped out =
      impl_->buffer.lookupTransform(target, source, ros::Time(0));
  const auto& q = out.transform.rotation;
  const auto& p = out.transform.translation;
  return Pose7{q.w, q.x, q.y, q.z, p.x, p.y, p.z};
}

}  // namespace semgraph_bench::tf2peer
