// Unit tests of the JSON rendering of tools/semgraph/script_runner.h and of dot_writer.h. The
// outcomes of ops are tested end to end by the scripts in scripts/.
#include "semgraph/script_runner.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "semgraph/dot_writer.h"

namespace semgraph::script {
namespace {

TEST(JsonString, EscapesQuotesBackslashesAndControlCharacters) {
  EXPECT_EQ(JsonString("plain"), "\"plain\"");
  EXPECT_EQ(JsonString("a\"b\\c"), "\"a\\\"b\\\\c\"");
  EXPECT_EQ(JsonString("\n\t\r\b\f"), "\"\\n\\t\\r\\b\\f\"");
  EXPECT_EQ(JsonString(std::string("\x01\x1f\x7f", 3)), "\"\\u0001\\u001f\\u007f\"");
  EXPECT_EQ(JsonString(std::string("a\0b", 3)), "\"a\\u0000b\"");
}

TEST(JsonString, PassesValidUtf8AndReplacesInvalidBytes) {
  EXPECT_EQ(JsonString("K\xc3\xb6rper \xe2\x86\x92 \xf0\x9f\x98\x80"),
            "\"K\xc3\xb6rper \xe2\x86\x92 \xf0\x9f\x98\x80\"");
  EXPECT_EQ(JsonString("\xff"), "\"\\ufffd\"");
  EXPECT_EQ(JsonString("\xc3"), "\"\\ufffd\"");                        // truncated
  EXPECT_EQ(JsonString("\xc0\xaf"), "\"\\ufffd\\ufffd\"");             // overlong '/'
  EXPECT_EQ(JsonString("\xed\xa0\x80"), "\"\\ufffd\\ufffd\\ufffd\"");  // surrogate U+D800
  EXPECT_EQ(JsonString("\xf4\x90\x80\x80"), "\"\\ufffd\\ufffd\\ufffd\\ufffd\"");  // > U+10FFFF
  EXPECT_EQ(JsonString("\x80x"), "\"\\ufffdx\"");  // stray continuation
}

TEST(JsonString, EscapesC1ControlsAndUnicodeLineSeparators) {
  // U+0085 (next line), U+2028, U+2029 end lines for some readers; C1 controls are controls.
  EXPECT_EQ(JsonString("a\xC2\x85"
                       "b"),
            "\"a\\u0085b\"");
  EXPECT_EQ(JsonString("\xC2\x80\xC2\x9F"), "\"\\u0080\\u009f\"");
  EXPECT_EQ(JsonString("\xE2\x80\xA8\xE2\x80\xA9"), "\"\\u2028\\u2029\"");
  // Their neighbours stay as they are: U+00A0, U+2027, U+202A.
  EXPECT_EQ(JsonString("\xC2\xA0\xE2\x80\xA7\xE2\x80\xAA"), "\"\xC2\xA0\xE2\x80\xA7\xE2\x80\xAA\"");
}

TEST(JsonNumber, RoundTripsWithSeventeenDigits) {
  EXPECT_EQ(JsonNumber(0.0), "0");
  EXPECT_EQ(JsonNumber(-0.0), "0");
  EXPECT_EQ(JsonNumber(1.0), "1");
  EXPECT_EQ(JsonNumber(-2.5), "-2.5");
  EXPECT_EQ(JsonNumber(0.1), "0.10000000000000001");
  EXPECT_EQ(JsonNumber(1e-300), "1e-300");  // %g drops trailing zeros
  for (const double x : {0.1, 1.0 / 3.0, 6.02214076e23, -1e-17, 2.2250738585072014e-308}) {
    EXPECT_EQ(std::stod(JsonNumber(x)), x);
  }
}

TEST(ApplyOp, RendersEachOutcomeAsOneJsonLine) {
  core::SceneGraph<coord::QuaternionBackend> graph;
  ScriptOp body;
  body.kind = OpKind::kBody;
  body.name = "B";
  body.location = {7, 3};
  // The op's kind and its script line close every line.
  EXPECT_EQ(ApplyOp(graph, body, 0).json,
            "{\"op\": 0, \"ok\": true, \"kind\": \"body\", \"line\": 7}");
  const OpOutcome again = ApplyOp(graph, body, 1);
  EXPECT_FALSE(again.ok);
  EXPECT_EQ(again.json.rfind(
                "{\"op\": 1, \"ok\": false, \"error\": \"duplicate_body\", \"message\": \"", 0),
            0u)
      << again.json;

  // A 180-degree turn about z has w = 0: the sign is fixed by the first nonzero component.
  ScriptOp pose;
  pose.kind = OpKind::kPose;
  pose.names.point = pose.names.orientation = "a";
  pose.names.body = "A";
  pose.names.ref_point = pose.names.ref_orientation = pose.names.coord = "w";
  pose.names.ref_body = "W";
  pose.rotation.form = RotationForm::kQuaternion;
  pose.rotation.quaternion = {0.0, 0.0, 0.0, -1.0};
  ASSERT_TRUE(ApplyOp(graph, pose, 2).ok);
  ScriptOp query = pose;
  query.kind = OpKind::kQuery;
  query.query_kind = QueryKind::kOrientation;
  query.location = {12, 5};
  EXPECT_EQ(ApplyOp(graph, query, 3).json,
            "{\"op\": 3, \"ok\": true, \"quaternion\": [0,0,0,1], \"kind\": \"query orientation\", "
            "\"line\": 12}");
  ScriptOp remove;
  remove.kind = OpKind::kRemoveTwist;
  remove.names.point = "a";
  remove.names.ref_body = "W";
  remove.location = {13, 5};
  const OpOutcome no_edge = ApplyOp(graph, remove, 4);
  EXPECT_EQ(no_edge.error, "no_such_edge");
  EXPECT_TRUE(no_edge.json.ends_with("\", \"kind\": \"remove twist\", \"line\": 13}"))
      << no_edge.json;
}

// Time keys: those that apply, after the value keys and before kind/line; seconds as the nearest
// double of the nanoseconds (17 digits). A graph of yours keeps its own time options.
TEST(ApplyOp, RendersTheTimeKeysThatApply) {
  core::TimeOptions options;
  options.interpolation = core::Interpolation::kLinear;
  auto graph = *core::SceneGraph<coord::QuaternionBackend>::Create(options);
  const auto script = ReadScript(
      "ops:\n"
      "  - {op: pose, of: o, body: O, wrt: w, ref_body: W, stamp: 0.1}\n"
      "  - {op: pose, of: o, wrt: w, position: [1, 0, 0], stamp: 0.3}\n"
      "  - {op: query, kind: position, of: o, wrt: w, at: 0.2}\n"
      "  - {op: query, kind: position, of: o, wrt: w}\n"
      "  - {op: query, kind: position, of: w, wrt: w, at: latest_common}\n"
      "  - {op: query, kind: position, of: w, wrt: w, at: 5}\n"
      "  - {op: query, kind: position, of: o, wrt: w, at: 0.2, ref_at: 0.3, fixed: w}\n"
      "  - {op: pose, of: o, wrt: w, position: [2, 0, 0], stamp: 9.3e9}\n");
  ASSERT_TRUE(script.has_value()) << script.error().message;
  std::vector<std::string> out;
  for (std::size_t i = 0; i < script->ops.size(); ++i)
    out.push_back(ApplyOp(graph, script->ops[i], i).json);
  EXPECT_EQ(out[2],
            "{\"op\": 2, \"ok\": true, \"position\": [0.5,0,0], \"time\": 0.20000000000000001, "
            "\"oldest\": "
            "0.10000000000000001, \"newest\": 0.29999999999999999, \"kind\": \"query position\", "
            "\"line\": 4}");
  EXPECT_EQ(out[3],
            "{\"op\": 3, \"ok\": true, \"position\": [1,0,0], \"oldest\": 0.29999999999999999, "
            "\"newest\": "
            "0.29999999999999999, \"kind\": \"query position\", \"line\": 5}");
  // No stamped edge used: latest common reports no time; `at` reports the time asked.
  EXPECT_EQ(out[4],
            "{\"op\": 4, \"ok\": true, \"position\": [0,0,0], \"kind\": \"query position\", "
            "\"line\": 6}");
  EXPECT_EQ(
      out[5],
      "{\"op\": 5, \"ok\": true, \"position\": [0,0,0], \"time\": 5, \"kind\": \"query position\", "
      "\"line\": 7}");
  EXPECT_EQ(out[6],
            "{\"op\": 6, \"ok\": true, \"position\": [0.5,0,0], \"time\": 0.20000000000000001, "
            "\"ref_time\": "
            "0.29999999999999999, \"oldest\": 0.10000000000000001, \"newest\": "
            "0.29999999999999999, \"kind\": "
            "\"query position\", \"line\": 8}");
  EXPECT_NE(out[7].find("\"error\": \"invalid_number\""), std::string::npos) << out[7];
  EXPECT_NE(out[7].find("'stamp' 9300000000 s is not a finite time"), std::string::npos) << out[7];
  EXPECT_EQ(graph.time_options().interpolation, core::Interpolation::kLinear);
}

TEST(WriteDot, QuotesNamesAndDrawsPoseEdgesSolidAndTwistEdgesDashed) {
  core::SceneGraph<coord::QuaternionBackend> graph;
  ASSERT_TRUE(graph.AddPose(core::PoseSpec::Of("f\"1", "Body \\ \"1\"").RelativeTo("w", "W"),
                            Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero()));
  ASSERT_TRUE(graph.AddTwist(core::TwistSpec::Of("f\"1").RelativeTo("W").ExpressedIn("w"),
                             Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  const std::string dot = WriteDot(graph);
  EXPECT_NE(dot.find("label=\"Body \\\\ \\\"1\\\"\";"), std::string::npos) << dot;
  EXPECT_NE(dot.find("[label=\"{f\\\"1}\"]"), std::string::npos) << dot;
  EXPECT_NE(dot.find("subgraph cluster_0 {"), std::string::npos) << dot;
  EXPECT_NE(dot.find("subgraph cluster_1 {"), std::string::npos) << dot;
  // {w} (frame 1) -> {f"1} (frame 0) solid; W (body 1) -> {f"1} dashed.
  EXPECT_NE(dot.find("  frame_1 -> frame_0;\n"), std::string::npos) << dot;
  EXPECT_NE(dot.find("  body_1 -> frame_0 [style=dashed];\n"), std::string::npos) << dot;
}

TEST(WriteDot, LabelsJointEdgesWithTypeAndName) {
  core::SceneGraph<coord::QuaternionBackend> graph;
  core::JointSpec j;
  j.name = "elbow";
  j.type = core::JointType::kRevolute;
  j.parent = "upper";
  j.parent_body = "Upper";
  j.child = "fore";
  j.child_body = "Fore";
  j.lower = -1;
  j.upper = 1;
  ASSERT_TRUE(graph.AddJoint(j));
  ASSERT_TRUE(graph.AddPose(core::PoseSpec::Of("cam", "Cam").RelativeTo("fore"),
                            Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero()));
  const std::string dot = WriteDot(graph);
  // {upper} is frame 1, {fore} frame 0; body Upper is body 0.
  EXPECT_NE(dot.find("  frame_1 -> frame_0 [label=\"revolute elbow\", penwidth=2];\n"),
            std::string::npos)
      << dot;
  EXPECT_NE(dot.find("  body_0 -> frame_0 [style=dashed, label=\"revolute elbow\", penwidth=2];\n"),
            std::string::npos)
      << dot;
  EXPECT_NE(dot.find("  frame_0 -> frame_2;\n"), std::string::npos) << dot;  // an ordinary edge
}

}  // namespace
}  // namespace semgraph::script
