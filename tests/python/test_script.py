"""semgraph.run_script against the semgraph tool: the same JSON lines, the same success, the
same error text for malformed scripts, on the example and on every test script of the tool."""

import glob
import json
import os
import subprocess

import numpy as np
import pytest

import semgraph
from conftest import source_dir

CLI = os.environ.get("SEMGRAPH_CLI") or ""
SCRIPTS = sorted(glob.glob(os.path.join(source_dir(), "tests", "tools", "scripts", "*.yaml")))
EXAMPLE = os.path.join(source_dir(), "examples", "spray_painting.yaml")

needs_cli = pytest.mark.skipif(not os.path.exists(CLI), reason="the semgraph tool is not built")
pytestmark = pytest.mark.skipif(not semgraph._semgraph._has_tools,
                                reason="built without the tool library (SEMGRAPH_BUILD_TOOLS=OFF)")


@needs_cli
@pytest.mark.parametrize("path", [EXAMPLE] + SCRIPTS, ids=lambda p: os.path.basename(p))
def test_run_script_matches_the_tool(path):
    done = subprocess.run([CLI, "run", path], capture_output=True)
    if done.returncode == 2:  # malformed: the tool prints FILE:LINE:COLUMN: message
        with pytest.raises(semgraph.ScriptError) as info:
            semgraph.run_script(path)
        assert str(info.value) == done.stderr.decode("utf-8").rstrip("\n")
        return
    run = semgraph.run_script(path)
    assert run.json_lines == done.stdout.decode("utf-8").splitlines()
    assert run.ok == (done.returncode == 0)
    assert run.outcomes == [json.loads(line) for line in run.json_lines]


def test_example_script_outcomes_and_graph():
    run = semgraph.run_script(EXAMPLE)
    assert run.ok and all(o["ok"] for o in run.outcomes)
    assert [o["op"] for o in run.outcomes] == list(range(len(run.outcomes)))
    g = run.graph
    assert g.num_frames == 6 and g.num_pose_edges == 5 and g.num_twist_edges == 4
    # The graph is live: a query on it gives the script's pose query's numbers.
    queries = [o for o in run.outcomes if "position" in o and "quaternion" in o]
    assert queries
    assert "ScriptRun(ops=" in repr(run)


def test_run_script_text_applies_ops_and_reports_failures():
    text = """
representation: homogeneous
ops:
  - {op: pose, of: c, body: C, wrt: b, ref_body: B, position: [1, 2, 3], rotation: {rpy: [0, 0, 1.5707963267948966]}}
  - {op: query, kind: pose, of: b, wrt: c}
  - {op: pose, of: c, wrt: e, ref_body: E}
  - {op: query, kind: pose, of: c, wrt: b, coord: c}
"""
    run = semgraph.run_script_text(text)
    assert run.graph.representation == "homogeneous"
    assert not run.ok
    assert [o["ok"] for o in run.outcomes] == [True, True, False, False]
    assert run.outcomes[2]["error"] == "multiple_pose_parents"
    assert run.outcomes[3]["error"] == "representation_constraint"
    np.testing.assert_allclose(run.outcomes[1]["position"], [-2.0, 1.0, -3.0], atol=1e-12)
    X = run.graph.pose(of="b", wrt="c")
    np.testing.assert_allclose(X.position, run.outcomes[1]["position"], atol=0, rtol=0)


def test_malformed_script_error_gives_line_column_and_message_apart():
    text = "ops:\n  - {op: body, name: B}\n  - {op: teleport}\n"
    with pytest.raises(semgraph.ScriptError) as info:
        semgraph.run_script_text(text, file_name="s.yaml")
    # The op map of line 3 starts at column 5; its `op` value "teleport" at column 10.
    assert (info.value.line, info.value.column) == (3, 10)
    assert info.value.message.startswith('unknown op "teleport"')
    assert str(info.value) == "s.yaml:3:10: " + info.value.message


def test_run_script_text_keeps_the_scripts_time_options():
    run = semgraph.run_script_text("time: {window: 2.5, interpolation: linear}\nops: []\n")
    assert run.graph.representation == "quaternion"
    assert run.graph.time_options["window_ns"] == 2_500_000_000
    assert run.graph.time_options["interpolation"] == "linear"
    assert run.ok and run.outcomes == []
