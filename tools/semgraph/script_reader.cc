// Scene-script reader: the schema of a scene script over the generic YAML tree (yaml_tree.h).
// Contract: script_reader.h and docs/scene-script.md.
//
// The Interpreter walks only the shapes a script may have, so its work is bounded by the
// number of ops and fields, which the tree's expanded-size limit bounds whatever aliases the
// document contains.
#include "semgraph/script_reader.h"

#include <algorithm>
#include <set>
#include <span>
#include <utility>

#include "semgraph/core/time.h"

namespace semgraph::script {

namespace {

using base::Unexpected;

// ====================================================================== op shapes

enum Field : int {
  kOp,
  kKind,
  kName,
  kBody,
  kOf,
  kWrt,
  kPoint,
  kOrientation,
  kRefPoint,
  kRefOrientation,
  kRefBody,
  kCoord,
  kPosition,
  kRotation,
  kLinear,
  kAngular,
  kFile,
  kPrefix,
  kType,
  kParent,
  kChild,
  kParentBody,
  kChildBody,
  kAxis,
  kLower,
  kUpper,
  kMimic,
  kPositions,
  kVelocities,
  kRepair,
  kStamp,
  kAt,
  kMaxExtrapolation,
  kNotBefore,
  kRefAt,
  kFixed,
  kSource,
  kTopics,
  kStatic,
  kBodies,
  kPoseTopics,
  kStart,
  kEnd,
  kCovariance,
  kCovarianceOrder,
  kOn,
  kBy,
  kForce,
  kMoment,
  kAcceleration,
  kAccelerations,
  kNumFields,
};
constexpr Field kNoField = kNumFields;

constexpr std::string_view kFieldNames[kNumFields] = {"op",
                                                      "kind",
                                                      "name",
                                                      "body",
                                                      "of",
                                                      "wrt",
                                                      "point",
                                                      "orientation",
                                                      "ref_point",
                                                      "ref_orientation",
                                                      "ref_body",
                                                      "coord",
                                                      "position",
                                                      "rotation",
                                                      "linear",
                                                      "angular",
                                                      "file",
                                                      "prefix",
                                                      "type",
                                                      "parent",
                                                      "child",
                                                      "parent_body",
                                                      "child_body",
                                                      "axis",
                                                      "lower",
                                                      "upper",
                                                      "mimic",
                                                      "positions",
                                                      "velocities",
                                                      "repair",
                                                      "stamp",
                                                      "at",
                                                      "max_extrapolation",
                                                      "not_before",
                                                      "ref_at",
                                                      "fixed",
                                                      "source",
                                                      "topics",
                                                      "static",
                                                      "bodies",
                                                      "pose_topics",
                                                      "start",
                                                      "end",
                                                      "covariance",
                                                      "covariance_order",
                                                      "on",
                                                      "by",
                                                      "force",
                                                      "moment",
                                                      "acceleration",
                                                      "accelerations"};

static_assert(kFieldNames[kNumFields - 1] == "accelerations", "one name per Field, in order");
static_assert(kNumFields <= 64, "fields are bits of a uint64_t");

constexpr std::uint64_t Bit(Field f) { return std::uint64_t{1} << f; }

// One op variant: the fields it accepts and the ones it needs. A required field may be
// supplied by a shorthand instead (`of` for point/orientation, `wrt` for the reference side).
struct Requirement {
  Field field;
  Field shorthand;  // kNoField: none
};
struct Shape {
  std::string_view label;  // for messages: "a 'pose' op", "a 'position' query"
  std::uint64_t allowed = 0;
  std::vector<Requirement> required;
};

Shape ShapeOf(OpKind op, QueryKind query) {
  constexpr std::uint64_t kHeader = Bit(kOp) | Bit(kKind);
  constexpr std::uint64_t kShorthand = Bit(kOf) | Bit(kWrt);
  // Time (the document's Time section): a query's policy (every kind), time travel for the
  // pose kinds, the twist source for the velocity kinds.
  constexpr std::uint64_t kQueryTime = Bit(kAt) | Bit(kMaxExtrapolation) | Bit(kNotBefore);
  constexpr std::uint64_t kPoseTime = kQueryTime | Bit(kRefAt) | Bit(kFixed);
  constexpr std::uint64_t kTwistTime = kQueryTime | Bit(kSource);
  constexpr std::uint64_t kPoseNames = kShorthand | Bit(kPoint) | Bit(kOrientation) | Bit(kBody) |
                                       Bit(kRefPoint) | Bit(kRefOrientation) | Bit(kRefBody) |
                                       Bit(kCoord);
  constexpr std::uint64_t kTwistNames = Bit(kPoint) | Bit(kBody) | Bit(kRefBody) | Bit(kCoord);
  // Uncertainty (docs/uncertainty.md): every value query may ask for its answer's covariance;
  // the 6x6 answers (pose, twist) may also name its order.
  constexpr std::uint64_t kCov3 = Bit(kCovariance);
  constexpr std::uint64_t kCov6 = kCov3 | Bit(kCovarianceOrder);
  constexpr std::uint64_t kWrenchNames = Bit(kOn) | Bit(kBy) | Bit(kPoint) | Bit(kCoord);
  const std::vector<Requirement> pose_required = {{kPoint, kOf},
                                                  {kOrientation, kOf},
                                                  {kRefPoint, kWrt},
                                                  {kRefOrientation, kWrt},
                                                  {kCoord, kWrt}};
  const std::vector<Requirement> twist_required = {
      {kPoint, kNoField}, {kRefBody, kNoField}, {kCoord, kNoField}};
  switch (op) {
    case OpKind::kBody:
      return {"a 'body' op", Bit(kOp) | Bit(kName), {{kName, kNoField}}};
    case OpKind::kFrame:
      // `body` is optional: a frame without it is the op error frame_without_body (spec).
      return {"a 'frame' op", Bit(kOp) | Bit(kName) | Bit(kBody), {{kName, kNoField}}};
    case OpKind::kPose:
      return {"a 'pose' op",
              Bit(kOp) | kPoseNames | Bit(kPosition) | Bit(kRotation) | Bit(kRepair) | Bit(kStamp) |
                  Bit(kCovariance),
              pose_required};
    case OpKind::kTwist:
      return {"a 'twist' op",
              Bit(kOp) | kTwistNames | Bit(kLinear) | Bit(kAngular) | Bit(kRepair) | Bit(kStamp) |
                  Bit(kCovariance) | Bit(kAcceleration),
              twist_required};
    case OpKind::kAcceleration:
      return {"an 'acceleration' op",
              Bit(kOp) | kTwistNames | Bit(kLinear) | Bit(kAngular) | Bit(kStamp), twist_required};
    case OpKind::kRemovePose:
      return {"a 'remove' op of kind 'pose'",
              kHeader | kShorthand,
              {{kOf, kNoField}, {kWrt, kNoField}}};
    case OpKind::kRemoveTwist:
      return {"a 'remove' op of kind 'twist'",
              kHeader | Bit(kPoint) | Bit(kRefBody),
              {{kPoint, kNoField}, {kRefBody, kNoField}}};
    case OpKind::kUrdf:
      return {"an 'urdf' op", Bit(kOp) | Bit(kFile) | Bit(kPrefix), {{kFile, kNoField}}};
    case OpKind::kJoint:
      return {"a 'joint' op",
              Bit(kOp) | Bit(kName) | Bit(kType) | Bit(kParent) | Bit(kChild) | Bit(kParentBody) |
                  Bit(kChildBody) | Bit(kPosition) | Bit(kRotation) | Bit(kAxis) | Bit(kLower) |
                  Bit(kUpper) | Bit(kMimic),
              {{kName, kNoField}, {kType, kNoField}, {kParent, kNoField}, {kChild, kNoField}}};
    case OpKind::kJoints:
      return {"a 'joints' op",
              Bit(kOp) | Bit(kPositions) | Bit(kVelocities) | Bit(kAccelerations) | Bit(kStamp),
              {}};
    case OpKind::kBag:
      return {"a 'bag' op",
              Bit(kOp) | Bit(kFile) | Bit(kTopics) | Bit(kStatic) | Bit(kBodies) |
                  Bit(kPoseTopics) | Bit(kStart) | Bit(kEnd),
              {{kFile, kNoField}}};
    case OpKind::kWrench:
      return {"a 'wrench' op",
              Bit(kOp) | kWrenchNames | Bit(kForce) | Bit(kMoment) | Bit(kStamp),
              {{kOn, kNoField}, {kBy, kNoField}, {kPoint, kNoField}, {kCoord, kNoField}}};
    case OpKind::kRemoveWrench:
      return {"a 'remove' op of kind 'wrench'",
              kHeader | Bit(kOn) | Bit(kBy),
              {{kOn, kNoField}, {kBy, kNoField}}};
    case OpKind::kQuery:
      break;
  }
  const std::vector<Requirement> wrench_required = {
      {kOn, kNoField}, {kPoint, kNoField}, {kCoord, kNoField}};
  switch (query) {
    case QueryKind::kPose:
      return {"a 'pose' query", kHeader | kPoseNames | kPoseTime | kCov6, pose_required};
    case QueryKind::kPosition:
      return {"a 'position' query",
              kHeader | kShorthand | Bit(kPoint) | Bit(kBody) | Bit(kRefPoint) | Bit(kRefBody) |
                  Bit(kCoord) | kPoseTime | kCov3,
              {{kPoint, kOf}, {kRefPoint, kWrt}, {kCoord, kWrt}}};
    case QueryKind::kOrientation:
      return {"an 'orientation' query",
              kHeader | kShorthand | Bit(kOrientation) | Bit(kBody) | Bit(kRefOrientation) |
                  Bit(kRefBody) | Bit(kCoord) | kPoseTime | kCov3,
              {{kOrientation, kOf}, {kRefOrientation, kWrt}, {kCoord, kWrt}}};
    case QueryKind::kTwist:
      return {"a 'twist' query", kHeader | kTwistNames | kTwistTime | kCov6, twist_required};
    case QueryKind::kLinearVelocity:
      return {"a 'linear_velocity' query", kHeader | kTwistNames | kTwistTime | kCov3,
              twist_required};
    case QueryKind::kJacobian:
      return {"a 'jacobian' query", kHeader | kTwistNames | kQueryTime, twist_required};
    case QueryKind::kWrench:
      return {"a 'wrench' query", kHeader | kWrenchNames | kQueryTime, wrench_required};
    case QueryKind::kForce:
      return {"a 'force' query", kHeader | kWrenchNames | kQueryTime, wrench_required};
    case QueryKind::kMoment:
      return {"a 'moment' query", kHeader | kWrenchNames | kQueryTime, wrench_required};
    case QueryKind::kAcceleration:
      return {"an 'acceleration' query", kHeader | kTwistNames | kQueryTime, twist_required};
    case QueryKind::kLinearAcceleration:
      return {"a 'linear_acceleration' query", kHeader | kTwistNames | kQueryTime, twist_required};
    case QueryKind::kAngularAcceleration:
      return {"an 'angular_acceleration' query",
              kHeader | Bit(kBody) | Bit(kRefBody) | Bit(kCoord) | kQueryTime,
              {{kBody, kNoField}, {kRefBody, kNoField}, {kCoord, kNoField}}};
    case QueryKind::kAngularVelocity:
      // No point: an angular velocity is the same at every point of the body.
      return {"an 'angular_velocity' query",
              kHeader | Bit(kBody) | Bit(kRefBody) | Bit(kCoord) | kTwistTime | kCov3,
              {{kBody, kNoField}, {kRefBody, kNoField}, {kCoord, kNoField}}};
  }
  return {};
}

std::string AllowedList(std::uint64_t allowed) {
  std::string s;
  for (int f = 0; f < kNumFields; ++f) {
    if ((allowed & Bit(static_cast<Field>(f))) == 0) continue;
    if (!s.empty()) s += ", ";
    s += kFieldNames[f];
  }
  return s;
}

// Scalar text for a message: quoted, control bytes escaped (the message goes to a terminal),
// long texts cut (at a UTF-8 character boundary).
// Scalar text for a message: quoted, control bytes escaped, long texts cut (with their length).
std::string Quoted(std::string_view text) { return QuoteForMessage(text); }

// ====================================================================== interpreter

class Interpreter {
 public:
  explicit Interpreter(const YamlTree& tree) : tree_(tree) {}

