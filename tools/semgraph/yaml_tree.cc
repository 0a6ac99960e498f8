// Compact YAML tree. Contract: yaml_tree.h; the reasons for it: docs/yaml.md.
//
// Three steps: (1) CheckEncoding looks at the raw bytes (yaml-cpp would guess UTF-16 from a
// leading NUL and pass invalid bytes through); (2) yaml-cpp's event parser feeds TreeBuilder,
// which enforces the limits event by event, so that nothing is ever built or recursed into
// beyond them; (3) Finish groups the children by parent.
#include "semgraph/yaml_tree.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/parser.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <istream>
#include <streambuf>
#include <utility>

#include "semgraph/base/utf8.h"

namespace semgraph::script {

using base::Unexpected;

NodeView YamlTree::At(NodeId id) const noexcept {
  const Node& n = nodes_[id];
  return NodeView{n.kind, n.style, n.location,
                  std::string_view(text_).substr(n.text_begin, n.text_size),
                  std::span<const NodeId>(children_).subspan(n.first_child, n.num_children)};
}

namespace {

std::string Hex(unsigned char c) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  return std::string("0x") + kHex[c >> 4] + kHex[c & 0xF];
}

// The text must be UTF-8 before yaml-cpp sees it: yaml-cpp picks UTF-16 or UTF-32 from a
// byte-order mark or from NUL bytes among the first four, and copies invalid bytes into scalars.
base::Expected<base::Ok, YamlError> CheckEncoding(std::string_view text) {
  const auto starts = [&](std::string_view prefix) {
    return text.substr(0, prefix.size()) == prefix;
  };
  using namespace std::string_view_literals;
  if (starts("\x00\x00\xFE\xFF"sv) || starts("\xFF\xFE\x00\x00"sv)) {
    return Unexpected{YamlError{{1, 1},
                                "the text starts with a UTF-32 byte-order mark; the "
                                "script must be UTF-8 (convert it, e.g. with iconv)"}};
  }
  if (starts("\xFE\xFF"sv) || starts("\xFF\xFE"sv)) {
    return Unexpected{YamlError{{1, 1},
                                "the text starts with a UTF-16 byte-order mark; the "
                                "script must be UTF-8 (convert it, e.g. with iconv)"}};
  }
  int line = 1, column = 1;
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == 0) {
      std::string message = "a raw NUL byte; the script must be UTF-8 text";
      if (i < 4) message += " (NUL bytes at the start are the mark of UTF-16 or UTF-32 text)";
      message += ". Write U+0000 in a name as \\0 inside double quotes";
      return Unexpected{YamlError{{line, column}, std::move(message)}};
    }
    const std::size_t n = base::Utf8Length(text, i);
    if (n == 0) {
      return Unexpected{YamlError{{line, column},
                                  "byte " + Hex(c) +
                                      " is not valid UTF-8; the script must be UTF-8 text "
                                      "(a Latin-1 or UTF-16 file must be converted)"}};
    }
    if (c == '\n') {
      ++line, column = 1;
    } else {
      column += static_cast<int>(n);  // bytes, as yaml-cpp's marks count them
    }
    i += n;
  }
  return base::Ok{};
}

// yaml-cpp 0.7 gives the escapes \N and \_ as the single bytes 0x85 and 0xA0 (every other
// escape it encodes in UTF-8). The text was checked to be UTF-8 and every other escape yields
// whole UTF-8 sequences, so a byte that does not start a sequence here can only be one of those
// two: it becomes the UTF-8 of U+0085 / U+00A0.
void RepairEscapes(std::string* value) {
  std::size_t i = 0;
  while (i < value->size() && base::Utf8Length(*value, i) != 0) i += base::Utf8Length(*value, i);
  if (i == value->size()) return;  // the common case: nothing to repair
  std::string repaired = value->substr(0, i);
  while (i < value->size()) {
    const std::size_t n = base::Utf8Length(*value, i);
    if (n == 0) {
      repaired += '\xC2';  // U+0080..U+00BF is C2 followed by the byte itself
      repaired += (*value)[i];
      ++i;
    } else {
      repaired.append(*value, i, n);
      i += n;
    }
  }
  *value = std::move(repaired);
}

SourceLocation FromMark(const YAML::Mark& mark) {
  // yaml-cpp marks are 0-based; a null mark (-1) has no position, so point at the start.
  return SourceLocation{mark.line < 0 ? 1 : mark.line + 1, mark.column < 0 ? 1 : mark.column + 1};
}

// Thrown by TreeBuilder to stop yaml-cpp mid-document: its event API has no other way to stop.
struct StopParsing {
  YamlError error;
};

