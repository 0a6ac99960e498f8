// yaml_tree_fuzzer: the generic YAML tree of tools/semgraph/yaml_tree.h on arbitrary bytes.
// Must never crash, hang or leak, and a tree it returns must keep the header's promises.
//
// Input: byte 0 picks the limits, the rest is the text.
//   byte 0 even   the scene-script limits (16 MiB, 64 levels, 2^23 nodes, 32 MiB expanded)
//   byte 0 odd    tiny limits (8 levels, 64 nodes, 300 expanded bytes), so that the fuzzer
//                 reaches every limit, the alias expansion count in particular, in 4 KB
// Checks of a returned tree (each recomputed here, not read from the builder):
//   - every child index is a node; every map has an even number of children (key, value);
//   - it is a tree with shared aliases: no node reaches itself (a walk terminates);
//   - the expanded size (one unit a node plus its scalar's bytes, aliases expanded) equals
//     expanded_bytes() and is within the limit; nodes are within theirs;
//   - every scalar is valid UTF-8 and the input was too (no NUL byte, no byte-order mark of
//     UTF-16/32);
//   - with the default limits and an expanded size below 2^16: the same document as yaml-cpp's
//     own YAML::Load (node kinds, scalar texts with \N and \_ re-encoded as UTF-8, plain vs.
//     quoted, children in order). YAML::Load is only called on inputs our tree accepted, whose
//     depth is at most 64: on others its recursion could overflow a sanitizer's stack.
// Errors must carry a 1-based location and a message.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "semgraph/yaml_tree.h"

namespace semgraph::fuzz {
namespace {

using script::kNoNode;
using script::NodeId;
using script::NodeKind;
using script::YamlTree;

[[noreturn]] void Fail(const std::string& why, std::string_view text) {
  std::fprintf(stderr,
               "\n==== yaml_tree_fuzzer FAILED ====\n%s\n---- text ----\n%.*s\n==== end ====\n",
               why.c_str(), static_cast<int>(text.size()), text.data());
  std::fflush(stderr);
  std::abort();
}

// An independent UTF-8 check (RFC 3629 table 3-7 ranges).
bool IsUtf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = b(i);
    std::size_t n;
    unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte
    if (c <= 0x7F) {
      ++i;
      continue;
    } else if (c >= 0xC2 && c <= 0xDF) {
      n = 2;
    } else if (c == 0xE0) {
      n = 3, lo = 0xA0;
    } else if (c == 0xED) {
      n = 3, hi = 0x9F;
    } else if (c >= 0xE1 && c <= 0xEF) {
      n = 3;
    } else if (c == 0xF0) {
      n = 4, lo = 0x90;
    } else if (c >= 0xF1 && c <= 0xF3) {
      n = 4;
    } else if (c == 0xF4) {
      n = 4, hi = 0x8F;
    } else {
      return false;
    }
    if (i + n > s.size() || b(i + 1) < lo || b(i + 1) > hi) return false;
    for (std::size_t k = 2; k < n; ++k) {
      if (b(i + k) < 0x80 || b(i + k) > 0xBF) return false;
    }
    i += n;
  }
  return true;
}

// yaml-cpp's scalar with the two raw bytes it makes of \N and \_ written as UTF-8 (the input is
// UTF-8, so a lone 0x85 or 0xA0 after a complete character can only come from those escapes).
std::string Reencoded(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const std::size_t n = c < 0x80 ? 1 : c < 0xC0 ? 0 : c < 0xE0 ? 2 : c < 0xF0 ? 3 : 4;
    if (n == 0) {
      out += '\xC2';
      out += s[i++];
    } else {
      out.append(s, i, n);
      i += n;
    }
  }
  return out;
}

// Expanded size of every node, memoized; aborts on a cycle.
struct Measure {
  std::vector<std::size_t> expanded;
};

Measure MeasureTree(const YamlTree& tree, std::string_view text) {
  const std::size_t n = tree.num_nodes();
  Measure m{std::vector<std::size_t>(n, 0)};
  std::vector<std::uint8_t> state(n, 0);              // 0 new, 1 on the stack, 2 done
  std::vector<std::pair<NodeId, std::size_t>> stack;  // node, next child to visit
  for (NodeId start = 0; start < n; ++start) {
    if (state[start] != 0) continue;
    stack.push_back({start, 0});
    state[start] = 1;
    while (!stack.empty()) {
      auto& [node, next] = stack.back();
      const auto view = tree.At(node);
      if (next < view.children.size()) {
        const NodeId child = view.children[next++];
        if (child >= n) Fail("a child index past the last node", text);
        if (state[child] == 1) Fail("a node reaches itself: the tree has a cycle", text);
        if (state[child] == 0) {
          state[child] = 1;
          stack.push_back({child, 0});
        }
        continue;
      }
      std::size_t size = 1 + view.text.size();
      for (const NodeId child : view.children) size += m.expanded[child];
      m.expanded[node] = size;
      state[node] = 2;
      stack.pop_back();
    }
  }
  return m;
}

