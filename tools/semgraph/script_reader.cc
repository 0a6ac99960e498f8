// Scene-script reader. Contract: script_reader.h and spec/scene-script.md.
//
// Two stages. (1) yaml-cpp's event parser feeds TreeBuilder, which builds a compact tree and
// enforces the size limits while parsing (yaml-cpp's own Node tree costs several hundred bytes a
// node and has no depth limit below 2000). (2) Interpreter walks only the shapes a script may
// have, so its work is bounded by the number of ops whatever aliases the document contains.
#include "semgraph/script_reader.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/parser.h>

#include <algorithm>
#include <cstdlib>
#include <istream>
#include <limits>
#include <set>
#include <span>
#include <streambuf>
#include <utility>

namespace semgraph::tools {

namespace {

using base::Unexpected;

constexpr std::uint32_t kNoNode = std::numeric_limits<std::uint32_t>::max();

// ====================================================================== compact YAML tree

enum class NodeKind : std::uint8_t { kNull, kScalar, kSequence, kMap };

// How a scalar was written. Only plain scalars and those tagged !!int / !!float can be numbers:
// a quoted "1" is a string, and accepting it would hide a typo-level mistake.
enum class ScalarStyle : std::uint8_t { kPlain, kString, kNumberTag, kOtherTag };

// 28 bytes a node plus its text: a 16 MiB script has at most ~8 M nodes ("1," is 2 bytes).
struct YamlNode {
  NodeKind kind = NodeKind::kNull;
  ScalarStyle style = ScalarStyle::kPlain;
  SourceLocation location;
  std::uint32_t text_begin = 0, text_size = 0;      // scalars: in YamlTree::text
  std::uint32_t first_child = 0, num_children = 0;  // collections: in YamlTree::children
};

struct YamlTree {
  std::vector<YamlNode> nodes;
  std::string text;                     // every scalar's text, concatenated
  std::vector<std::uint32_t> children;  // grouped by parent; a map's keys and values alternate
  std::uint32_t root = kNoNode;
};

// What the interpreter sees of a node.
struct NodeView {
  NodeKind kind;
  ScalarStyle style;
  SourceLocation location;
  std::string_view text;
  std::span<const std::uint32_t> children;
};

SourceLocation FromMark(const YAML::Mark& mark) {
  // yaml-cpp marks are 0-based; a null mark (-1) has no position, so point at the start.
  return SourceLocation{mark.line < 0 ? 1 : mark.line + 1, mark.column < 0 ? 1 : mark.column + 1};
}

// Thrown by TreeBuilder to stop yaml-cpp mid-document: its event API has no other way to stop.
struct StopParsing {
  ScriptError error;
};

ScalarStyle StyleOf(const std::string& tag) {
  if (tag == "?") return ScalarStyle::kPlain;
  if (tag == "!" || tag == "tag:yaml.org,2002:str") return ScalarStyle::kString;
  if (tag == "tag:yaml.org,2002:int" || tag == "tag:yaml.org,2002:float") {
    return ScalarStyle::kNumberTag;
  }
  return ScalarStyle::kOtherTag;
}

class TreeBuilder final : public YAML::EventHandler {
 public:
  explicit TreeBuilder(YamlTree& tree) : tree_(tree) {}

  void OnDocumentStart(const YAML::Mark& mark) override {
    if (++documents_ > 1) Stop(mark, "a script is a single YAML document; this is a second one");
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    Add(mark, anchor, NodeKind::kNull, ScalarStyle::kPlain, {});
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    // Shared, not copied: an alias costs one index however large its target.
    if (anchor >= anchors_.size() || anchors_[anchor] == kNoNode) Stop(mark, "unknown alias");
    Attach(anchors_[anchor]);
  }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                const std::string& value) override {
    Add(mark, anchor, NodeKind::kScalar, StyleOf(tag), value);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string& /*tag*/, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value /*style*/) override {
    Open(mark, anchor, NodeKind::kSequence);
  }
  void OnSequenceEnd() override { open_.pop_back(); }
  void OnMapStart(const YAML::Mark& mark, const std::string& /*tag*/, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value /*style*/) override {
    Open(mark, anchor, NodeKind::kMap);
  }
  void OnMapEnd() override { open_.pop_back(); }

  // Groups the recorded (parent, child) edges into YamlTree::children, in document order.
  void Finish() {
    for (const Edge& e : edges_) ++tree_.nodes[e.parent].num_children;
    std::uint32_t offset = 0;
    for (YamlNode& n : tree_.nodes) {
      n.first_child = offset;
      offset += n.num_children;
      n.num_children = 0;  // refilled below
    }
    tree_.children.resize(edges_.size());
    for (const Edge& e : edges_) {
      YamlNode& parent = tree_.nodes[e.parent];
      tree_.children[parent.first_child + parent.num_children++] = e.child;
    }
    edges_ = {};
  }

