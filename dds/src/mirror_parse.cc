// Mirror (mirror.h): a structure sample checked and copied out (ParseStructure), and the
// wire's number checks that values share.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "mirror_impl.h"
#include "semgraph/coord/validate.h"

namespace semgraph::dds::internal {

namespace {

constexpr std::uint32_t kMaxElements = 1u << 20;  // per structure sample
constexpr std::uint32_t kMaxSampleCapacity =
    1u << 20;  // per stamped edge (a hostile one must not exhaust memory)

std::string Str(const char* s) { return s == nullptr ? std::string() : std::string(s); }
bool GoodName(const std::string& s) { return static_cast<bool>(semantics::ValidateName(s)); }

const char* KindName(std::uint8_t k) {
  switch (k) {
    case semgraph_wire_ELEMENT_BODY:
      return "body";
    case semgraph_wire_ELEMENT_FRAME:
      return "frame";
    case semgraph_wire_ELEMENT_POSE:
      return "pose";
    case semgraph_wire_ELEMENT_TWIST:
      return "twist";
    case semgraph_wire_ELEMENT_WRENCH:
      return "wrench";
  }
  return "?";
}

}  // namespace

bool Finite(const double* n, int k) {
  for (int i = 0; i < k; ++i) {
    if (!std::isfinite(n[i])) return false;
  }
  return true;
}
bool UnitQuaternion(const double* n) {  // w x y z, with coord's tolerance
  return coord::ValidateQuaternion(Eigen::Quaterniond(n[0], n[1], n[2], n[3])).has_value();
}
// Stamps the graph accepts (core/time.h).
bool GoodStamp(std::int64_t t) {
  return t >= -core::kMaxStampNanoseconds && t <= core::kMaxStampNanoseconds;
}

using EdgeHeads = std::map<std::pair<std::uint8_t, std::string>, int>;  // (kind, head frame)

namespace {

// One wrench element alone: names, numbers, and its pair (or the reaction's) and id not seen yet.
std::string CheckWrench(const Row& r,
                        std::map<std::pair<std::string, std::string>, std::uint32_t>& seen) {
  if (!GoodName(r.head) || !GoodName(r.head_body) || !GoodName(r.tail_body)) return "invalid name";
  if (!r.tail.empty()) return "a wrench names no reference frame";
  if (r.head_body == r.tail_body) return "a wrench on a body by itself (self_wrench)";
  if (r.stamped && !GoodStamp(r.time_ns)) return "the stamp is out of range (invalid_number)";
  if (HasCovariance(r.cov)) return "a wrench carries no covariance";
  if (!Finite(r.n, 6) || r.n[6] != 0.0) return "a number is not finite (invalid_number)";
  const auto pair = std::minmax(r.head_body, r.tail_body);
  if (!seen.emplace(std::pair{pair.first, pair.second}, r.edge).second)
    return "a second wrench of the same pair of bodies (duplicate_wrench)";
  return {};
}

// Each wrench names bodies and a storage frame this structure declares, the frame one of the
// wrench's `on` body (the publisher's graph stores it so; anything else is malformed).
std::string WrenchesNameDeclared(const OwnerRec& o) {
  std::map<std::string, const std::string*> frames;  // frame -> its body
  std::map<std::string, int> bodies;
  for (const Row& r : o.rows) {
    if (r.kind == semgraph_wire_ELEMENT_BODY) bodies.emplace(r.head, 0);
    if (r.kind == semgraph_wire_ELEMENT_FRAME) frames.emplace(r.head, &r.head_body);
  }
  for (const Row& r : o.rows) {
    if (r.kind != semgraph_wire_ELEMENT_WRENCH) continue;
    const std::string at = "wrench on '" + r.head_body + "' by '" + r.tail_body + "': ";
    if (!bodies.count(r.head_body) || !bodies.count(r.tail_body))
      return at + "a body the structure does not declare (unknown_body)";
    auto f = frames.find(r.head);
    if (f == frames.end()) return at + "storage frame '" + r.head + "' is not declared";
    if (*f->second != r.head_body)
      return at + "storage frame '" + r.head + "' is a frame of '" + *f->second + "', not of '" +
             r.head_body + "'";
  }
  return {};
}

// The structure's elements (bodies, frames, edges) into out->rows; `heads` gets each edge's head.
std::string ParseElements(const semgraph_wire_Structure& s, OwnerRec* out, EdgeHeads& heads) {
  out->rows.clear();
  out->rows.reserve(s.elements._length);
  std::map<std::pair<std::uint8_t, std::uint32_t>, int> ids;
  std::map<std::pair<std::string, std::string>, std::uint32_t> wrenches;  // unordered pair -> id
  for (std::uint32_t i = 0; i < s.elements._length; ++i) {
    const semgraph_wire_Element& e = s.elements._buffer[i];
    Row r;
    r.kind = e.kind;
    r.edge = e.edge;
    r.seq = e.seq;
    r.head = Str(e.head);
    r.head_body = Str(e.head_body);
    r.tail = Str(e.tail);
    r.tail_body = Str(e.tail_body);
    std::copy(e.numbers, e.numbers + 7, r.n);
    std::copy(e.covariance, e.covariance + internal::kPackedCovariance, r.cov);
    r.stamped = e.stamped;
    r.time_ns = e.time_ns;
    r.has_acc = e.has_acceleration;
    std::copy(e.acceleration, e.acceleration + 6, r.acc);
    const std::string at =
        "element " + std::to_string(i) + " (" + KindName(e.kind) + " '" + r.head + "'): ";
    if (e.kind > semgraph_wire_ELEMENT_WRENCH)
      return "element " + std::to_string(i) + ": unknown kind " + std::to_string(e.kind);
    if (r.has_acc && e.kind != semgraph_wire_ELEMENT_TWIST)
      return at + "an acceleration on an element that is not a twist edge";
    if (r.has_acc && !Finite(r.acc, 6))
      return at + "an acceleration number is not finite (invalid_number)";
    if (e.kind == semgraph_wire_ELEMENT_WRENCH) {
      if (std::string why = CheckWrench(r, wrenches); !why.empty()) return at + why;
      if (!ids.emplace(std::pair{e.kind, e.edge}, 0).second)
        return at + "a second wrench with the same id";
      out->any_stamped = out->any_stamped || r.stamped;
      out->rows.push_back(std::move(r));
      continue;
    }
    if (!GoodName(r.head)) return at + "invalid name";
    if (e.kind != semgraph_wire_ELEMENT_BODY && !GoodName(r.head_body))
      return at + "invalid body name";
    if (e.kind >= semgraph_wire_ELEMENT_POSE) {
      if (!GoodName(r.tail)) return at + "invalid reference name";
      if (e.kind == semgraph_wire_ELEMENT_POSE && !GoodName(r.tail_body))
        return at + "invalid reference body name";
      if (!Finite(r.n, 7)) return at + "a number is not finite (invalid_number)";
      if (!Finite(r.cov, internal::kPackedCovariance))
        return at + "a covariance entry is not finite (invalid_number)";
      if (e.kind == semgraph_wire_ELEMENT_POSE && !UnitQuaternion(r.n))
        return at + "not a unit quaternion (invalid_rotation)";
      if (!heads.emplace(std::pair{e.kind, r.head}, 0).second)
        return at + "a second edge into the same frame";
      if (!ids.emplace(std::pair{e.kind, e.edge}, 0).second)
        return at + "a second edge with the same id";
      if (r.stamped && !GoodStamp(r.time_ns))
        return at + "the stamp is out of range (invalid_number)";
      if (r.stamped && e.kind == semgraph_wire_ELEMENT_POSE && r.head_body == r.tail_body) {
        return at + "a constant (same-body) edge cannot be stamped";
      }
      out->any_stamped = out->any_stamped || r.stamped;
    } else if (e.stamped) {
      return at + "only edges can be stamped";
    }
    out->rows.push_back(std::move(r));
  }
  return WrenchesNameDeclared(*out);
}

// The structure's joints into out->joints; a joint owns the edges into its child (`heads`).
std::string ParseJoints(const semgraph_wire_Structure& s, OwnerRec* out, EdgeHeads& heads) {
  if (s.joints._length > kMaxElements) return "more than 1048576 joints";
  if (s.joints._length > 0 && s.joints._buffer == nullptr) return "joints missing";
  out->joints.clear();
  out->joints.reserve(s.joints._length);
  std::map<std::string, int> joint_names;
  std::map<std::uint32_t, int> joint_ids;
  for (std::uint32_t i = 0; i < s.joints._length; ++i) {
    const semgraph_wire_Joint& w = s.joints._buffer[i];
    JointRow j;
    j.id = w.id;
    j.seq = w.seq;
    j.name = Str(w.name);
    j.parent = Str(w.parent);
    j.parent_body = Str(w.parent_body);
    j.child = Str(w.child);
    j.child_body = Str(w.child_body);
    j.mimic = Str(w.mimic);
    std::copy(w.origin, w.origin + 7, j.origin);
    std::copy(w.axis, w.axis + 3, j.axis);
    j.lower = w.lower;
    j.upper = w.upper;
    j.multiplier = w.multiplier;
    j.offset = w.offset;
    j.state = w.state;
    j.q = w.q;
    j.qdot = w.qdot;
    j.time_ns = w.time_ns;
    j.has_qddot = w.has_qddot;
    j.qddot = w.has_qddot ? w.qddot : 0.0;
    const std::string at = "joint " + std::to_string(i) + " ('" + j.name + "'): ";
    if (w.type > semgraph_wire_JOINT_FIXED)
      return at + "unknown joint type " + std::to_string(w.type);
    j.type = static_cast<core::JointType>(w.type);
    if (!GoodName(j.name) || !GoodName(j.parent) || !GoodName(j.parent_body) ||
        !GoodName(j.child) || !GoodName(j.child_body) || (!j.mimic.empty() && !GoodName(j.mimic))) {
      return at + "invalid name";
    }
    const double numbers[] = {j.lower, j.upper, j.multiplier, j.offset, j.q, j.qdot};
    if (!Finite(j.origin, 7) || !Finite(j.axis, 3) || !Finite(numbers, 6)) {
      return at + "a number is not finite (invalid_number)";
    }
    if (!UnitQuaternion(j.origin)) return at + "not a unit quaternion (invalid_rotation)";
    if (w.state > semgraph_wire_JOINT_STATE_STAMPED)
      return at + "unknown state " + std::to_string(w.state);
    if (j.stamped() && !GoodStamp(j.time_ns))
      return at + "the stamp is out of range (invalid_number)";
    if (j.has_qddot && (!std::isfinite(j.qddot) || j.state == semgraph_wire_JOINT_STATE_NONE))
      return at + "qddot is not finite, or given with a joint never set";
    if (!joint_names.emplace(j.name, 0).second) return at + "a second joint of that name";
    if (!joint_ids.emplace(j.id, 0).second) return at + "a second joint with the same id";
    // The joint owns the edges into its child: the owner must not publish them as well.
    if (!heads.emplace(std::pair{std::uint8_t{semgraph_wire_ELEMENT_POSE}, j.child}, 0).second ||
        !heads.emplace(std::pair{std::uint8_t{semgraph_wire_ELEMENT_TWIST}, j.child}, 0).second) {
      return at + "a second edge into the same frame";
    }
    out->any_stamped = out->any_stamped || j.stamped();
    out->joints.push_back(std::move(j));
  }
  return {};
}

// The structure's time options (sample_capacity 0: not given).
std::string ParseTimeOptions(const semgraph_wire_Structure& s, OwnerRec* out) {
  if (s.sample_capacity != 0) {
    if (s.window_ns <= 0) return "time options: the window is not positive (invalid_number)";
    if (s.sample_capacity < 2 || s.sample_capacity > kMaxSampleCapacity) {
      return "time options: sample capacity " + std::to_string(s.sample_capacity) +
             " is outside [2, 1048576]";
    }
    if (s.interpolation > 1 || s.duplicate_stamp > 1)
      return "time options: unknown interpolation or duplicate policy";
    out->has_time = true;
    out->time.window = core::Duration::Nanoseconds(s.window_ns);
    out->time.interpolation = static_cast<core::Interpolation>(s.interpolation);
    out->time.duplicate_stamp = static_cast<core::DuplicatePolicy>(s.duplicate_stamp);
    out->time.sample_capacity = s.sample_capacity;
  }
  return {};
}

}  // namespace

// Checks one structure sample and copies it out; the reason when it is malformed.
std::string ParseStructure(const semgraph_wire_Structure& s, OwnerRec* out) {
  out->owner = Str(s.owner);
  if (!GoodName(out->owner)) return "the owner name is not a valid name";
  if (s.elements._length > kMaxElements) return "more than 1048576 elements";
  if (s.elements._length > 0 && s.elements._buffer == nullptr) return "elements missing";
  out->source = s.source;
  out->started_ns = s.started_ns;
  out->revision = s.revision;
  EdgeHeads heads;
  if (std::string why = ParseElements(s, out, heads); !why.empty()) return why;
  if (std::string why = ParseJoints(s, out, heads); !why.empty()) return why;
  return ParseTimeOptions(s, out);
}

}  // namespace semgraph::dds::internal