ScalarStyle StyleOf(const std::string& tag) {
  if (tag == "?") return ScalarStyle::kPlain;
  if (tag == "!" || tag == "tag:yaml.org,2002:str") return ScalarStyle::kString;
  if (tag == "tag:yaml.org,2002:int" || tag == "tag:yaml.org,2002:float") {
    return ScalarStyle::kNumberTag;
  }
  return ScalarStyle::kOtherTag;
}

// yaml-cpp reads from an istream; this one reads the text in place instead of copying it.
class ViewStreamBuf final : public std::streambuf {
 public:
  explicit ViewStreamBuf(std::string_view text) {
    // The get area is only read (never written), so dropping const is safe.
    char* begin = const_cast<char*>(text.data());
    setg(begin, begin, begin + text.size());
  }
};

}  // namespace

class TreeBuilder final : public YAML::EventHandler {
 public:
  TreeBuilder(YamlTree& tree, const YamlLimits& limits) : tree_(tree), limits_(limits) {}

  void OnDocumentStart(const YAML::Mark& mark) override {
    if (++documents_ > 1) Stop(mark, "a script is a single YAML document; this is a second one");
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    std::string empty;
    Add(mark, anchor, NodeKind::kNull, ScalarStyle::kPlain, empty);
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    if (anchor >= anchors_.size() || anchors_[anchor].node == kNoNode) Stop(mark, "unknown alias");
    const Anchor& target = anchors_[anchor];
    if (target.open) {
      Stop(mark,
           "this alias refers to a collection that contains it (a recursive structure); "
           "aliases must refer to a complete node");
    }
    Expand(mark, target.expanded_bytes);
    Attach(target.node);  // shared, not copied: one index however large its target
  }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                const std::string& value) override {
    std::string text = value;
    RepairEscapes(&text);
    Add(mark, anchor, NodeKind::kScalar, StyleOf(tag), text);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string& /*tag*/, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value /*style*/) override {
    Open(mark, anchor, NodeKind::kSequence);
  }
  void OnSequenceEnd() override { Close(); }
  void OnMapStart(const YAML::Mark& mark, const std::string& /*tag*/, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value /*style*/) override {
    Open(mark, anchor, NodeKind::kMap);
  }
  void OnMapEnd() override { Close(); }

  // Groups the recorded (parent, child) edges into children_, in document order.
  void Finish() {
    for (const Edge& e : edges_) ++tree_.nodes_[e.parent].num_children;
    std::uint32_t offset = 0;
    for (YamlTree::Node& n : tree_.nodes_) {
      n.first_child = offset;
      offset += n.num_children;
      n.num_children = 0;  // refilled below
    }
    tree_.children_.resize(edges_.size());
    for (const Edge& e : edges_) {
      YamlTree::Node& parent = tree_.nodes_[e.parent];
      tree_.children_[parent.first_child + parent.num_children++] = e.child;
    }
    edges_ = {};
    tree_.expanded_bytes_ = expanded_;
  }

 private:
  struct Edge {
    NodeId parent, child;
  };
  struct OpenCollection {
    NodeId node;
    std::uint32_t num_children;
    NodeId last_child;
    std::size_t expanded_at_open;  // expanded_ before the collection's own unit
    YAML::anchor_t anchor;
  };
  struct Anchor {
    NodeId node = kNoNode;
    bool open = false;               // a collection not yet closed
    std::size_t expanded_bytes = 0;  // of the node, once complete
  };

  [[noreturn]] static void Stop(const YAML::Mark& mark, std::string message) {
    throw StopParsing{YamlError{FromMark(mark), std::move(message)}};
  }

  // Counts `bytes` more of the expanded document; refuses at the node that crosses the limit.
  void Expand(const YAML::Mark& mark, std::size_t bytes) {
    if (bytes > limits_.max_expanded_bytes - expanded_) {
      Stop(mark, "the document is too large with its aliases expanded: more than " +
                     std::to_string(limits_.max_expanded_bytes >> 20) +
                     " MiB (one byte a node plus the scalars' text, an alias counting as a copy "
                     "of its anchor)");
    }
    expanded_ += bytes;
  }

  NodeId Add(const YAML::Mark& mark, YAML::anchor_t anchor, NodeKind kind, ScalarStyle style,
             const std::string& text) {
    if (tree_.nodes_.size() >= limits_.max_nodes) {
      Stop(mark, "the document has more than " + std::to_string(limits_.max_nodes) + " nodes");
    }
    Expand(mark, 1 + text.size());
    const auto index = static_cast<NodeId>(tree_.nodes_.size());
    YamlTree::Node& node = tree_.nodes_.emplace_back();
    node.kind = kind;
    node.style = style;
    node.location = FromMark(mark);
    node.text_begin = static_cast<std::uint32_t>(tree_.text_.size());
    node.text_size = static_cast<std::uint32_t>(text.size());
    tree_.text_ += text;
    if (kind == NodeKind::kNull && !open_.empty()) {
      // An empty map value (`name:`) gets yaml-cpp's mark of the *next* token, often on the
      // next line; its key is where the reader should look.
      const OpenCollection& parent = open_.back();
      if (tree_.nodes_[parent.node].kind == NodeKind::kMap && parent.num_children % 2 == 1) {
        node.location = tree_.nodes_[parent.last_child].location;
      }
    }
    Attach(index);
    if (anchor != 0) {
      if (anchor >= anchors_.size()) anchors_.resize(anchor + 1);
      anchors_[anchor] = Anchor{index, false, 1 + text.size()};
    }
    return index;
  }

  void Open(const YAML::Mark& mark, YAML::anchor_t anchor, NodeKind kind) {
    // Checked before yaml-cpp descends further, so its recursion stays this shallow.
    if (open_.size() >= static_cast<std::size_t>(limits_.max_depth)) {
      Stop(mark, "the document is nested more than " + std::to_string(limits_.max_depth) +
                     " levels deep");
    }
    const std::size_t before = expanded_;
    std::string empty;
    const NodeId index = Add(mark, anchor, kind, ScalarStyle::kPlain, empty);
    if (anchor != 0) anchors_[anchor].open = true;
    open_.push_back(OpenCollection{index, 0, kNoNode, before, anchor});
  }

  void Close() {
    const OpenCollection closed = open_.back();
    open_.pop_back();
    if (closed.anchor != 0) {
      // Everything counted since the collection opened is its own expanded size.
      anchors_[closed.anchor].open = false;
      anchors_[closed.anchor].expanded_bytes = expanded_ - closed.expanded_at_open;
    }
  }

  void Attach(NodeId index) {
    if (open_.empty()) {
      tree_.root_ = index;
      return;
    }
    OpenCollection& parent = open_.back();
    edges_.push_back(Edge{parent.node, index});
    ++parent.num_children;
    parent.last_child = index;
  }

  YamlTree& tree_;
  const YamlLimits& limits_;
  std::vector<Edge> edges_;           // (parent, child) in document order
  std::vector<OpenCollection> open_;  // collections being filled, outermost first
  std::vector<Anchor> anchors_;       // by yaml-cpp anchor id
  std::size_t expanded_ = 0;          // the expanded size so far
  int documents_ = 0;
};