 private:
  struct Edge {
    std::uint32_t parent, child;
  };
  struct OpenCollection {
    std::uint32_t node;
    std::uint32_t num_children;
    std::uint32_t last_child;
  };

  [[noreturn]] static void Stop(const YAML::Mark& mark, std::string message) {
    throw StopParsing{ScriptError{FromMark(mark), std::move(message)}};
  }

  std::uint32_t Add(const YAML::Mark& mark, YAML::anchor_t anchor, NodeKind kind, ScalarStyle style,
                    const std::string& text) {
    if (tree_.nodes.size() >= kMaxYamlNodes) {
      Stop(mark, "the script has more than " + std::to_string(kMaxYamlNodes) + " YAML nodes");
    }
    const auto index = static_cast<std::uint32_t>(tree_.nodes.size());
    YamlNode& node = tree_.nodes.emplace_back();
    node.kind = kind;
    node.style = style;
    node.location = FromMark(mark);
    node.text_begin = static_cast<std::uint32_t>(tree_.text.size());
    node.text_size = static_cast<std::uint32_t>(text.size());
    tree_.text += text;
    if (kind == NodeKind::kNull && !open_.empty()) {
      // An empty map value (`name:`) gets yaml-cpp's mark of the *next* token, often on the
      // next line; its key is where the reader should look.
      const OpenCollection& parent = open_.back();
      if (tree_.nodes[parent.node].kind == NodeKind::kMap && parent.num_children % 2 == 1) {
        node.location = tree_.nodes[parent.last_child].location;
      }
    }
    Attach(index);
    if (anchor != 0) {
      if (anchor >= anchors_.size()) anchors_.resize(anchor + 1, kNoNode);
      anchors_[anchor] = index;
    }
    return index;
  }

  void Open(const YAML::Mark& mark, YAML::anchor_t anchor, NodeKind kind) {
    // Checked before yaml-cpp descends further, so its recursion stays this shallow.
    if (open_.size() >= static_cast<std::size_t>(kMaxNestingDepth)) {
      Stop(mark,
           "the document is nested more than " + std::to_string(kMaxNestingDepth) + " levels deep");
    }
    const std::uint32_t index = Add(mark, anchor, kind, ScalarStyle::kPlain, {});
    open_.push_back(OpenCollection{index, 0, kNoNode});
  }

  void Attach(std::uint32_t index) {
    if (open_.empty()) {
      tree_.root = index;
      return;
    }
    OpenCollection& parent = open_.back();
    edges_.push_back(Edge{parent.node, index});
    ++parent.num_children;
    parent.last_child = index;
  }

  YamlTree& tree_;
  std::vector<Edge> edges_;             // (parent, child) in document order
  std::vector<OpenCollection> open_;    // collections being filled, outermost first
  std::vector<std::uint32_t> anchors_;  // yaml-cpp anchor id -> node
  int documents_ = 0;
};

// yaml-cpp reads from an istream; this one reads the text in place instead of copying it.
class ViewStreamBuf final : public std::streambuf {
 public:
  explicit ViewStreamBuf(std::string_view text) {
    // The get area is only read (never written), so dropping const is safe.
    char* begin = const_cast<char*>(text.data());
    setg(begin, begin, begin + text.size());
  }
};

// ====================================================================== numbers

// YAML 1.2 core-schema floats and decimal ints: [-+]? ( digits [. digits?] | . digits )
// ([eE] [-+]? digits)?, plus [-+]?.inf and .nan. Anything else (hex, "1_000", "abc") is not a
// number in a script.
bool ParseNumber(std::string_view text, double* value) {
  std::size_t i = 0;
  bool negative = false;
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) {
    negative = text[i] == '-';
    ++i;
  }
  const std::string_view body = text.substr(i);
  if (body == ".inf" || body == ".Inf" || body == ".INF") {
    *value = negative ? -std::numeric_limits<double>::infinity()
                      : std::numeric_limits<double>::infinity();
    return true;
  }
  if (i == 0 && (body == ".nan" || body == ".NaN" || body == ".NAN")) {
    *value = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  const auto is_digit = [](char c) { return c >= '0' && c <= '9'; };
  std::size_t j = 0, mantissa_digits = 0;
  while (j < body.size() && is_digit(body[j])) ++j, ++mantissa_digits;
  if (j < body.size() && body[j] == '.') {
    ++j;
    while (j < body.size() && is_digit(body[j])) ++j, ++mantissa_digits;
  }
  if (mantissa_digits == 0) return false;
  if (j < body.size() && (body[j] == 'e' || body[j] == 'E')) {
    ++j;
    if (j < body.size() && (body[j] == '+' || body[j] == '-')) ++j;
    std::size_t exponent_digits = 0;
    while (j < body.size() && is_digit(body[j])) ++j, ++exponent_digits;
    if (exponent_digits == 0) return false;
  }
  if (j != body.size()) return false;
  // The grammar above is a subset of strtod's (the program never changes the C locale). An
  // overflow gives +-inf, which the scene graph then rejects as invalid_number.
  const std::string copy(text);
  *value = std::strtod(copy.c_str(), nullptr);
  return true;
}

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
  kNumFields,
};
constexpr Field kNoField = kNumFields;

