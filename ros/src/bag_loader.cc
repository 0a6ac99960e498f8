// A bag into a scene graph in two passes (bag_loader.h).
#include "semgraph/ros/bag_loader.h"

#include <algorithm>
#include <string_view>
#include <unordered_set>
#include <utility>

#include "json_text.h"
#include "semgraph/models/urdf.h"

namespace semgraph::ros {

namespace {

constexpr std::string_view kStaticTopic = "/tf_static";
constexpr std::string_view kDescriptionTopic = "/robot_description";

/// A topic of `topics`, or a pose topic of the lift (LiftOptions::pose_topics).
bool Selected(const BagLoadOptions& options, std::string_view topic) {
  return std::find(options.topics.begin(), options.topics.end(), topic) != options.topics.end() ||
         options.lift.pose_topics.find(topic) != options.lift.pose_topics.end();
}

bool InWindow(const BagLoadOptions& options, std::int64_t log_time_ns) {
  return (!options.start_ns || log_time_ns >= *options.start_ns) &&
         (!options.end_ns || log_time_ns <= *options.end_ns);
}

/// A decodable message of a selected topic: its kind and encoding are known.
bool Decodable(const BagRecord& r) {
  return r.kind != MessageKind::kOther && r.encoding != MessageEncoding::kOther;
}

template <class M>
Expected<Ok, BagError> Decode(const BagRecord& r, const std::string& path, M& out) {
  const Expected<Ok, CodecError> decoded =
      r.encoding == MessageEncoding::kCdr ? DecodeCdr(r.data, out) : DecodeRos1(r.data, out);
  if (decoded) return Ok{};
  return Unexpected{BagError{
      BagErrorCode::kMalformed, path, 0,
      "the " + std::string(r.type_name) + " message on " + std::string(r.topic) + " at log time " +
          json::Seconds(r.log_time_ns) + " s does not decode: " + Describe(decoded.error())}};
}

/// Reads every record of a bag, calling `visit(record)` (which may fail) for each.
template <class Visit>
Expected<Ok, BagError> ForEachRecord(const std::string& path, const BagLoadOptions& options,
                                     int pass, Visit&& visit) {
  auto reader = OpenBag(path, options.reader);
  if (!reader) return Unexpected{reader.error()};
  BagRecord record;
  std::uint64_t n = 0;
  while (true) {
    const Expected<bool, BagError> more = (*reader)->Next(record);
    if (!more) return Unexpected{more.error()};
    if (!*more) return Ok{};
    if (auto ok = visit(**reader, record); !ok) return ok;
    if (++n % 4096 == 0 && options.progress) options.progress(pass, n, record.log_time_ns);
  }
}

void NoteStamp(BagScan& scan, std::int64_t stamp_ns) {
  if (!scan.has_stamps) {
    scan.has_stamps = true;
    scan.first_stamp_ns = scan.last_stamp_ns = stamp_ns;
  }
  scan.first_stamp_ns = std::min(scan.first_stamp_ns, stamp_ns);
  scan.last_stamp_ns = std::max(scan.last_stamp_ns, stamp_ns);
}

/// The (parent, child) pairs seen by the scan, keyed "parent\nchild" ('\n' is in no valid
/// frame name; an invalid one only shares a key with another invalid one, for `bag info`).
struct SeenPairs {
  std::unordered_set<std::string> keys;
  std::string key;  ///< the lookup buffer: no allocation for a pair seen before
  bool Insert(std::string_view parent, std::string_view child) {
    key.assign(parent).append(1, '\n').append(child);
    return !keys.contains(key) && keys.insert(key).second;
  }
};

/// Pass 1's work on one decodable record of a selected topic.
Expected<Ok, BagError> ScanRecord(const BagRecord& r, const std::string& path, BagScan& scan,
                                  SeenPairs& seen, TFMessage& tf) {
  if (r.kind == MessageKind::kTfMessage) {
    if (auto ok = Decode(r, path, tf); !ok) return ok;
    const bool is_static = r.topic == kStaticTopic;
    for (const TransformStamped& t : tf.transforms) {
      const std::string_view parent = LiftFrameName(t.header.frame_id);
      const std::string_view child = LiftFrameName(t.child_frame_id);
      if (!is_static) NoteStamp(scan, ToNanoseconds(t.header.stamp));
      if (seen.Insert(parent, child) || is_static) {
        (is_static ? scan.statics : scan.dynamics)
            .push_back(StaticEdge{std::string(parent), std::string(child)});
      }
    }
  } else if (r.kind == MessageKind::kJointState) {
    JointState js;
    if (auto ok = Decode(r, path, js); !ok) return ok;
    NoteStamp(scan, ToNanoseconds(js.header.stamp));
  } else if (r.kind == MessageKind::kPoseWithCovarianceStamped) {
    PoseWithCovarianceStamped m;
    if (auto ok = Decode(r, path, m); !ok) return ok;
    NoteStamp(scan, ToNanoseconds(m.header.stamp));
  } else if (r.kind == MessageKind::kOdometry) {
    Odometry m;
    if (auto ok = Decode(r, path, m); !ok) return ok;
    NoteStamp(scan, ToNanoseconds(m.header.stamp));
  } else if (r.kind == MessageKind::kString && r.topic == kDescriptionTopic) {
    String s;
    if (auto ok = Decode(r, path, s); !ok) return ok;
    if (!scan.robot_description) scan.robot_description = std::move(s.data);
  }
  return Ok{};
}

}  // namespace

std::vector<std::string> DefaultBagTopics() { return {"/tf", "/tf_static", "/joint_states"}; }

Expected<BagScan, BagError> ScanBag(const std::string& path, const BagLoadOptions& options) {
  BagScan scan;
  SeenPairs seen;
  TFMessage tf;  // reused: its strings and vectors keep their capacity from message to message
  auto done = ForEachRecord(path, options, 1, [&](const BagReader& reader, const BagRecord& r) {
    if (scan.records++ == 0) scan.first_log_time_ns = r.log_time_ns;
    scan.last_log_time_ns = r.log_time_ns;
    scan.format = reader.format();
    auto it = std::find_if(scan.topics.begin(), scan.topics.end(),
                           [&](const TopicSummary& s) { return s.topic.name == r.topic; });
    if (it == scan.topics.end()) {
      scan.topics.push_back(
          {BagTopic{std::string(r.topic), std::string(r.type_name), r.encoding, r.kind, -1}, 0});
      it = scan.topics.end() - 1;
    }
    ++it->messages;
    if (!Selected(options, r.topic) || !Decodable(r)) return Expected<Ok, BagError>(Ok{});
    return ScanRecord(r, path, scan, seen, tf);
  });
  if (!done) return Unexpected{done.error()};
  return scan;
}

template <coord::Backend B>
Expected<BagLoadReport, BagError> ApplyBag(core::SceneGraph<B>& graph, const std::string& path,
                                           const BagScan& scan, const BagLoadOptions& options,
                                           const models::Robot* robot) {
  auto plan = BodyPlan::Make(options.lift);
  if (!plan) {
    return Unexpected{BagError{BagErrorCode::kMalformed, path, 0, plan.error()}};
  }
  for (const StaticEdge& e : scan.statics) plan->AddStatic(e.parent, e.child);
  TfLift<B> lift(graph, std::move(*plan));
  BagLoadReport report;
  std::optional<models::Robot> loaded;
  if (robot != nullptr) {
    lift.CoverModel(*robot);
  } else if (scan.robot_description) {
    auto model = models::LoadUrdfString(graph, *scan.robot_description);
    if (model) {
      loaded = std::move(*model);
      lift.CoverModel(*loaded);
      report.loaded_robot_description = true;
    }
  }
  // Pass 2 reads the file pass 1 checked: its CRCs are not computed again (a file changed in
  // between may then fail half way, as the header says, or apply what decodes).
  BagLoadOptions unchecked = options;
  unchecked.reader.verify_crc = false;
  TFMessage tf;  // reused, as in pass 1
  auto done = ForEachRecord(path, unchecked, 2, [&](const BagReader&, const BagRecord& r) {
    const bool is_static = r.topic == kStaticTopic;
    const auto child = options.lift.pose_topics.find(r.topic);
    const bool frameless_pose = r.kind == MessageKind::kPoseWithCovarianceStamped &&
                                child == options.lift.pose_topics.end();  // no frame to give it
    if (!Selected(options, r.topic) || !Decodable(r) || frameless_pose ||
        (!is_static && !InWindow(options, r.log_time_ns))) {
      ++report.skipped;
      return Expected<Ok, BagError>(Ok{});
    }
    if (report.messages++ == 0) report.first_log_time_ns = r.log_time_ns;
    report.last_log_time_ns = r.log_time_ns;
    if (r.kind == MessageKind::kString) {  // the URDF: loaded before this pass
      return Expected<Ok, BagError>(Ok{});
    } else if (r.kind == MessageKind::kTfMessage) {
      if (auto ok = Decode(r, path, tf); !ok) return ok;
      lift.Apply(tf, is_static, r.topic, r.log_time_ns);
    } else if (r.kind == MessageKind::kJointState) {
      JointState js;
      if (auto ok = Decode(r, path, js); !ok) return ok;
      lift.Apply(js, r.topic, r.log_time_ns);
    } else if (r.kind == MessageKind::kOdometry) {
      Odometry odometry;
      if (auto ok = Decode(r, path, odometry); !ok) return ok;
      (void)lift.Apply(odometry, r.topic, r.log_time_ns);
    } else {  // a PoseWithCovarianceStamped of a pose topic
      PoseWithCovarianceStamped pose;
      if (auto ok = Decode(r, path, pose); !ok) return ok;
      (void)lift.Apply(pose, child->second, r.topic, r.log_time_ns);
    }
    return Expected<Ok, BagError>(Ok{});
  });
  if (!done) return Unexpected{done.error()};
  lift.Flush();  // covered transforms still waiting for a joint state at their stamp
  report.counts = lift.counts();
  report.findings = lift.findings();
  return report;
}

template <coord::Backend B>
Expected<BagLoadReport, BagError> LoadBag(core::SceneGraph<B>& graph, const std::string& path,
                                          const BagLoadOptions& options,
                                          const models::Robot* robot) {
  auto scan = ScanBag(path, options);
  if (!scan) return Unexpected{scan.error()};
  return ApplyBag(graph, path, *scan, options, robot);
}

#define SEMGRAPH_INSTANTIATE_BAG_LOADER(B)                                                      \
  template Expected<BagLoadReport, BagError> ApplyBag(core::SceneGraph<B>&, const std::string&, \
                                                      const BagScan&, const BagLoadOptions&,    \
                                                      const models::Robot*);                    \
  template Expected<BagLoadReport, BagError> LoadBag(core::SceneGraph<B>&, const std::string&,  \
                                                     const BagLoadOptions&, const models::Robot*);
SEMGRAPH_INSTANTIATE_BAG_LOADER(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_BAG_LOADER(coord::HomogeneousBackend)

}  // namespace semgraph::ros
