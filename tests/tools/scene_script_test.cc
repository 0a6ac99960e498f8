// Tests of the public scene-script API (semgraph/script/scene_script.h): RunScene gives the
// tool's lines and status, LoadScene leaves the scene in the caller's graph, malformed scripts
// apply nothing. The expected lines are written by hand from docs/scene-script.md.
#include "semgraph/script/scene_script.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <variant>

#include "semgraph/core/scene_graph_debug.h"

namespace semgraph::script {
namespace {

constexpr const char* kScript =
    "ops:\n"
    "  - {op: body, name: B}\n"
    "  - {op: body, name: B}\n"
    "  - {op: pose, of: c, body: C, wrt: b, ref_body: B, position: [1, 0, 0.5],"
    " rotation: {rpy: [0, 0, 1.5707963267948966]}}\n"
    "  - {op: query, kind: position, of: c, wrt: b}\n"
    "  - {op: query, kind: position, of: c, wrt: nowhere}\n";

TEST(RunScene, GivesTheToolsLinesAndStatus) {
  const SceneRun run = RunScene(kScript);
  EXPECT_EQ(run.status, kExitOpFailed);  // op 1 and op 4 fail
  EXPECT_TRUE(run.error.empty());
  ASSERT_EQ(run.ops.size(), 5u);
  EXPECT_EQ(run.ops[0].json, "{\"op\": 0, \"ok\": true, \"kind\": \"body\", \"line\": 2}");
  EXPECT_EQ(run.ops[0].kind, "body");
  EXPECT_EQ(run.ops[0].line, 2);
  EXPECT_TRUE(run.ops[0].ok);
  EXPECT_EQ(run.ops[1].index, 1u);
  EXPECT_FALSE(run.ops[1].ok);
  EXPECT_EQ(run.ops[1].error, "duplicate_body");
  EXPECT_EQ(run.ops[1].json.rfind("{\"op\": 1, \"ok\": false, \"error\": \"duplicate_body\"", 0),
            0u)
      << run.ops[1].json;
  // {c} is at [1, 0, 0.5] in [b]; the rotation does not move its origin.
  EXPECT_EQ(run.ops[3].json,
            "{\"op\": 3, \"ok\": true, \"position\": [1,0,0.5], \"kind\": \"query position\", "
            "\"line\": 5}");
  EXPECT_EQ(run.ops[3].kind, "query position");
  EXPECT_EQ(run.ops[4].line, 6);
  EXPECT_EQ(run.ops[4].error, "unknown_frame");
  EXPECT_TRUE(run.dot.empty());
}

TEST(RunScene, MalformedScriptAppliesNothingAndSaysWhere) {
  RunOptions options;
  options.display_name = "s.yaml";
  const SceneRun run = RunScene("ops:\n  - {op: body, name: B}\n  - {op: teleport}\n", options);
  EXPECT_EQ(run.status, kExitMalformed);
  EXPECT_TRUE(run.ops.empty());
  EXPECT_EQ(run.error.rfind("s.yaml:3:10: unknown op \"teleport\"", 0), 0u) << run.error;
}

TEST(RunScene, MalformedScriptGivesLineColumnAndMessageApart) {
  const SceneRun run = RunScene("ops:\n  - {op: body, name: B}\n  - {op: teleport}\n");
  EXPECT_EQ(run.status, kExitMalformed);
  EXPECT_EQ(run.error_line, 3);
  EXPECT_EQ(run.error_column, 10);
  EXPECT_EQ(run.error_message.rfind("unknown op \"teleport\"", 0), 0u) << run.error_message;
  EXPECT_EQ(run.error, "<script>:3:10: " + run.error_message);
  EXPECT_FALSE(run.out_of_memory);
  // No place at fault: 0, 0.
  const SceneRun missing = RunSceneFile("/nonexistent/scene.yaml");
  EXPECT_EQ(missing.error_line, 0);
  EXPECT_EQ(missing.error_column, 0);
  EXPECT_FALSE(missing.out_of_memory);
}

TEST(BuildScene, HandsOverTheGraphOfTheScriptsRepresentationAndTime) {
  const std::string text = std::string("representation: homogeneous\n") +
                           "time: {window: 2.5, interpolation: linear}\n" + kScript;
  BuiltScene built = BuildScene(text);
  EXPECT_EQ(built.run.status, kExitOpFailed);  // as RunScene: op 1 and op 4 fail
  ASSERT_EQ(built.run.ops.size(), 5u);
  EXPECT_EQ(built.run.ops[3].json, RunScene(text).ops[3].json);
  using G = core::SceneGraph<coord::HomogeneousBackend>;
  ASSERT_TRUE(std::holds_alternative<G>(built.graph));
  const G& graph = std::get<G>(built.graph);
  EXPECT_EQ(graph.time_options().window.nanoseconds(), 2'500'000'000);
  EXPECT_EQ(graph.time_options().interpolation, core::Interpolation::kLinear);
  EXPECT_EQ(graph.num_bodies(), 2u);
  // The pose op's value, by hand: {c} at [1, 0, 0.5] in [b], rotated Rz(90 deg).
  const auto X = graph.GetPose(core::PoseSpec::Of("c").RelativeTo("b"));
  ASSERT_TRUE(X.has_value());
  const auto p = coord::HomogeneousBackend::TranslationOf(X->value);
  EXPECT_EQ(p.x(), 1.0);
  EXPECT_EQ(p.z(), 0.5);
  EXPECT_NEAR(coord::HomogeneousBackend::RotationOf(X->value)(1, 0), 1.0, 1e-15);
  // The default representation; a malformed script builds no graph.
  EXPECT_TRUE(std::holds_alternative<core::SceneGraph<coord::QuaternionBackend>>(
      BuildScene(kScript).graph));
  const BuiltScene bad = BuildScene("ops: [{op: body}]");
  EXPECT_EQ(bad.run.status, kExitMalformed);
  EXPECT_TRUE(std::holds_alternative<std::monostate>(bad.graph));
}

TEST(RunScene, RendersDotAndStreamsResults) {
  RunOptions options;
  options.dot = true;
  std::vector<std::size_t> seen;
  options.on_op = [&](const OpResult& r) {
    seen.push_back(r.index);
    return r.index < 2;  // stop after op 2
  };
  const SceneRun run = RunScene(kScript, options);
  EXPECT_EQ(seen, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_TRUE(run.ops.empty());  // given to on_op instead
  // The graph after ops 0-2: bodies B and C, frames b and c, one pose edge b -> c.
  EXPECT_NE(run.dot.find("label=\"B\""), std::string::npos) << run.dot;
  EXPECT_NE(run.dot.find("label=\"C\""), std::string::npos) << run.dot;
}

TEST(LoadScene, LeavesTheSceneInTheCallersGraph) {
  core::SceneGraph<coord::HomogeneousBackend> graph;
  const SceneRun run = LoadScene(kScript, graph);
  EXPECT_EQ(run.status, kExitOpFailed);
  ASSERT_EQ(run.ops.size(), 5u);
  const auto X = graph.GetPose(core::PoseSpec::Of("c").RelativeTo("b"));
  ASSERT_TRUE(X.has_value());
  // Rz(90 deg): the x axis of [c] is the y axis of [b].
  const auto R = coord::HomogeneousBackend::RotationOf(X->value);
  EXPECT_NEAR(R(1, 0), 1.0, 1e-15);
  EXPECT_NEAR(R(0, 0), 0.0, 1e-15);
  // A malformed script leaves the graph as it was.
  const std::string before = Dump(graph);
  EXPECT_EQ(LoadScene("ops: [{op: body}]", graph).status, kExitMalformed);
  EXPECT_EQ(Dump(graph), before);
}

TEST(LoadSceneFile, ReadsFilesAndNamesUnreadableOnes) {
  const std::string path = ::testing::TempDir() + "scene_script_test.yaml";
  {
    std::ofstream out(path);
    out << kScript;
  }
  core::SceneGraph<coord::QuaternionBackend> graph;
  const SceneRun run = LoadSceneFile(path, graph);
  EXPECT_EQ(run.status, kExitOpFailed);
  EXPECT_EQ(run.ops.size(), 5u);
  EXPECT_EQ(graph.num_bodies(), 2u);
  std::remove(path.c_str());
  const SceneRun missing = RunSceneFile("/nonexistent/scene.yaml");
  EXPECT_EQ(missing.status, kExitMalformed);
  EXPECT_EQ(missing.error, "/nonexistent/scene.yaml: cannot read: No such file or directory");
}

}  // namespace
}  // namespace semgraph::script