base::Expected<YamlTree, YamlError> ParseYaml(std::string_view text, const YamlLimits& limits) {
  if (text.size() > limits.max_bytes) {
    return Unexpected{YamlError{
        {1, 1}, "the text is larger than " + std::to_string(limits.max_bytes >> 20) + " MiB"}};
  }
  if (auto encoding = CheckEncoding(text); !encoding) return Unexpected{encoding.error()};
  YamlTree tree;
  try {
    ViewStreamBuf buffer(text);
    std::istream in(&buffer);
    YAML::Parser parser(in);
    TreeBuilder builder(tree, limits);
    while (parser.HandleNextDocument(builder)) {
    }
    builder.Finish();
  } catch (const StopParsing& stop) {
    return Unexpected{stop.error};
  } catch (const YAML::Exception& e) {
    std::string message = e.msg;
    // yaml-cpp says "invalid unicode: 55296" for \uD800; say which rule it breaks.
    static constexpr std::string_view kInvalidUnicode = "invalid unicode: ";
    if (message.rfind(kInvalidUnicode, 0) == 0) {
      const unsigned long code =
          std::strtoul(message.c_str() + kInvalidUnicode.size(), nullptr, 10);
      char hex[16];
      std::snprintf(hex, sizeof(hex), "U+%04lX", code);
      message = std::string("the escape names ") + hex +
                (code >= 0xD800 && code <= 0xDFFF
                     ? ", a UTF-16 surrogate, which is not a character (write the character "
                       "itself, or \\U with its full code point)"
                     : ", which is above U+10FFFF, the last Unicode code point");
    }
    return Unexpected{YamlError{FromMark(e.mark), "invalid YAML: " + message}};
  }
  return tree;
}

bool ParseCoreNumber(std::string_view text, double* value) {
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

std::string QuoteForMessage(std::string_view text, std::size_t max_shown) {
  const auto is_continuation = [&](std::size_t i) {
    return (static_cast<unsigned char>(text[i]) & 0xC0u) == 0x80u;
  };
  std::size_t shown = std::min(text.size(), max_shown);
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
  if (shown < text.size()) return s + "...\" (" + std::to_string(text.size()) + " bytes)";
  return s + "\"";
}

}  // namespace semgraph::script
