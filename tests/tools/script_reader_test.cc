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

TEST(ReadScript, ReadsWrenchOpsRemovalsAndQueries) {
  const Script s = ReadOk(
      "ops:\n"
      "  - {op: wrench, on: C, by: D, point: e, coord: r, force: [1, 2, 3]}\n"
      "  - {op: remove, kind: wrench, on: C, by: D}\n"
      "  - {op: query, kind: moment, on: C, point: e, coord: r}\n");
  ASSERT_EQ(s.ops.size(), 3u);
  EXPECT_EQ(s.ops[0].kind, OpKind::kWrench);
  EXPECT_EQ(s.ops[0].names.body, "C");      // on
  EXPECT_EQ(s.ops[0].names.ref_body, "D");  // by
  EXPECT_EQ(s.ops[0].names.point, "e");
  EXPECT_EQ(s.ops[0].names.coord, "r");
  EXPECT_EQ(s.ops[0].force, (std::array<double, 3>{1.0, 2.0, 3.0}));
  EXPECT_EQ(s.ops[0].moment, (std::array<double, 3>{0.0, 0.0, 0.0}));  // missing: zero
  EXPECT_EQ(s.ops[1].kind, OpKind::kRemoveWrench);
  EXPECT_EQ(s.ops[2].query_kind, QueryKind::kMoment);
  EXPECT_EQ(s.ops[2].names.ref_body, "");  // no by: the net wrench
  // Fields of other ops, and missing ones, make the script malformed.
  EXPECT_NE(ReadBad("ops:\n  - {op: wrench, on: C, by: D, point: e, coord: r, linear: [1, 2, 3]}\n")
                .message.find("linear\" is not part of a 'wrench' op"),
            std::string::npos);
  EXPECT_NE(ReadBad("ops:\n  - {op: wrench, on: C, point: e, coord: r}\n")
                .message.find("a 'wrench' op needs 'by'"),
            std::string::npos);
  EXPECT_NE(ReadBad("ops:\n  - {op: query, kind: force, body: C, point: e, coord: r}\n")
                .message.find("body\" is not part of a 'force' query"),
            std::string::npos);
}