  bool ReadDocument(Script* script);
  const ScriptError& error() const { return error_; }

 private:
  NodeView At(NodeId i) const { return tree_.At(i); }

  bool Fail(SourceLocation location, std::string message) {
    error_ = ScriptError{location, std::move(message)};
    return false;
  }
  bool Fail(std::uint32_t node, std::string message) {
    return Fail(At(node).location, std::move(message));
  }

  std::string Describe(std::uint32_t i) const {
    const NodeView n = At(i);
    switch (n.kind) {
      case NodeKind::kNull:
        return "nothing (null)";
      case NodeKind::kScalar:
        return n.style == ScalarStyle::kString ? "the string " + Quoted(n.text) : Quoted(n.text);
      case NodeKind::kSequence:
        return "a list of " + std::to_string(n.children.size());
      case NodeKind::kMap:
        return "a map";
    }
    return "?";
  }

  // A map's (key, value) pairs in document order; keys must be distinct scalars.
  bool ReadMap(std::uint32_t map, std::string_view what,
               std::vector<std::pair<std::uint32_t, std::uint32_t>>* pairs);
  bool ReadOp(std::uint32_t node, ScriptOp* op);
  bool ReadText(std::uint32_t node, std::string_view field, std::string* out);
  bool ReadNumber(std::uint32_t node, std::string_view what, double* out);
  bool ReadVector3(std::uint32_t node, std::string_view field, std::array<double, 3>* out);
  bool ReadRotation(std::uint32_t node, RotationValue* out);
  bool ReadAcceleration(std::uint32_t node, const std::array<std::uint32_t, kNumFields>& value,
                        ScriptOp* op);
  bool ReadJointFields(std::uint32_t node, const std::array<std::uint32_t, kNumFields>& value,
                       ScriptOp* op);
  bool ReadJointValues(std::uint32_t node, std::string_view field,
                       std::vector<std::pair<std::string, double>>* out);
  bool ReadNames(std::uint32_t node, std::string_view field, std::vector<std::string>* out);
  bool ReadBagFields(const std::array<std::uint32_t, kNumFields>& value, ScriptOp* op);
  bool ReadTimeSettings(std::uint32_t node, TimeSettings* out);
  bool ReadOpTime(std::uint32_t node, const std::array<std::uint32_t, kNumFields>& value,
                  ScriptOp* op);
  bool ReadBool(std::uint32_t node, std::string_view field, bool* out);
  bool ReadCovariance(const std::array<std::uint32_t, kNumFields>& value, ScriptOp* op);
  bool ReadCovarianceValue(std::uint32_t node, ScriptOp* op);
  bool ReadMatrix6(std::uint32_t node, std::string_view what, ScriptOp* op);
  bool ReadQueryCovariance(const std::array<std::uint32_t, kNumFields>& value, ScriptOp* op);