// Our node against yaml-cpp's; `budget` bounds the walk (aliases are compared as copies).
void Compare(const YamlTree& tree, NodeId id, const YAML::Node& theirs, std::string_view text,
             int* budget) {
  if (--*budget < 0) return;
  const auto ours = tree.At(id);
  const auto where = "node at " + std::to_string(ours.location.line) + ":" +
                     std::to_string(ours.location.column) + ": ";
  switch (ours.kind) {
    case NodeKind::kNull:
      if (!theirs.IsNull()) Fail(where + "null here, not for YAML::Load", text);
      return;
    case NodeKind::kScalar: {
      if (!theirs.IsScalar()) Fail(where + "a scalar here, not for YAML::Load", text);
      if (ours.text != Reencoded(theirs.Scalar())) Fail(where + "scalar texts differ", text);
      const std::string& tag = theirs.Tag();
      if ((ours.style == script::ScalarStyle::kPlain) != (tag == "?") ||
          (ours.style == script::ScalarStyle::kString) !=
              (tag == "!" || tag == "tag:yaml.org,2002:str")) {
        Fail(where + "the style differs from the tag " + tag, text);
      }
      return;
    }
    case NodeKind::kSequence: {
      if (!theirs.IsSequence() || theirs.size() != ours.children.size()) {
        Fail(where + "a sequence of " + std::to_string(ours.children.size()) +
                 ", not for YAML::Load",
             text);
      }
      for (std::size_t i = 0; i < ours.children.size(); ++i) {
        Compare(tree, ours.children[i], theirs[i], text, budget);
      }
      return;
    }
    case NodeKind::kMap: {
      if (!theirs.IsMap() || 2 * theirs.size() != ours.children.size()) {
        Fail(where + "a map of " + std::to_string(ours.children.size() / 2) +
                 " pairs, not for YAML::Load",
             text);
      }
      std::size_t k = 0;
      for (const auto& pair : theirs) {  // yaml-cpp keeps a map's pairs in document order
        Compare(tree, ours.children[k], pair.first, text, budget);
        Compare(tree, ours.children[k + 1], pair.second, text, budget);
        k += 2;
      }
      return;
    }
  }
}

}  // namespace
}  // namespace semgraph::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace semgraph;
  using namespace semgraph::fuzz;
  if (size == 0) return 0;
  const bool tiny = (data[0] & 1u) != 0;
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  script::YamlLimits limits;
  if (tiny) {
    limits.max_depth = 8;
    limits.max_nodes = 64;
    limits.max_expanded_bytes = 300;
  }
  const auto tree = script::ParseYaml(text, limits);
  if (!tree) {
    const auto& e = tree.error();
    if (e.location.line < 1 || e.location.column < 1 || e.message.empty()) {
      Fail("an error without a 1-based location or a message: " + e.message, text);
    }
    return 0;
  }
  if (!IsUtf8(text) || text.find('\0') != std::string_view::npos) {
    Fail("accepted a text that is not UTF-8 or holds a NUL byte", text);
  }
  if (tree->num_nodes() > limits.max_nodes) Fail("more nodes than the limit", text);
  if (tree->root() == kNoNode) {
    if (tree->num_nodes() != 0 || tree->expanded_bytes() != 0) Fail("nodes without a root", text);
    return 0;
  }
  for (NodeId i = 0; i < tree->num_nodes(); ++i) {
    const auto v = tree->At(i);
    if (v.kind == NodeKind::kMap && v.children.size() % 2 != 0)
      Fail("a map with an odd child count", text);
    if (v.kind != NodeKind::kScalar && !v.text.empty()) Fail("text on a non-scalar", text);
    if ((v.kind == NodeKind::kScalar || v.kind == NodeKind::kNull) && !v.children.empty()) {
      Fail("children under a scalar", text);
    }
    if (!IsUtf8(v.text)) Fail("a scalar that is not UTF-8", text);
  }
  const Measure m = MeasureTree(*tree, text);
  if (m.expanded[tree->root()] != tree->expanded_bytes()) {
    Fail("expanded_bytes() " + std::to_string(tree->expanded_bytes()) + ", recomputed " +
             std::to_string(m.expanded[tree->root()]),
         text);
  }
  if (tree->expanded_bytes() > limits.max_expanded_bytes)
    Fail("expanded size over the limit", text);
  if (tiny || tree->expanded_bytes() > (1u << 16)) return 0;
  YAML::Node theirs;
  try {
    theirs = YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    Fail("our tree accepted a text YAML::Load refuses: " + e.msg, text);
  }
  int budget = 1 << 16;
  Compare(*tree, tree->root(), theirs, text, &budget);
  return 0;
}