TEST(ReadScript, ReadsTheTimeFieldsOfWrenchOpsAndQueries) {
  const Script s = ReadOk(
      "ops:\n"
      "  - {op: wrench, on: C, by: D, point: e, coord: r, force: [1, 2, 3], stamp: 1.5}\n"
      "  - {op: query, kind: wrench, on: C, point: e, coord: r, at: 2, max_extrapolation: 0.5}\n"
      "  - {op: query, kind: force, on: C, point: e, coord: r, at: latest_common}\n"
      "  - {op: query, kind: moment, on: C, point: e, coord: r, not_before: 3}\n");
  ASSERT_EQ(s.ops.size(), 4u);
  EXPECT_EQ(s.ops[0].stamp, 1.5);
  EXPECT_EQ(s.ops[1].at, AtKind::kTime);
  EXPECT_EQ(s.ops[1].at_seconds, 2.0);
  EXPECT_EQ(s.ops[1].max_extrapolation, 0.5);
  EXPECT_EQ(s.ops[2].at, AtKind::kLatestCommon);
  EXPECT_EQ(s.ops[3].not_before, 3.0);
  // The twist queries' source and the pose queries' time travel are not wrench fields.
  EXPECT_NE(
      ReadBad("ops:\n  - {op: query, kind: wrench, on: C, point: e, coord: r, source: poses}\n")
          .message.find("source\" is not part of a 'wrench' query"),
      std::string::npos);
  EXPECT_NE(ReadBad("ops:\n  - {op: query, kind: force, on: C, point: e, coord: r, at: 1, "
                    "ref_at: 2, fixed: w}\n")
                .message.find("is not part of a 'force' query"),
            std::string::npos);
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

// ---------------------------------------------------------------- time (the Time section)

TEST(ReadScriptTime, ReadsTheDocumentsTimeOptions) {
  const Script d = ReadOk("ops: []\n");
  EXPECT_FALSE(d.time.given);
  EXPECT_EQ(d.time.window_ns, 10'000'000'000);
  EXPECT_FALSE(d.time.linear);
  EXPECT_FALSE(d.time.reject_duplicates);
  const Script s =
      ReadOk("time: {window: 2.5, interpolation: linear, duplicate_stamp: reject}\nops: []\n");
  EXPECT_TRUE(s.time.given);
  EXPECT_EQ(s.time.window_ns, 2'500'000'000);
  EXPECT_TRUE(s.time.linear);
  EXPECT_TRUE(s.time.reject_duplicates);
  const Script t = ReadOk("time: {interpolation: screw, duplicate_stamp: replace}\nops: []\n");
  EXPECT_FALSE(t.time.linear);
  EXPECT_FALSE(t.time.reject_duplicates);
  EXPECT_EQ(ReadOk("time: {}\nops: []\n").time.window_ns, 10'000'000'000);
}

TEST(ReadScriptTime, RefusesBadTimeOptionsWhereTheyAre) {
  struct Case {
    const char* text;
    int line, column;
    const char* words;
  } cases[] = {
      {"time: {window: 0}\nops: []\n", 1, 16, "'window' must be a finite positive time"},
      {"time: {window: -1}\nops: []\n", 1, 16, "'window' must be a finite positive time"},
      {"time: {window: 1e-10}\nops: []\n", 1, 16,
       "'window' must be a finite positive time"},  // 0 ns
      {"time: {window: .inf}\nops: []\n", 1, 16, "'window' must be a finite positive time"},
      {"time: {window: soon}\nops: []\n", 1, 16, "'window' must be a number"},
      {"time: {interpolation: cubic}\nops: []\n", 1, 23, "'interpolation' must be screw or linear"},
      {"time: {duplicate_stamp: keep}\nops: []\n", 1, 25,
       "'duplicate_stamp' must be replace or reject"},
      {"time: {horizon: 1}\nops: []\n", 1, 8, "unknown field \"horizon\" in 'time'"},
      {"time: 10\nops: []\n", 1, 7, "'time' must be a map"},
  };
  for (const Case& c : cases) {
    const ScriptError e = ReadBad(c.text);
    EXPECT_EQ(e.location.line, c.line) << c.text;
    EXPECT_EQ(e.location.column, c.column) << c.text << e.message;
    EXPECT_NE(e.message.find(c.words), std::string::npos) << c.text << e.message;
  }
}

TEST(ReadScriptTime, ReadsStampsAndQueryTimes) {
  const Script s = ReadOk(
      "ops:\n"
      "  - {op: pose, of: o, body: O, wrt: w, stamp: 1.5}\n"
      "  - {op: twist, point: o, ref_body: W, coord: o, stamp: -2}\n"
      "  - {op: joints, positions: {j: 1}, stamp: 3e-3}\n"
      "  - {op: query, kind: pose, of: o, wrt: w}\n"
      "  - {op: query, kind: pose, of: o, wrt: w, at: 1.25, max_extrapolation: 0.1, not_before: "
      "1}\n"
      "  - {op: query, kind: position, of: o, wrt: w, at: latest_common}\n"
      "  - {op: query, kind: orientation, of: o, wrt: w, at: 2, ref_at: 3, fixed: w}\n"
      "  - {op: query, kind: twist, point: o, ref_body: W, coord: o, source: poses, at: .nan}\n"
      "  - {op: query, kind: linear_velocity, point: o, ref_body: W, coord: o, source: twists}\n"
      "  - {op: query, kind: angular_velocity, body: O, ref_body: W, coord: o, not_before: 4}\n"
      "  - {op: query, kind: jacobian, point: o, ref_body: W, coord: o, at: latest_common, "
      "max_extrapolation: 0}\n");
  ASSERT_EQ(s.ops.size(), 11u);
  EXPECT_EQ(s.ops[10].at, AtKind::kLatestCommon);
  EXPECT_EQ(s.ops[10].max_extrapolation, 0.0);
  EXPECT_EQ(s.ops[0].stamp, 1.5);
  EXPECT_EQ(s.ops[1].stamp, -2.0);
  EXPECT_EQ(s.ops[2].stamp, 3e-3);
  EXPECT_FALSE(s.ops[3].stamp.has_value());
  EXPECT_EQ(s.ops[3].at, AtKind::kLatest);
  EXPECT_EQ(s.ops[4].at, AtKind::kTime);
  EXPECT_EQ(s.ops[4].at_seconds, 1.25);
  EXPECT_EQ(s.ops[4].max_extrapolation, 0.1);
  EXPECT_EQ(s.ops[4].not_before, 1.0);
  EXPECT_EQ(s.ops[5].at, AtKind::kLatestCommon);
  EXPECT_EQ(s.ops[6].ref_at, 3.0);
  EXPECT_EQ(s.ops[6].fixed, "w");
  EXPECT_TRUE(s.ops[7].source_poses);
  EXPECT_TRUE(std::isnan(s.ops[7].at_seconds));  // the graph's call: invalid_number
  EXPECT_FALSE(s.ops[8].source_poses);
  EXPECT_EQ(s.ops[9].not_before, 4.0);
}

TEST(ReadScriptTime, RefusesMisplacedAndMistypedTimeFieldsWhereTheyAre) {
  struct Case {
    const char* op;
    int column;
    const char* words;
  } cases[] = {
      // A time field on an op that does not take it is an unknown field of that op.
      {"{op: body, name: B, stamp: 1}", 25, "field \"stamp\" is not part of a 'body' op"},
      {"{op: frame, name: f, body: B, at: 1}", 35, "field \"at\" is not part of a 'frame' op"},
      {"{op: remove, kind: pose, of: a, wrt: b, stamp: 1}", 45, "is not part of a 'remove' op"},
      {"{op: pose, of: a, wrt: b, at: 1}", 31, "field \"at\" is not part of a 'pose' op"},
      {"{op: twist, point: a, ref_body: B, coord: a, source: poses}", 50,
       "not part of a 'twist' op"},
      {"{op: query, kind: twist, point: a, ref_body: B, coord: a, ref_at: 1, fixed: w}", 63,
       "field \"ref_at\" is not part of a 'twist' query"},
      {"{op: query, kind: angular_velocity, body: A, ref_body: B, coord: a, fixed: w}", 73,
       "field \"fixed\" is not part of an 'angular_velocity' query"},
      {"{op: query, kind: pose, of: a, wrt: b, source: poses}", 44,
       "field \"source\" is not part of a 'pose' query"},
      {"{op: query, kind: position, of: a, wrt: b, stamp: 1}", 48,
       "field \"stamp\" is not part of a 'position' query"},
      {"{op: query, kind: jacobian, point: a, ref_body: B, coord: a, at: 1, source: poses}", 73,
       "field \"source\" is not part of a 'jacobian' query"},
      {"{op: query, kind: jacobian, point: a, ref_body: B, coord: a, ref_at: 1, fixed: a, at: 1}",
       66, "field \"ref_at\" is not part of a 'jacobian' query"},
      {"{op: joint, name: j, type: fixed, parent: a, child: b, stamp: 1}", 60,
       "not part of a 'joint' op"},
      {"{op: urdf, file: r.urdf, stamp: 1}", 30, "not part of an 'urdf' op"},
      // Mistyped values.
      {"{op: pose, of: a, wrt: b, stamp: now}", 38, "'stamp' (seconds) must be a number"},
      {"{op: pose, of: a, wrt: b, stamp: [1]}", 38, "'stamp' (seconds) must be a number"},
      {"{op: query, kind: pose, of: a, wrt: b, at: soon}", 48,
       "'at' must be a time in seconds or latest_common"},
      {"{op: query, kind: pose, of: a, wrt: b, at: \"1\"}", 48,
       "'at' must be a time in seconds or latest_common"},
      {"{op: query, kind: pose, of: a, wrt: b, max_extrapolation: a}", 63,
       "'max_extrapolation' (seconds) must be"},
      {"{op: query, kind: pose, of: a, wrt: b, not_before: latest_common}", 56,
       "'not_before' (seconds) must be"},
      {"{op: query, kind: twist, point: a, ref_body: B, coord: a, source: edges}", 71,
       "'source' must be twists or poses"},
      // Time travel: both fields or neither, and `at` a number.
      {"{op: query, kind: pose, of: a, wrt: b, at: 1, ref_at: 2}", 59,
       "time travel needs both 'ref_at'"},
      {"{op: query, kind: pose, of: a, wrt: b, at: 1, fixed: w}", 58,
       "time travel needs both 'ref_at'"},
      {"{op: query, kind: pose, of: a, wrt: b, ref_at: 2, fixed: w}", 5,
       "needs 'at' as a time in seconds"},
      {"{op: query, kind: pose, of: a, wrt: b, at: latest_common, ref_at: 2, fixed: w}", 48,
       "needs 'at' as a time in seconds"},
      {"{op: query, kind: pose, of: a, wrt: b, at: 1, ref_at: 2, fixed: [w]}", 69,
       "'fixed' must be a name"},
      // repair takes no stamp.
      {"{op: pose, of: a, wrt: b, stamp: 1, repair: true}", 49,
       "'repair' does not take a stamped value"},
  };
  for (const Case& c : cases) {
    const std::string text = std::string("ops:\n  - ") + c.op + "\n";
    const ScriptError e = ReadBad(text);
    EXPECT_EQ(e.location.line, 2) << c.op;
    EXPECT_EQ(e.location.column, c.column) << c.op << " " << e.message;
    EXPECT_NE(e.message.find(c.words), std::string::npos) << c.op << " " << e.message;
  }
}

}  // namespace
}  // namespace semgraph::script