constexpr std::string_view kFieldNames[kNumFields] = {
    "op",       "kind",  "name",        "body",      "of",
    "wrt",      "point", "orientation", "ref_point", "ref_orientation",
    "ref_body", "coord", "position",    "rotation",  "linear",
    "angular"};

static_assert(kFieldNames[kNumFields - 1] == "angular", "one name per Field, in order");

constexpr std::uint32_t Bit(Field f) { return std::uint32_t{1} << f; }

// One op variant: the fields it accepts and the ones it needs. A required field may be
// supplied by a shorthand instead (`of` for point/orientation, `wrt` for the reference side).
struct Requirement {
  Field field;
  Field shorthand;  // kNoField: none
};
struct Shape {
  std::string_view label;  // for messages: "a 'pose' op", "a 'position' query"
  std::uint32_t allowed = 0;
  std::vector<Requirement> required;
};

Shape ShapeOf(OpKind op, QueryKind query) {
  constexpr std::uint32_t kHeader = Bit(kOp) | Bit(kKind);
  constexpr std::uint32_t kShorthand = Bit(kOf) | Bit(kWrt);
  constexpr std::uint32_t kPoseNames = kShorthand | Bit(kPoint) | Bit(kOrientation) | Bit(kBody) |
                                       Bit(kRefPoint) | Bit(kRefOrientation) | Bit(kRefBody) |
                                       Bit(kCoord);
  constexpr std::uint32_t kTwistNames = Bit(kPoint) | Bit(kBody) | Bit(kRefBody) | Bit(kCoord);
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
      return {"a 'pose' op", Bit(kOp) | kPoseNames | Bit(kPosition) | Bit(kRotation),
              pose_required};
    case OpKind::kTwist:
      return {"a 'twist' op", Bit(kOp) | kTwistNames | Bit(kLinear) | Bit(kAngular),
              twist_required};
    case OpKind::kRemovePose:
      return {"a 'remove' op of kind 'pose'",
              kHeader | kShorthand,
              {{kOf, kNoField}, {kWrt, kNoField}}};
    case OpKind::kRemoveTwist:
      return {"a 'remove' op of kind 'twist'",
              kHeader | Bit(kPoint) | Bit(kRefBody),
              {{kPoint, kNoField}, {kRefBody, kNoField}}};
    case OpKind::kQuery:
      break;
  }
  switch (query) {
    case QueryKind::kPose:
      return {"a 'pose' query", kHeader | kPoseNames, pose_required};
    case QueryKind::kPosition:
      return {"a 'position' query",
              kHeader | kShorthand | Bit(kPoint) | Bit(kBody) | Bit(kRefPoint) | Bit(kRefBody) |
                  Bit(kCoord),
              {{kPoint, kOf}, {kRefPoint, kWrt}, {kCoord, kWrt}}};
    case QueryKind::kOrientation:
      return {"an 'orientation' query",
              kHeader | kShorthand | Bit(kOrientation) | Bit(kBody) | Bit(kRefOrientation) |
                  Bit(kRefBody) | Bit(kCoord),
              {{kOrientation, kOf}, {kRefOrientation, kWrt}, {kCoord, kWrt}}};
    case QueryKind::kTwist:
      return {"a 'twist' query", kHeader | kTwistNames, twist_required};
    case QueryKind::kLinearVelocity:
      return {"a 'linear_velocity' query", kHeader | kTwistNames, twist_required};
    case QueryKind::kAngularVelocity:
      // No point: an angular velocity is the same at every point of the body.
      return {"an 'angular_velocity' query",
              kHeader | Bit(kBody) | Bit(kRefBody) | Bit(kCoord),
              {{kBody, kNoField}, {kRefBody, kNoField}, {kCoord, kNoField}}};
  }
  return {};
}