  const YamlTree& tree_;
  ScriptError error_;
};

bool Interpreter::ReadMap(std::uint32_t map, std::string_view what,
                          std::vector<std::pair<std::uint32_t, std::uint32_t>>* pairs) {
  const NodeView n = At(map);
  pairs->clear();
  std::set<std::string_view> seen;  // a set, not a scan: a hostile map may have 10^6 keys
  for (std::size_t k = 0; k + 1 < n.children.size(); k += 2) {
    const std::uint32_t key = n.children[k];
    if (At(key).kind != NodeKind::kScalar) {
      return Fail(
          key, "the keys of " + std::string(what) + " must be field names, got " + Describe(key));
    }
    if (!seen.insert(At(key).text).second) {
      return Fail(key, "field " + Quoted(At(key).text) + " appears twice in " + std::string(what));
    }
    pairs->emplace_back(key, n.children[k + 1]);
  }
  return true;
}

bool Interpreter::ReadDocument(Script* script) {
  const NodeId root = tree_.root();
  if (At(root).kind != NodeKind::kMap) {
    return Fail(root,
                "a script is a map with 'ops' (and optionally 'representation' and 'time'), got " +
                    Describe(root));
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  if (!ReadMap(root, "the script", &pairs)) return false;
  std::uint32_t ops = kNoNode;
  for (const auto& [key, value] : pairs) {
    const std::string_view name = At(key).text;
    if (name == "representation") {
      const NodeView v = At(value);
      if (v.kind == NodeKind::kScalar && v.text == "quaternion") {
        script->representation = Representation::kQuaternion;
      } else if (v.kind == NodeKind::kScalar && v.text == "homogeneous") {
        script->representation = Representation::kHomogeneous;
      } else {
        return Fail(value, "unknown representation " + Describe(value) +
                               " (expected quaternion or homogeneous)");
      }
    } else if (name == "ops") {
      ops = value;
    } else if (name == "time") {
      if (!ReadTimeSettings(value, &script->time)) return false;
    } else {
      return Fail(key, "unknown top-level field " + Quoted(name) +
                           " (expected 'representation', 'time' and 'ops')");
    }
  }
  if (ops == kNoNode) return Fail(root, "the script has no 'ops' list");
  if (At(ops).kind != NodeKind::kSequence) {
    return Fail(ops, "'ops' must be a list of ops, got " + Describe(ops));
  }
  const std::span<const std::uint32_t> items = At(ops).children;
  script->ops.reserve(items.size());
  for (const std::uint32_t item : items) {
    ScriptOp op;
    if (!ReadOp(item, &op)) return false;
    script->ops.push_back(std::move(op));
  }
  return true;
}

bool Interpreter::ReadOp(std::uint32_t node, ScriptOp* op) {
  op->location = At(node).location;
  if (At(node).kind != NodeKind::kMap) {
    return Fail(node, "an op must be a map with an 'op' field, got " + Describe(node));
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  if (!ReadMap(node, "an op", &pairs)) return false;
  // Known fields first, so that the op's kind is known before judging the other fields.
  std::array<std::uint32_t, kNumFields> value;
  value.fill(kNoNode);
  for (const auto& [key, v] : pairs) {
    for (int f = 0; f < kNumFields; ++f) {
      if (At(key).text == kFieldNames[f]) value[f] = v;
    }
  }
  if (value[kOp] == kNoNode) return Fail(node, "an op needs an 'op' field");
  const NodeView op_name = At(value[kOp]);
  static constexpr std::string_view kOps =
      "body, frame, pose, twist, acceleration, wrench, remove, query, urdf, joint, joints, bag";
  if (op_name.kind != NodeKind::kScalar) {
    return Fail(value[kOp],
                "'op' must be one of " + std::string(kOps) + ", got " + Describe(value[kOp]));
  }
  const bool kind_is_text = value[kKind] != kNoNode && At(value[kKind]).kind == NodeKind::kScalar;
  const std::string_view kind_text = kind_is_text ? At(value[kKind]).text : std::string_view();
  if (op_name.text == "body") {
    op->kind = OpKind::kBody;
  } else if (op_name.text == "frame") {
    op->kind = OpKind::kFrame;
  } else if (op_name.text == "pose") {
    op->kind = OpKind::kPose;
  } else if (op_name.text == "twist") {
    op->kind = OpKind::kTwist;
  } else if (op_name.text == "urdf") {
    op->kind = OpKind::kUrdf;
  } else if (op_name.text == "joint") {
    op->kind = OpKind::kJoint;
  } else if (op_name.text == "joints") {
    op->kind = OpKind::kJoints;
  } else if (op_name.text == "bag") {
    op->kind = OpKind::kBag;
  } else if (op_name.text == "wrench") {
    op->kind = OpKind::kWrench;
  } else if (op_name.text == "acceleration") {
    op->kind = OpKind::kAcceleration;
  } else if (op_name.text == "remove") {
    if (value[kKind] == kNoNode) {
      return Fail(node, "a 'remove' op needs 'kind' (pose, twist or wrench)");
    }
    if (kind_is_text && kind_text == "pose") {
      op->kind = OpKind::kRemovePose;
    } else if (kind_is_text && kind_text == "twist") {
      op->kind = OpKind::kRemoveTwist;
    } else if (kind_is_text && kind_text == "wrench") {
      op->kind = OpKind::kRemoveWrench;
    } else {
      return Fail(value[kKind], "the 'kind' of a 'remove' op must be pose, twist or wrench, got " +
                                    Describe(value[kKind]));
    }
  } else if (op_name.text == "query") {
    op->kind = OpKind::kQuery;
    static constexpr std::string_view kQueries =
        "pose, position, orientation, twist, linear_velocity, angular_velocity, jacobian, wrench, "
        "force, moment, acceleration, linear_acceleration, angular_acceleration";
    if (value[kKind] == kNoNode) {
      return Fail(node, "a 'query' op needs 'kind' (one of " + std::string(kQueries) + ")");
    }
    static constexpr std::pair<std::string_view, QueryKind> kKinds[] = {
        {"pose", QueryKind::kPose},
        {"position", QueryKind::kPosition},
        {"orientation", QueryKind::kOrientation},
        {"twist", QueryKind::kTwist},
        {"linear_velocity", QueryKind::kLinearVelocity},
        {"angular_velocity", QueryKind::kAngularVelocity},
        {"jacobian", QueryKind::kJacobian},
        {"wrench", QueryKind::kWrench},
        {"force", QueryKind::kForce},
        {"moment", QueryKind::kMoment},
        {"acceleration", QueryKind::kAcceleration},
        {"linear_acceleration", QueryKind::kLinearAcceleration},
        {"angular_acceleration", QueryKind::kAngularAcceleration}};
    bool found = false;
    for (const auto& [text, kind] : kKinds) {
      if (kind_is_text && kind_text == text) {
        op->query_kind = kind;
        found = true;
      }
    }
    if (!found) {
      return Fail(value[kKind], "the 'kind' of a query must be one of " + std::string(kQueries) +
                                    ", got " + Describe(value[kKind]));
    }
  } else {
    return Fail(value[kOp], "unknown op " + Describe(value[kOp]) + " (expected one of " +
                                std::string(kOps) + ")");
  }

  const Shape shape = ShapeOf(op->kind, op->query_kind);
  for (const auto& [key, v] : pairs) {
    bool allowed = false;
    bool known = false;
    for (int f = 0; f < kNumFields; ++f) {
      if (At(key).text != kFieldNames[f]) continue;
      known = true;
      allowed = (shape.allowed & Bit(static_cast<Field>(f))) != 0;
    }
    if (!allowed) {
      return Fail(key, std::string(known ? "field " : "unknown field ") + Quoted(At(key).text) +
                           " is not part of " + std::string(shape.label) +
                           " (its fields: " + AllowedList(shape.allowed) + ")");
    }
  }
  for (const Requirement& r : shape.required) {
    if (value[r.field] != kNoNode || (r.shorthand != kNoField && value[r.shorthand] != kNoNode)) {
      continue;
    }
    std::string message =
        std::string(shape.label) + " needs '" + std::string(kFieldNames[r.field]) + "'";
    if (r.shorthand != kNoField) {
      message += " (or the shorthand '" + std::string(kFieldNames[r.shorthand]) + "')";
    }
    return Fail(node, message);
  }

  // Names: shorthand first, explicit fields override it.
  SemanticNames& names = op->names;
  std::string text;
  if (value[kOf] != kNoNode) {
    if (!ReadText(value[kOf], "of", &text)) return false;
    names.point = names.orientation = text;
  }
  if (value[kWrt] != kNoNode) {
    if (!ReadText(value[kWrt], "wrt", &text)) return false;
    names.ref_point = names.ref_orientation = names.coord = text;
  }
  const std::pair<Field, std::string*> explicit_names[] = {
      {kName, &op->name},
      {kPoint, &names.point},
      {kOrientation, &names.orientation},
      {kBody, &names.body},
      {kRefPoint, &names.ref_point},
      {kRefOrientation, &names.ref_orientation},
      {kRefBody, &names.ref_body},
      {kCoord, &names.coord},
      {kOn, &names.body},  // a wrench's fields (no shape takes both on and body)
      {kBy, &names.ref_body}};
  for (const auto& [field, out] : explicit_names) {
    if (value[field] != kNoNode && !ReadText(value[field], kFieldNames[field], out)) return false;
  }
  const std::pair<Field, std::array<double, 3>*> vectors[] = {{kPosition, &op->position},
                                                              {kLinear, &op->linear},
                                                              {kAngular, &op->angular},
                                                              {kForce, &op->force},
                                                              {kMoment, &op->moment}};
  for (const auto& [field, out] : vectors) {
    if (value[field] != kNoNode && !ReadVector3(value[field], kFieldNames[field], out)) {
      return false;
    }
  }
  if (value[kRotation] != kNoNode && !ReadRotation(value[kRotation], &op->rotation)) return false;
  if (op->kind == OpKind::kAcceleration) {  // its own linear / angular are the acceleration
    op->has_acceleration = true;
    op->acceleration_linear = op->linear;
    op->acceleration_angular = op->angular;
  }
  if (value[kAcceleration] != kNoNode && !ReadAcceleration(value[kAcceleration], value, op)) {
    return false;
  }
  if (op->kind == OpKind::kUrdf) {
    if (!ReadText(value[kFile], "file", &op->file)) return false;
    if (value[kPrefix] != kNoNode && !ReadText(value[kPrefix], "prefix", &op->prefix)) return false;
  }
  if (op->kind == OpKind::kJoint && !ReadJointFields(node, value, op)) return false;
  if (op->kind == OpKind::kBag && !ReadBagFields(value, op)) return false;
  if (op->kind == OpKind::kJoints) {
    if (value[kPositions] == kNoNode && value[kVelocities] == kNoNode &&
        value[kAccelerations] == kNoNode) {
      return Fail(node,
                  "a 'joints' op needs 'positions', 'velocities' or 'accelerations' (or several)");
    }
    if ((op->has_positions = value[kPositions] != kNoNode) &&
        !ReadJointValues(value[kPositions], "positions", &op->positions)) {
      return false;
    }
    if ((op->has_velocities = value[kVelocities] != kNoNode) &&
        !ReadJointValues(value[kVelocities], "velocities", &op->velocities)) {
      return false;
    }
    if ((op->has_accelerations = value[kAccelerations] != kNoNode) &&
        !ReadJointValues(value[kAccelerations], "accelerations", &op->accelerations)) {
      return false;
    }
  }
  if (!ReadOpTime(node, value, op)) return false;
  if (value[kRepair] != kNoNode && !ReadBool(value[kRepair], "repair", &op->repair)) return false;
  if (op->kind == OpKind::kQuery) return ReadQueryCovariance(value, op);
  return ReadCovariance(value, op);
}

bool Interpreter::ReadBool(std::uint32_t node, std::string_view field, bool* out) {
  // YAML 1.2 core schema booleans, plain style only.
  const NodeView n = At(node);
  const bool plain = n.kind == NodeKind::kScalar && n.style == ScalarStyle::kPlain;
  if (plain && (n.text == "true" || n.text == "True" || n.text == "TRUE")) {
    *out = true;
  } else if (plain && (n.text == "false" || n.text == "False" || n.text == "FALSE")) {
    *out = false;
  } else {
    return Fail(node, "'" + std::string(field) + "' must be true or false, got " + Describe(node));
  }
  return true;
}

// A query's `covariance: true|false` and `covariance_order` (only with covariance: true).
bool Interpreter::ReadQueryCovariance(const std::array<std::uint32_t, kNumFields>& value,
                                      ScriptOp* op) {
  if (value[kCovariance] != kNoNode &&
      !ReadBool(value[kCovariance], "covariance", &op->query_covariance)) {
    return false;
  }
  const std::uint32_t order = value[kCovarianceOrder];
  if (order == kNoNode) return true;
  if (!op->query_covariance) {
    return Fail(order, "'covariance_order' needs 'covariance: true' on the query");
  }
  const NodeView n = At(order);
  if (n.kind == NodeKind::kScalar && (n.text == "linear_angular" || n.text == "angular_linear")) {
    op->covariance_angular_first = n.text == "angular_linear";
    return true;
  }
  return Fail(
      order, "'covariance_order' must be linear_angular or angular_linear, got " + Describe(order));
}

// A pose or twist op's `covariance` (docs/uncertainty.md): a 6x6 list of lists, or a map
// {matrix, order, convention}; `convention: body` only for a pose in edge form (of/wrt: point =
// orientation, ref_point = ref_orientation = coord), the only form it has a meaning in.
bool Interpreter::ReadCovariance(const std::array<std::uint32_t, kNumFields>& value, ScriptOp* op) {
  if (value[kCovariance] == kNoNode) return true;
  if (!ReadCovarianceValue(value[kCovariance], op)) return false;
  if (value[kRepair] != kNoNode) {
    return Fail(value[kRepair], "field " + Quoted(kFieldNames[kRepair]) +
                                    " does not go with 'covariance' in this version (a "
                                    "covariance is given without repair)");
  }
  const SemanticNames& n = op->names;
  const bool edge_form =
      n.point == n.orientation && n.ref_point == n.ref_orientation && n.coord == n.ref_orientation;
  if (op->covariance_body && !edge_form) {
    return Fail(value[kCovariance],
                "'convention: body' applies to a pose given in edge form only (point = "
                "orientation, ref_point = ref_orientation = coord, as 'of' and 'wrt' give)");
  }
  return true;
}

bool Interpreter::ReadCovarianceValue(std::uint32_t node, ScriptOp* op) {
  static constexpr std::string_view kForms =
      "a 6x6 list of lists of numbers, or a map {matrix: 6x6, order: linear_angular | "
      "angular_linear, convention: coordinates | body}";
  op->has_covariance = true;
  const NodeView v = At(node);
  if (v.kind == NodeKind::kSequence) return ReadMatrix6(node, "'covariance'", op);
  if (v.kind != NodeKind::kMap) {
    return Fail(node, "'covariance' must be " + std::string(kForms) + ", got " + Describe(node));
  }
  const bool pose = op->kind == OpKind::kPose;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  if (!ReadMap(node, "'covariance'", &pairs)) return false;
  bool has_matrix = false;
  for (const auto& [key, item] : pairs) {
    const std::string_view k = At(key).text;
    const NodeView iv = At(item);
    const bool text = iv.kind == NodeKind::kScalar;
    if (k == "matrix") {
      if (!ReadMatrix6(item, "the 'matrix' of 'covariance'", op)) return false;
      has_matrix = true;
    } else if (k == "order") {
      if (!text || (iv.text != "linear_angular" && iv.text != "angular_linear")) {
        return Fail(item,
                    "the 'order' of 'covariance' must be linear_angular or angular_linear, "
                    "got " +
                        Describe(item));
      }
      op->covariance_angular_first = iv.text == "angular_linear";
    } else if (k == "convention" && pose) {
      if (!text || (iv.text != "coordinates" && iv.text != "body")) {
        return Fail(item, "the 'convention' of 'covariance' must be coordinates or body, got " +
                              Describe(item));
      }
      op->covariance_body = iv.text == "body";
    } else {
      return Fail(key, "unknown field " + Quoted(k) + " in 'covariance' of a '" +
                           std::string(pose ? "pose" : "twist") + "' op (its fields: matrix, " +
                           (pose ? "order, convention)" : "order; a twist has no convention)"));
    }
  }
  if (!has_matrix) return Fail(node, "'covariance' needs 'matrix' (6 rows of 6 numbers)");
  return true;
}

bool Interpreter::ReadMatrix6(std::uint32_t node, std::string_view what, ScriptOp* op) {
  const NodeView v = At(node);
  if (v.kind != NodeKind::kSequence || v.children.size() != 6) {
    return Fail(
        node, std::string(what) + " must be a list of 6 rows of 6 numbers, got " + Describe(node));
  }
  for (std::size_t r = 0; r < 6; ++r) {
    const std::uint32_t row = v.children[r];
    if (At(row).kind != NodeKind::kSequence || At(row).children.size() != 6) {
      return Fail(row, "row " + std::to_string(r + 1) + " of " + std::string(what) +
                           " must be a list of 6 numbers, got " + Describe(row));
    }
    for (std::size_t c = 0; c < 6; ++c) {
      const std::string element = "element " + std::to_string(c + 1) + " of row " +
                                  std::to_string(r + 1) + " of " + std::string(what);
      if (!ReadNumber(At(row).children[c], element, &op->covariance[r][c])) return false;
    }
  }
  return true;
}

// A twist op's `acceleration: {linear: [..], angular: [..]}` (docs/dynamics.md §7), in the op's
// point and frame; a missing part is zero. Given with a twist value, stamped or not, without
// repair or covariance.
bool Interpreter::ReadAcceleration(std::uint32_t node,
                                   const std::array<std::uint32_t, kNumFields>& value,
                                   ScriptOp* op) {
  for (const Field f : {kRepair, kCovariance}) {
    if (value[f] == kNoNode) continue;
    return Fail(value[f], "field " + Quoted(kFieldNames[f]) +
                              " does not go with 'acceleration' in this version (an acceleration "
                              "is given with a twist value, without repair or covariance)");
  }
  if (At(node).kind != NodeKind::kMap) {
    return Fail(node, "'acceleration' must be a map {linear: [x, y, z], angular: [x, y, z]}, got " +
                          Describe(node));
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  if (!ReadMap(node, "'acceleration'", &pairs)) return false;
  op->has_acceleration = true;
  for (const auto& [key, item] : pairs) {
    const std::string_view k = At(key).text;
    if (k == "linear") {
      if (!ReadVector3(item, "acceleration.linear", &op->acceleration_linear)) return false;
    } else if (k == "angular") {
      if (!ReadVector3(item, "acceleration.angular", &op->acceleration_angular)) return false;
    } else {
      return Fail(
          key, "unknown field " + Quoted(k) + " in 'acceleration' (its fields: linear, angular)");
    }
  }
  return true;
}

bool Interpreter::ReadJointFields(std::uint32_t node,
                                  const std::array<std::uint32_t, kNumFields>& value,
                                  ScriptOp* op) {
  static constexpr std::pair<std::string_view, JointKind> kTypes[] = {
      {"revolute", JointKind::kRevolute},
      {"continuous", JointKind::kContinuous},
      {"prismatic", JointKind::kPrismatic},
      {"fixed", JointKind::kFixed}};
  const NodeView type = At(value[kType]);
  bool found = false;
  for (const auto& [text, kind] : kTypes) {
    if (type.kind == NodeKind::kScalar && type.text == text) {
      op->joint_type = kind;
      found = true;
    }
  }
  if (!found) {
    return Fail(
        value[kType],
        "the 'type' of a joint must be one of revolute, continuous, prismatic, fixed, got " +
            Describe(value[kType]));
  }
  const std::pair<Field, std::string*> names[] = {{kParent, &op->names.ref_orientation},
                                                  {kParentBody, &op->names.ref_body},
                                                  {kChild, &op->names.orientation},
                                                  {kChildBody, &op->names.body}};
  for (const auto& [field, out] : names) {
    if (value[field] != kNoNode && !ReadText(value[field], kFieldNames[field], out)) return false;
  }
  if (value[kAxis] != kNoNode && !ReadVector3(value[kAxis], "axis", &op->axis)) return false;
  const bool limited =
      op->joint_type == JointKind::kRevolute || op->joint_type == JointKind::kPrismatic;
  for (const auto& [field, out] : {std::pair{kLower, &op->lower}, std::pair{kUpper, &op->upper}}) {
    if (value[field] == kNoNode) {
      if (limited) {
        return Fail(node, "a '" + std::string(type.text) + "' joint needs '" +
                              std::string(kFieldNames[field]) + "'");
      }
      continue;
    }
    if (!ReadNumber(value[field], "'" + std::string(kFieldNames[field]) + "'", out)) return false;
  }
  if (value[kMimic] != kNoNode) {
    const std::uint32_t m = value[kMimic];
    if (At(m).kind != NodeKind::kMap) {
      return Fail(m, "'mimic' must be a map {joint, multiplier, offset}, got " + Describe(m));
    }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    if (!ReadMap(m, "'mimic'", &pairs)) return false;
    bool has_joint = false;
    for (const auto& [key, v] : pairs) {
      const std::string_view k = At(key).text;
      if (k == "joint") {
        if (!ReadText(v, "joint", &op->mimic_joint)) return false;
        has_joint = true;
      } else if (k == "multiplier") {
        if (!ReadNumber(v, "'multiplier'", &op->mimic_multiplier)) return false;
      } else if (k == "offset") {
        if (!ReadNumber(v, "'offset'", &op->mimic_offset)) return false;
      } else {
        return Fail(key, "unknown field " + Quoted(k) +
                             " in 'mimic' (its fields: joint, multiplier, offset)");
      }
    }
    if (!has_joint) return Fail(m, "'mimic' needs 'joint'");
    op->has_mimic = true;
  }
  return true;
}

bool Interpreter::ReadTimeSettings(std::uint32_t node, TimeSettings* out) {
  static constexpr std::string_view kKeys = "window, interpolation, duplicate_stamp";
  if (At(node).kind != NodeKind::kMap) {
    return Fail(
        node, "'time' must be a map with any of " + std::string(kKeys) + ", got " + Describe(node));
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  if (!ReadMap(node, "'time'", &pairs)) return false;
  out->given = true;
  for (const auto& [key, v] : pairs) {
    const std::string_view k = At(key).text;
    const NodeView n = At(v);
    const bool scalar = n.kind == NodeKind::kScalar;
    if (k == "window") {
      // The graph refuses a window that is not a finite positive time; a script states it, so
      // a bad one is a malformed script (nothing is applied).
      double seconds = 0;
      if (!ReadNumber(v, "'window'", &seconds)) return false;
      const auto ns = core::NanosecondsFromSeconds(seconds);
      if (!ns || *ns <= 0) {
        return Fail(v,
                    "'window' must be a finite positive time in seconds (at least 1 ns, at most "
                    "9.2e9 s), got " +
                        Describe(v));
      }
      out->window_ns = *ns;
    } else if (k == "interpolation") {
      if (scalar && n.text == "screw") {
        out->linear = false;
      } else if (scalar && n.text == "linear") {
        out->linear = true;
      } else {
        return Fail(v, "'interpolation' must be screw or linear, got " + Describe(v));
      }
    } else if (k == "duplicate_stamp") {
      if (scalar && n.text == "replace") {
        out->reject_duplicates = false;
      } else if (scalar && n.text == "reject") {
        out->reject_duplicates = true;
      } else {
        return Fail(v, "'duplicate_stamp' must be replace or reject, got " + Describe(v));
      }
    } else {
      return Fail(key, "unknown field " + Quoted(k) +
                           " in 'time' (its fields: " + std::string(kKeys) + ")");
    }
  }
  return true;
}

bool Interpreter::ReadOpTime(std::uint32_t node, const std::array<std::uint32_t, kNumFields>& value,
                             ScriptOp* op) {
  // The shape admitted each field only on the ops that take it; here their values.
  const std::pair<Field, std::optional<double>*> numbers[] = {
      {kStamp, &op->stamp},
      {kMaxExtrapolation, &op->max_extrapolation},
      {kNotBefore, &op->not_before},
      {kRefAt, &op->ref_at}};
  for (const auto& [field, out] : numbers) {
    if (value[field] == kNoNode) continue;
    double seconds = 0;
    if (!ReadNumber(value[field], "'" + std::string(kFieldNames[field]) + "' (seconds)", &seconds))
      return false;
    *out = seconds;
  }
  if (value[kAt] != kNoNode) {
    const NodeView n = At(value[kAt]);
    if (n.kind == NodeKind::kScalar && n.text == "latest_common") {
      op->at = AtKind::kLatestCommon;
    } else {
      const bool may_be_number =
          n.style == ScalarStyle::kPlain || n.style == ScalarStyle::kNumberTag;
      if (n.kind != NodeKind::kScalar || !may_be_number ||
          !ParseCoreNumber(n.text, &op->at_seconds)) {
        return Fail(value[kAt],
                    "'at' must be a time in seconds or latest_common, got " + Describe(value[kAt]));
      }
      op->at = AtKind::kTime;
    }
  }
  if ((value[kRefAt] == kNoNode) != (value[kFixed] == kNoNode)) {
    return Fail(
        value[kRefAt] != kNoNode ? value[kRefAt] : value[kFixed],
        "time travel needs both 'ref_at' (the reference side's time) and 'fixed' (the frame fixed "
        "between the two times)");
  }
  if (value[kFixed] != kNoNode) {
    if (!ReadText(value[kFixed], "fixed", &op->fixed)) return false;
    if (op->at != AtKind::kTime) {
      return Fail(value[kAt] != kNoNode ? value[kAt] : node,
                  "time travel ('ref_at', 'fixed') needs 'at' as a time in seconds (the point "
                  "side's time)");
    }
  }
  if (value[kSource] != kNoNode) {
    const NodeView n = At(value[kSource]);
    if (n.kind == NodeKind::kScalar && n.text == "twists") {
      op->source_poses = false;
    } else if (n.kind == NodeKind::kScalar && n.text == "poses") {
      op->source_poses = true;
    } else {
      return Fail(value[kSource],
                  "'source' must be twists or poses, got " + Describe(value[kSource]));
    }
  }
  if (value[kStamp] != kNoNode && value[kRepair] != kNoNode) {
    return Fail(value[kRepair],
                "'repair' does not take a stamped value: give either 'repair' or 'stamp'");
  }
  return true;
}

bool Interpreter::ReadJointValues(std::uint32_t node, std::string_view field,
                                  std::vector<std::pair<std::string, double>>* out) {
  if (At(node).kind != NodeKind::kMap) {
    return Fail(node, "'" + std::string(field) + "' must be a map of joint names to numbers, got " +
                          Describe(node));
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  if (!ReadMap(node, "'" + std::string(field) + "'", &pairs)) return false;
  out->reserve(pairs.size());
  for (const auto& [key, v] : pairs) {
    double x = 0;
    if (!ReadNumber(
            v, "the value of joint " + Quoted(At(key).text) + " in '" + std::string(field) + "'",
            &x)) {
      return false;
    }
    out->emplace_back(std::string(At(key).text), x);
  }
  return true;
}

bool Interpreter::ReadNames(std::uint32_t node, std::string_view field,
                            std::vector<std::string>* out) {
  const NodeView n = At(node);
  if (n.kind != NodeKind::kSequence) {
    return Fail(node,
                "'" + std::string(field) + "' must be a list of names, got " + Describe(node));
  }
  out->resize(n.children.size());
  for (std::size_t i = 0; i < n.children.size(); ++i) {
    if (!ReadText(n.children[i], field, &(*out)[i])) return false;
  }
  return true;
}

// The `bag` op (docs/ros.md): file, topics, static, bodies {BODY: [frames]}, pose_topics
// {TOPIC: frame}, start, end.
bool Interpreter::ReadBagFields(const std::array<std::uint32_t, kNumFields>& value, ScriptOp* op) {
  if (!ReadText(value[kFile], "file", &op->file)) return false;
  if ((op->has_topics = value[kTopics] != kNoNode) &&
      !ReadNames(value[kTopics], "topics", &op->topics)) {
    return false;
  }
  if (value[kStatic] != kNoNode) {
    if (!ReadText(value[kStatic], "static", &op->static_mode)) return false;
    if (op->static_mode != "same_body" && op->static_mode != "own_body") {
      return Fail(value[kStatic],
                  "'static' must be same_body or own_body, got " + Describe(value[kStatic]));
    }
  }
  if (value[kBodies] != kNoNode) {
    if (At(value[kBodies]).kind != NodeKind::kMap) {
      return Fail(value[kBodies], "'bodies' must be a map of body names to lists of frames, got " +
                                      Describe(value[kBodies]));
    }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    if (!ReadMap(value[kBodies], "'bodies'", &pairs)) return false;
    for (const auto& [key, frames] : pairs) {
      op->bodies.emplace_back(std::string(At(key).text), std::vector<std::string>());
      if (!ReadNames(frames, "bodies", &op->bodies.back().second)) return false;
    }
  }
  if (value[kPoseTopics] != kNoNode) {
    if (At(value[kPoseTopics]).kind != NodeKind::kMap) {
      return Fail(value[kPoseTopics], "'pose_topics' must be a map of topics to frames, got " +
                                          Describe(value[kPoseTopics]));
    }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    if (!ReadMap(value[kPoseTopics], "'pose_topics'", &pairs)) return false;
    for (const auto& [key, frame] : pairs) {
      op->pose_topics.emplace_back(std::string(At(key).text), std::string());
      if (!ReadText(frame, "pose_topics", &op->pose_topics.back().second)) return false;
    }
  }
  const std::pair<Field, std::optional<double>*> times[] = {{kStart, &op->start}, {kEnd, &op->end}};
  for (const auto& [field, out] : times) {
    if (value[field] == kNoNode) continue;
    double t = 0;
    if (!ReadNumber(value[field], "'" + std::string(kFieldNames[field]) + "'", &t)) return false;
    *out = t;
  }
  return true;
}

bool Interpreter::ReadText(std::uint32_t node, std::string_view field, std::string* out) {
  // Any scalar is accepted as a name (`1` names a frame "1"); whether the name is valid is the
  // scene graph's call (invalid_name), so that scripts and the C++ API agree.
  if (At(node).kind != NodeKind::kScalar) {
    return Fail(node, "'" + std::string(field) + "' must be a name, got " + Describe(node));
  }
  *out = At(node).text;
  return true;
}

bool Interpreter::ReadNumber(std::uint32_t node, std::string_view what, double* out) {
  const NodeView n = At(node);
  const bool may_be_number = n.style == ScalarStyle::kPlain || n.style == ScalarStyle::kNumberTag;
  if (n.kind != NodeKind::kScalar || !may_be_number || !ParseCoreNumber(n.text, out)) {
    return Fail(node, std::string(what) + " must be a number, got " + Describe(node));
  }
  return true;
}

bool Interpreter::ReadVector3(std::uint32_t node, std::string_view field,
                              std::array<double, 3>* out) {
  const NodeView n = At(node);
  if (n.kind != NodeKind::kSequence || n.children.size() != 3) {
    return Fail(node,
                "'" + std::string(field) + "' must be a list of 3 numbers, got " + Describe(node));
  }
  for (std::size_t i = 0; i < 3; ++i) {
    const std::string what =
        "element " + std::to_string(i + 1) + " of '" + std::string(field) + "'";
    if (!ReadNumber(n.children[i], what, &(*out)[i])) return false;
  }
  return true;
}

bool Interpreter::ReadRotation(std::uint32_t node, RotationValue* out) {
  static constexpr std::string_view kForms =
      "exactly one of quaternion: [w, x, y, z], rpy: [roll, pitch, yaw], matrix: [[...], [...], "
      "[...]]";
  if (At(node).kind != NodeKind::kMap) {
    return Fail(node,
                "'rotation' must be a map with " + std::string(kForms) + ", got " + Describe(node));
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  if (!ReadMap(node, "'rotation'", &pairs)) return false;
  if (pairs.empty()) return Fail(node, "'rotation' needs " + std::string(kForms));
  if (pairs.size() > 1) {
    return Fail(pairs[1].first, "'rotation' has both " + Quoted(At(pairs[0].first).text) + " and " +
                                    Quoted(At(pairs[1].first).text) + "; it needs " +
                                    std::string(kForms));
  }
  const auto [key, value] = pairs[0];
  const std::string_view form = At(key).text;
  const NodeView v = At(value);
  if (form == "quaternion") {
    out->form = RotationForm::kQuaternion;
    if (v.kind != NodeKind::kSequence || v.children.size() != 4) {
      return Fail(value,
                  "'quaternion' must be a list of 4 numbers [w, x, y, z], got " + Describe(value));
    }
    for (std::size_t i = 0; i < 4; ++i) {
      const std::string what = "element " + std::to_string(i + 1) + " of 'quaternion'";
      if (!ReadNumber(v.children[i], what, &out->quaternion[i])) return false;
    }
    return true;
  }
  if (form == "rpy") {
    out->form = RotationForm::kRpy;
    return ReadVector3(value, "rpy", &out->rpy);
  }
  if (form == "matrix") {
    out->form = RotationForm::kMatrix;
    if (v.kind != NodeKind::kSequence || v.children.size() != 3) {
      return Fail(value, "'matrix' must be a list of 3 rows of 3 numbers, got " + Describe(value));
    }
    for (std::size_t r = 0; r < 3; ++r) {
      const std::uint32_t row = v.children[r];
      if (At(row).kind != NodeKind::kSequence || At(row).children.size() != 3) {
        return Fail(row, "row " + std::to_string(r + 1) + " of 'matrix' must be a list of 3 " +
                             "numbers, got " + Describe(row));
      }
      for (std::size_t c = 0; c < 3; ++c) {
        const std::string what = "element " + std::to_string(c + 1) + " of row " +
                                 std::to_string(r + 1) + " of 'matrix'";
        if (!ReadNumber(At(row).children[c], what, &out->matrix[r][c])) return false;
      }
    }
    return true;
  }
  return Fail(
      key, "unknown rotation form " + Quoted(form) + "; 'rotation' needs " + std::string(kForms));
}

}  // namespace

base::Expected<Script, ScriptError> ReadScript(std::string_view text) {
  if (text.size() > kMaxScriptBytes) {
    return Unexpected{ScriptError{
        {1, 1}, "the script is larger than " + std::to_string(kMaxScriptBytes >> 20) + " MiB"}};
  }
  auto parsed = ParseYaml(text, kScriptLimits);
  if (!parsed) return Unexpected{ScriptError{parsed.error().location, parsed.error().message}};
  const YamlTree& tree = *parsed;
  if (tree.root() == kNoNode) {
    return Unexpected{ScriptError{{1, 1}, "the script is empty; expected a map with 'ops'"}};
  }
  Script script;
  Interpreter interpreter(tree);
  if (!interpreter.ReadDocument(&script)) return Unexpected{interpreter.error()};
  return script;
}

std::string FormatScriptError(std::string_view file_name, const ScriptError& error) {
  return std::string(file_name) + ":" + std::to_string(error.location.line) + ":" +
         std::to_string(error.location.column) + ": " + error.message;
}

std::string_view ToString(OpKind kind) noexcept {
  switch (kind) {
    case OpKind::kBody:
      return "body";
    case OpKind::kFrame:
      return "frame";
    case OpKind::kPose:
      return "pose";
    case OpKind::kTwist:
      return "twist";
    case OpKind::kRemovePose:
    case OpKind::kRemoveTwist:
    case OpKind::kRemoveWrench:
      return "remove";
    case OpKind::kQuery:
      return "query";
    case OpKind::kUrdf:
      return "urdf";
    case OpKind::kJoint:
      return "joint";
    case OpKind::kJoints:
      return "joints";
    case OpKind::kBag:
      return "bag";
    case OpKind::kWrench:
      return "wrench";
    case OpKind::kAcceleration:
      return "acceleration";
  }
  return "?";
}

std::string_view ToString(QueryKind kind) noexcept {
  switch (kind) {
    case QueryKind::kPose:
      return "pose";
    case QueryKind::kPosition:
      return "position";
    case QueryKind::kOrientation:
      return "orientation";
    case QueryKind::kTwist:
      return "twist";
    case QueryKind::kLinearVelocity:
      return "linear_velocity";
    case QueryKind::kAngularVelocity:
      return "angular_velocity";
    case QueryKind::kJacobian:
      return "jacobian";
    case QueryKind::kWrench:
      return "wrench";
    case QueryKind::kForce:
      return "force";
    case QueryKind::kMoment:
      return "moment";
    case QueryKind::kAcceleration:
      return "acceleration";
    case QueryKind::kLinearAcceleration:
      return "linear_acceleration";
    case QueryKind::kAngularAcceleration:
      return "angular_acceleration";
  }
  return "?";
}

}  // namespace semgraph::script
