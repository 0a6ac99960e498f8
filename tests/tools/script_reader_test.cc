// Unit tests of the scene-script reader (tools/semgraph/script_reader.h): what a well-formed
// script turns into, and where a malformed one is reported. End-to-end behaviour is tested by
// the scripts in scripts/ (run_script_test.py).
#include "semgraph/script_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace semgraph::script {
namespace {

Script ReadOk(const std::string& text) {
  auto script = ReadScript(text);
  EXPECT_TRUE(script.has_value()) << (script ? "" : script.error().message);
  return script ? *script : Script{};
}

ScriptError ReadBad(const std::string& text) {
  auto script = ReadScript(text);
  EXPECT_FALSE(script.has_value());
  return script ? ScriptError{} : script.error();
}

TEST(ReadScript, AppliesShorthandThenExplicitOverrides) {
  const Script s = ReadOk(
      "ops:\n"
      "  - {op: query, kind: pose, of: x, wrt: y, coord: r, ref_point: f, body: X}\n");
  ASSERT_EQ(s.ops.size(), 1u);
  const SemanticNames& n = s.ops[0].names;
  EXPECT_EQ(n.point, "x");
  EXPECT_EQ(n.orientation, "x");
  EXPECT_EQ(n.body, "X");
  EXPECT_EQ(n.ref_point, "f");
  EXPECT_EQ(n.ref_orientation, "y");
  EXPECT_EQ(n.ref_body, "");
  EXPECT_EQ(n.coord, "r");
  EXPECT_EQ(s.ops[0].kind, OpKind::kQuery);
  EXPECT_EQ(s.ops[0].query_kind, QueryKind::kPose);
  EXPECT_EQ(s.ops[0].location.line, 2);
  EXPECT_EQ(s.ops[0].location.column, 5);
}

TEST(ReadScript, ReadsValuesAndDefaults) {
  const Script s = ReadOk(
      "representation: homogeneous\n"
      "ops:\n"
      "  - {op: pose, of: a, wrt: b, position: [1, -2.5, 3e-1], rotation: {rpy: [.5, 0, -1]}}\n"
      "  - {op: pose, of: a, wrt: b, rotation: {matrix: [[1, 2, 3], [4, 5, 6], [7, 8, 9]]}}\n"
      "  - {op: pose, of: a, wrt: b}\n"
      "  - {op: twist, point: a, ref_body: B, coord: a, angular: [0, 0, +1]}\n");
  ASSERT_EQ(s.ops.size(), 4u);
  EXPECT_EQ(s.representation, Representation::kHomogeneous);
  EXPECT_EQ(s.ops[0].position, (std::array<double, 3>{1.0, -2.5, 0.3}));
  EXPECT_EQ(s.ops[0].rotation.form, RotationForm::kRpy);
  EXPECT_EQ(s.ops[0].rotation.rpy, (std::array<double, 3>{0.5, 0.0, -1.0}));
  EXPECT_EQ(s.ops[1].rotation.form, RotationForm::kMatrix);
  EXPECT_EQ(s.ops[1].rotation.matrix[1], (std::array<double, 3>{4.0, 5.0, 6.0}));  // rows
  EXPECT_EQ(s.ops[2].rotation.form, RotationForm::kIdentity);
  EXPECT_EQ(s.ops[2].position, (std::array<double, 3>{0.0, 0.0, 0.0}));
  EXPECT_EQ(s.ops[3].linear, (std::array<double, 3>{0.0, 0.0, 0.0}));
  EXPECT_EQ(s.ops[3].angular, (std::array<double, 3>{0.0, 0.0, 1.0}));
}

TEST(ReadScript, PassesNonFiniteNumbersToTheGraph) {
  // .nan / .inf are YAML numbers: the scene graph, not the reader, rejects them.
  const Script s = ReadOk("ops: [{op: pose, of: a, wrt: b, position: [.nan, .Inf, -.INF]}]\n");
  ASSERT_EQ(s.ops.size(), 1u);
  EXPECT_TRUE(std::isnan(s.ops[0].position[0]));
  EXPECT_EQ(s.ops[0].position[1], INFINITY);
  EXPECT_EQ(s.ops[0].position[2], -INFINITY);
  EXPECT_EQ(ReadOk("ops: [{op: pose, of: a, wrt: b, position: [1e999, 0, 0]}]").ops[0].position[0],
            INFINITY);
}

TEST(ReadScript, RejectsTextThatIsNotANumber) {
  for (const char* bad : {"abc", "\"1\"", "'1'", "0x10", "1_000", "1e", "1.2.3", "+.nan", "true",
                          "~", "--1", ".", "e5", "inf", "nan"}) {
    const ScriptError e =
        ReadBad(std::string("ops: [{op: pose, of: a, wrt: b, position: [") + bad + ", 0, 0]}]");
    EXPECT_EQ(e.location.line, 1) << bad;
    EXPECT_EQ(e.location.column, 44) << bad;
    EXPECT_NE(e.message.find("element 1 of 'position' must be a number"), std::string::npos)
        << bad << ": " << e.message;
  }
  for (const char* good : {"1", "-1", "+1", "1.", ".5", "-.5e-3", "1E+2", "!!float 2", "0"}) {
    EXPECT_TRUE(
        ReadScript(std::string("ops: [{op: pose, of: a, wrt: b, position: [") + good + ", 0, 0]}]")
            .has_value())
        << good;
  }
}

TEST(ReadScript, AcceptsAnyScalarAsAName) {
  // Validity of names (empty, control characters, length) is the graph's invalid_name.
  const Script s =
      ReadOk("ops: [{op: body, name: 12}, {op: body, name: \"\"}, {op: body, name: true}]");
  ASSERT_EQ(s.ops.size(), 3u);
  EXPECT_EQ(s.ops[0].name, "12");
  EXPECT_EQ(s.ops[1].name, "");
  EXPECT_EQ(s.ops[2].name, "true");
}

TEST(ReadScript, FrameWithoutBodyIsNotMalformed) {
  const Script s = ReadOk("ops: [{op: frame, name: f}]");
  ASSERT_EQ(s.ops.size(), 1u);
  EXPECT_EQ(s.ops[0].names.body, "");
}

TEST(ReadScript, AliasesAreSharedNotCopied) {
  const Script s = ReadOk(
      "ops:\n"
      "  - {op: pose, of: a, wrt: b, position: &p [1, 2, 3]}\n"
      "  - {op: pose, of: c, wrt: b, position: *p}\n");
  ASSERT_EQ(s.ops.size(), 2u);
  EXPECT_EQ(s.ops[1].position, (std::array<double, 3>{1.0, 2.0, 3.0}));
  // An anchor inside its own value would form a cycle: refused where the alias is (1:27).
  const ScriptError cycle = ReadBad("ops: [&m {op: body, name: *m}]");
  EXPECT_EQ(cycle.location.column, 27);
  EXPECT_NE(cycle.message.find("refers to a collection that contains it"), std::string::npos)
      << cycle.message;
}

TEST(ReadScript, ReportsTheFirstProblemWithItsLocation) {
  const ScriptError e = ReadBad(
      "ops:\n"
      "  - {op: body, name: B}\n"
      "  - {op: frame, name: f, body: B, colour: red}\n"
      "  - {op: nonsense}\n");
  EXPECT_EQ(e.location.line, 3);
  EXPECT_EQ(e.location.column, 35);
  EXPECT_EQ(FormatScriptError("s.yaml", e).rfind("s.yaml:3:35: unknown field \"colour\"", 0), 0u)
      << FormatScriptError("s.yaml", e);
}

TEST(ReadScript, RejectsDeepNestingWhileParsing) {
  const std::string deep = "ops: " + std::string(100000, '[') + std::string(100000, ']');
  const ScriptError e = ReadBad(deep);
  EXPECT_NE(e.message.find("nested more than 64 levels"), std::string::npos) << e.message;
  // 64 levels are fine as YAML (the script is then malformed for another reason).
  const std::string ok = "ops: " + std::string(63, '[') + std::string(63, ']');
  EXPECT_EQ(ReadBad(ok).message.find("nested"), std::string::npos);
}

TEST(ReadScript, RejectsOversizedScripts) {
  const std::string huge(kMaxScriptBytes + 1, ' ');
  const ScriptError e = ReadBad(huge);
  EXPECT_EQ(e.location.line, 1);
  EXPECT_NE(e.message.find("larger than 16 MiB"), std::string::npos);
}

TEST(ReadScript, EmptyOpsListIsAValidScript) {
  EXPECT_TRUE(ReadOk("ops: []").ops.empty());
  EXPECT_TRUE(ReadOk("# comment\nops: []\n...\n").ops.empty());
}

}  // namespace
}  // namespace semgraph::script