std::string AllowedList(std::uint32_t allowed) {
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
std::string Quoted(std::string_view text) {
  const auto is_continuation = [&](std::size_t i) {
    return (static_cast<unsigned char>(text[i]) & 0xC0u) == 0x80u;
  };
  std::size_t shown = std::min<std::size_t>(text.size(), 40);
  while (shown > 0 && shown < text.size() && is_continuation(shown)) --shown;
  std::string s = "\"";
  for (std::size_t i = 0; i < shown; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '"' || c == '\\') {
      s += '\\';
      s += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7F) {
      static constexpr char kHex[] = "0123456789abcdef";
      s += "\\x";
      s += kHex[c >> 4];
      s += kHex[c & 0xF];
    } else {
      s += static_cast<char>(c);
    }
  }
  if (shown < text.size()) s += "...";
  return s + "\"";
}

// ====================================================================== interpreter

class Interpreter {
 public:
  explicit Interpreter(const YamlTree& tree) : tree_(tree) {}

  bool ReadDocument(Script* script);
  const ScriptError& error() const { return error_; }

 private:
  NodeView At(std::uint32_t i) const {
    const YamlNode& n = tree_.nodes[i];
    const std::string_view text = tree_.text;
    const std::span<const std::uint32_t> children = tree_.children;
    return NodeView{n.kind, n.style, n.location, text.substr(n.text_begin, n.text_size),
                    children.subspan(n.first_child, n.num_children)};
  }

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
  const std::uint32_t root = tree_.root;
  if (At(root).kind != NodeKind::kMap) {
    return Fail(root, "a script is a map with 'ops' (and optionally 'representation'), got " +
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
    } else {
      return Fail(key, "unknown top-level field " + Quoted(name) +
                           " (expected 'representation' and 'ops')");
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
  static constexpr std::string_view kOps = "body, frame, pose, twist, remove, query";
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
  } else if (op_name.text == "remove") {
    if (value[kKind] == kNoNode) return Fail(node, "a 'remove' op needs 'kind' (pose or twist)");
    if (kind_is_text && kind_text == "pose") {
      op->kind = OpKind::kRemovePose;
    } else if (kind_is_text && kind_text == "twist") {
      op->kind = OpKind::kRemoveTwist;
    } else {
      return Fail(value[kKind], "the 'kind' of a 'remove' op must be pose or twist, got " +
                                    Describe(value[kKind]));
    }
  } else if (op_name.text == "query") {
    op->kind = OpKind::kQuery;
    static constexpr std::string_view kQueries =
        "pose, position, orientation, twist, linear_velocity, angular_velocity";
    if (value[kKind] == kNoNode) {
      return Fail(node, "a 'query' op needs 'kind' (one of " + std::string(kQueries) + ")");
    }
    static constexpr std::pair<std::string_view, QueryKind> kKinds[] = {
        {"pose", QueryKind::kPose},
        {"position", QueryKind::kPosition},
        {"orientation", QueryKind::kOrientation},
        {"twist", QueryKind::kTwist},
        {"linear_velocity", QueryKind::kLinearVelocity},
        {"angular_velocity", QueryKind::kAngularVelocity}};
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
      {kCoord, &names.coord}};
  for (const auto& [field, out] : explicit_names) {
    if (value[field] != kNoNode && !ReadText(value[field], kFieldNames[field], out)) return false;
  }
  const std::pair<Field, std::array<double, 3>*> vectors[] = {
      {kPosition, &op->position}, {kLinear, &op->linear}, {kAngular, &op->angular}};
  for (const auto& [field, out] : vectors) {
    if (value[field] != kNoNode && !ReadVector3(value[field], kFieldNames[field], out)) {
      return false;
    }
  }
  if (value[kRotation] != kNoNode && !ReadRotation(value[kRotation], &op->rotation)) return false;
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
  if (n.kind != NodeKind::kScalar || !may_be_number || !ParseNumber(n.text, out)) {
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
  YamlTree tree;
  try {
    ViewStreamBuf buffer(text);
    std::istream in(&buffer);
    YAML::Parser parser(in);
    TreeBuilder builder(tree);
    while (parser.HandleNextDocument(builder)) {
    }
    builder.Finish();
  } catch (const StopParsing& stop) {
    return Unexpected{stop.error};
  } catch (const YAML::Exception& e) {
    return Unexpected{ScriptError{FromMark(e.mark), "invalid YAML: " + e.msg}};
  }
  if (tree.root == kNoNode) {
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
      return "remove";
    case OpKind::kQuery:
      return "query";
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
  }
  return "?";
}

}  // namespace semgraph::tools
