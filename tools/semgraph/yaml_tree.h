// File: tools/semgraph/yaml_tree.h
//
// A compact, read-only YAML tree for hostile input, built from yaml-cpp's event parser. It
// knows nothing about scene scripts (script_reader.h gives the tree its meaning); why the
// project keeps its own tree instead of yaml-cpp's YAML::Node is written in docs/yaml.md.
//
// What ParseYaml() guarantees of a tree it returns, or refuses with a located YamlError:
//  - the text is UTF-8: no byte-order mark of UTF-16 or UTF-32, no raw NUL byte, no invalid
//    byte sequence (the error names the line and column of the first offending byte);
//  - scalars hold UTF-8: every YAML escape gives its character in UTF-8 (yaml-cpp 0.7 gives
//    \N and \_ as the raw bytes 0x85 and 0xA0; they are re-encoded as U+0085 and U+00A0), and an
//    escape naming a surrogate or a value above U+10FFFF is refused;
//  - one document; nesting at most YamlLimits::max_depth levels, checked while parsing, so that
//    yaml-cpp's recursive descent never goes deeper; at most max_nodes nodes; at most max_bytes
//    of text;
//  - aliases are shared, not copied (an alias is one child index), but counted at their expanded
//    size: the expanded size of the document, one unit per node plus the bytes of its scalar,
//    an alias counting as the expanded size of its anchor's node, is at most
//    max_expanded_bytes. So whatever walks the tree as if it were a copy (a reader that copies
//    names out of it, say) does at most that much work, and an alias bomb is refused at the
//    alias that crosses the limit;
//  - it is a tree: an alias to a collection that is still open (it would contain itself) is
//    refused, so a walk always terminates.
//
// Costs: O(text) time; 32 bytes a node, plus the scalars' text once and one 4-byte index per
// child. ParseYaml is a pure function (thread-safe); a YamlTree is immutable once returned.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "semgraph/base/expected.h"
#include "semgraph/script/export.h"

namespace semgraph::script {

/// A position in the text, both 1-based; the column counts bytes.
struct SourceLocation {
  int line = 1;
  int column = 1;
};

enum class NodeKind : std::uint8_t { kNull, kScalar, kSequence, kMap };

/// How a scalar was written. Only plain scalars and those tagged !!int / !!float can be numbers
/// in the core schema; a quoted "1" is a string.
enum class ScalarStyle : std::uint8_t { kPlain, kString, kNumberTag, kOtherTag };

struct YamlLimits {
  std::size_t max_bytes = std::size_t{16} << 20;           // 16 MiB of text
  int max_depth = 64;                                      // nested collections
  std::size_t max_nodes = std::size_t{1} << 23;            // more than 16 MiB of text can hold
  std::size_t max_expanded_bytes = std::size_t{32} << 20;  // twice max_bytes: see the header
};

/// Why a text is not an acceptable YAML document, and where.
struct YamlError {
  SourceLocation location;
  std::string message;
};

using NodeId = std::uint32_t;
inline constexpr NodeId kNoNode = std::numeric_limits<NodeId>::max();

/// What a reader sees of a node. The views point into the tree and live as long as it.
struct NodeView {
  NodeKind kind;
  ScalarStyle style;
  SourceLocation location;           // of the node's first token (a null map value: its key's)
  std::string_view text;             // scalars: the value, escapes resolved
  std::span<const NodeId> children;  // sequences: items; maps: key, value, key, value, ...
};

class SEMGRAPH_SCRIPT_EXPORT YamlTree {
 public:
  /// The document's root node; kNoNode for an empty document.
  [[nodiscard]] NodeId root() const noexcept { return root_; }
  /// @pre id < num_nodes().
  [[nodiscard]] NodeView At(NodeId id) const noexcept;
  /// Nodes stored (an alias adds none).
  [[nodiscard]] std::size_t num_nodes() const noexcept { return nodes_.size(); }
  /// The document's expanded size (see the header): what a copying walk would touch.
  [[nodiscard]] std::size_t expanded_bytes() const noexcept { return expanded_bytes_; }

 private:
  friend class TreeBuilder;
  struct Node {
    NodeKind kind = NodeKind::kNull;
    ScalarStyle style = ScalarStyle::kPlain;
    SourceLocation location;
    std::uint32_t text_begin = 0, text_size = 0;      // scalars: in text_
    std::uint32_t first_child = 0, num_children = 0;  // collections: in children_
  };
  std::vector<Node> nodes_;
  std::string text_;              // every scalar's text, concatenated
  std::vector<NodeId> children_;  // grouped by parent, in document order
  NodeId root_ = kNoNode;
  std::size_t expanded_bytes_ = 0;
};

/// Parses one YAML document within `limits`. Never throws except std::bad_alloc.
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT base::Expected<YamlTree, YamlError> ParseYaml(
    std::string_view text, const YamlLimits& limits = {});

/// YAML 1.2 core-schema float (which includes the decimal ints): [-+]? (digits [. digits?] |
/// . digits) ([eE] [-+]? digits)?, [-+]?.inf (.Inf, .INF), .nan (.NaN, .NAN). Anything else
/// (hex, octal, "1_000", "abc", "inf") is not a number; false then. Overflow gives +-inf.
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT bool ParseCoreNumber(std::string_view text, double* value);

/// `text` for a message: in double quotes, `"` and `\` escaped, control bytes as \xHH, and cut
/// (at a character boundary) after `max_shown` bytes; a cut text ends in `..." (N bytes)`, so
/// that a message never echoes megabytes.
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT std::string QuoteForMessage(std::string_view text,
                                                                 std::size_t max_shown = 40);

}  // namespace semgraph::script
