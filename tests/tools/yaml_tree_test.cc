// Unit tests of the generic YAML tree (tools/semgraph/yaml_tree.h): its shape, the UTF-8 of
// escapes, the encoding checks, the limits (the expanded size in particular) with their
// locations, and the core-schema number grammar. Expected values are worked out by hand in the
// comments.
#include "semgraph/yaml_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace semgraph::script {
namespace {

YamlTree ParseOk(const std::string& text, const YamlLimits& limits = {}) {
  auto tree = ParseYaml(text, limits);
  EXPECT_TRUE(tree.has_value()) << (tree ? "" : tree.error().message);
  return tree ? std::move(*tree) : YamlTree{};
}

YamlError ParseBad(const std::string& text, const YamlLimits& limits = {}) {
  auto tree = ParseYaml(text, limits);
  EXPECT_FALSE(tree.has_value()) << text;
  return tree ? YamlError{} : tree.error();
}

bool Contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(ParseYaml, BuildsMapsSequencesScalarsAndNulls) {
  const YamlTree t = ParseOk("a: [1, 'two']\nb:\n");
  const NodeView root = t.At(t.root());
  ASSERT_EQ(root.kind, NodeKind::kMap);
  ASSERT_EQ(root.children.size(), 4u);  // a, [..], b, null
  EXPECT_EQ(t.At(root.children[0]).text, "a");
  const NodeView list = t.At(root.children[1]);
  ASSERT_EQ(list.kind, NodeKind::kSequence);
  ASSERT_EQ(list.children.size(), 2u);
  EXPECT_EQ(t.At(list.children[0]).style, ScalarStyle::kPlain);
  EXPECT_EQ(t.At(list.children[1]).style, ScalarStyle::kString);
  EXPECT_EQ(t.At(list.children[1]).text, "two");
  EXPECT_EQ(t.At(list.children[1]).location.line, 1);
  EXPECT_EQ(t.At(list.children[1]).location.column, 8);  // its opening quote
  const NodeView null_value = t.At(root.children[3]);
  EXPECT_EQ(null_value.kind, NodeKind::kNull);
  // An empty map value is located at its key (2:1), not at the next token.
  EXPECT_EQ(null_value.location.line, 2);
  EXPECT_EQ(null_value.location.column, 1);
  EXPECT_EQ(t.num_nodes(), 7u);
  // Expanded size: 7 nodes + the text of a, 1, two, b = 7 + 1 + 1 + 3 + 1.
  EXPECT_EQ(t.expanded_bytes(), 13u);
}

TEST(ParseYaml, EmptyDocumentHasNoRoot) {
  EXPECT_EQ(ParseOk("").root(), kNoNode);
  EXPECT_EQ(ParseOk("# only a comment\n").root(), kNoNode);
}

TEST(ParseYaml, EveryEscapeGivesUtf8) {
  const YamlTree t =
      ParseOk(R"(["\N", "\_", "\L", "\P", "\u00A0", "\x85", "\U0001F600", "\0", "\e", "a\_b\Nc"])");
  const NodeView list = t.At(t.root());
  ASSERT_EQ(list.children.size(), 10u);
  const std::string expected[] = {"\xC2\x85",          // U+0085 next line
                                  "\xC2\xA0",          // U+00A0 no-break space
                                  "\xE2\x80\xA8",      // U+2028 line separator
                                  "\xE2\x80\xA9",      // U+2029 paragraph separator
                                  "\xC2\xA0",          // U+00A0
                                  "\xC2\x85",          // U+0085
                                  "\xF0\x9F\x98\x80",  // U+1F600
                                  std::string(1, '\0'),
                                  "\x1B",
                                  "a\xC2\xA0"
                                  "b\xC2\x85"
                                  "c"};
  for (std::size_t i = 0; i < 10; ++i) {
    EXPECT_EQ(t.At(list.children[i]).text, expected[i]) << "item " << i;
  }
}

TEST(ParseYaml, RefusesSurrogatesAndCodesAboveTheLast) {
  const YamlError surrogate = ParseBad("a: \"\\uD800\"\n");
  EXPECT_TRUE(Contains(surrogate.message, "U+D800, a UTF-16 surrogate")) << surrogate.message;
  EXPECT_EQ(surrogate.location.line, 1);
  EXPECT_TRUE(
      Contains(ParseBad("a: \"\\U00110000\"").message, "U+110000, which is above U+10FFFF"));
}

TEST(ParseYaml, RefusesTextThatIsNotUtf8) {
  // Latin-1 "café": byte 0xE9 at line 2, column 9 ("  name: " is 8 bytes, "caf" 3 more: 12).
  const YamlError latin1 = ParseBad("ops:\n  name: caf\xE9\n");
  EXPECT_EQ(latin1.location.line, 2);
  EXPECT_EQ(latin1.location.column, 12);
  EXPECT_TRUE(Contains(latin1.message, "byte 0xE9 is not valid UTF-8; the script must be UTF-8"))
      << latin1.message;
  // Columns count bytes: "é" (2 bytes) then "\xFF" is column 3.
  EXPECT_EQ(ParseBad("\xC3\xA9\xFF").location.column, 3);
  const YamlError nul = ParseBad(std::string("a: b\0c\n", 7));
  EXPECT_EQ(nul.location.column, 5);
  EXPECT_TRUE(Contains(nul.message, "a raw NUL byte; the script must be UTF-8")) << nul.message;
  // A leading NUL is what makes yaml-cpp decode UTF-16: refused, and the message says why.
  const YamlError leading = ParseBad(std::string("\0a\0:\0 \0b", 9));
  EXPECT_EQ(leading.location.column, 1);
  EXPECT_TRUE(Contains(leading.message, "mark of UTF-16 or UTF-32 text")) << leading.message;
  EXPECT_TRUE(Contains(ParseBad(std::string("\xFF\xFE"
                                            "a\0",
                                            4))
                           .message,
                       "UTF-16 byte-order mark"));
  EXPECT_TRUE(Contains(ParseBad(std::string("\xFF\xFE\0\0", 4)).message, "UTF-32 byte-order mark"));
  // A UTF-8 byte-order mark is UTF-8.
  EXPECT_EQ(ParseOk("\xEF\xBB\xBF"
                    "a: b")
                .At(0)
                .kind,
            NodeKind::kMap);
}

TEST(ParseYaml, SharesAliasesAndCountsThemExpanded) {
  const YamlTree t = ParseOk("a: &a [x, yy]\nb: *a\n");
  const NodeView root = t.At(t.root());
  ASSERT_EQ(root.children.size(), 4u);
  EXPECT_EQ(root.children[1], root.children[3]);  // one node, two parents
  EXPECT_EQ(t.num_nodes(), 6u);
  // map 1 + "a" 2 + [x, yy] (1 + 2 + 3 = 6) + "b" 2 + the alias as a copy 6 = 17.
  EXPECT_EQ(t.expanded_bytes(), 17u);
}

TEST(ParseYaml, RefusesAnAliasBombAtTheAliasThatCrossesTheLimit) {
  YamlLimits limits;
  limits.max_expanded_bytes = 100;
  // &a: seq 1 + 4 items of 2 = 9. Root map 1, "a" 2, 9; "b" 2, seq 1, then each *a adds 9:
  // 15 + 9k <= 100 for k <= 9, so the 10th alias (column 4 + 4 * 9 = 40) crosses.
  std::string text = "a: &a [x, x, x, x]\nb: [";
  for (int k = 0; k < 12; ++k) text += "*a, ";
  text += "]\n";
  const YamlError e = ParseBad(text, limits);
  EXPECT_EQ(e.location.line, 2);
  EXPECT_EQ(e.location.column, 41);
  EXPECT_TRUE(Contains(e.message, "too large with its aliases expanded")) << e.message;
  // Nine aliases fit exactly.
  std::string nine = "a: &a [x, x, x, x]\nb: [*a, *a, *a, *a, *a, *a, *a, *a, *a]\n";
  EXPECT_EQ(ParseOk(nine, limits).expanded_bytes(), 96u);
}

TEST(ParseYaml, RefusesARecursiveAlias) {
  const YamlError e = ParseBad("ops: &a [1, *a]");
  EXPECT_EQ(e.location.column, 13);
  EXPECT_TRUE(Contains(e.message, "refers to a collection that contains it")) << e.message;
}

TEST(ParseYaml, RefusesDeepNestingManyNodesAndSecondDocuments) {
  EXPECT_TRUE(Contains(ParseBad(std::string(100000, '[')).message, "nested more than 64 levels"));
  YamlLimits limits;
  limits.max_nodes = 3;
  EXPECT_TRUE(Contains(ParseBad("[1, 2, 3]", limits).message, "more than 3 nodes"));
  EXPECT_EQ(ParseOk("[1, 2]", limits).num_nodes(), 3u);
  const YamlError second = ParseBad("a: 1\n---\nb: 2\n");
  EXPECT_EQ(second.location.line, 2);
  EXPECT_TRUE(Contains(second.message, "single YAML document"));
  EXPECT_TRUE(Contains(ParseBad("a: [1, 2\n").message, "invalid YAML"));
}

TEST(ParseCoreNumber, AcceptsTheCoreSchemaFloatsOnly) {
  double v = 0;
  EXPECT_TRUE(ParseCoreNumber("-.5e-3", &v));
  EXPECT_EQ(v, -0.0005);
  EXPECT_TRUE(ParseCoreNumber("1.", &v));
  EXPECT_EQ(v, 1.0);
  EXPECT_TRUE(ParseCoreNumber("-.Inf", &v));
  EXPECT_EQ(v, -INFINITY);
  EXPECT_TRUE(ParseCoreNumber(".NaN", &v));
  EXPECT_TRUE(std::isnan(v));
  EXPECT_TRUE(ParseCoreNumber("1e999", &v));
  EXPECT_EQ(v, INFINITY);
  for (const char* bad : {"", "+", ".", "e5", "1e", "0x10", "1_000", "+.nan", "inf", "1.2.3"}) {
    EXPECT_FALSE(ParseCoreNumber(bad, &v)) << bad;
  }
}

TEST(QuoteForMessage, CutsLongTextsAndGivesTheirLength) {
  EXPECT_EQ(QuoteForMessage("a\"b\\c\n"), "\"a\\\"b\\\\c\\x0a\"");
  EXPECT_EQ(QuoteForMessage(std::string(41, 'x')),
            "\"" + std::string(40, 'x') + "...\" (41 bytes)");
  // The cut falls before a character that would be split: 39 x + "é" (2 bytes) + y = 42 bytes.
  EXPECT_EQ(QuoteForMessage(std::string(39, 'x') + "\xC3\xA9" + "y"),
            "\"" + std::string(39, 'x') + "...\" (42 bytes)");
}

}  // namespace
}  // namespace semgraph::script
