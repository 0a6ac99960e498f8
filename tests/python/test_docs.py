"""The Python examples of docs/python.md run as written (each block on its own, from the source
folder, so that its relative paths resolve), and the values their comments promise hold."""

import os
import re

import pytest

from conftest import source_dir


def blocks():
    with open(os.path.join(source_dir(), "docs", "python.md")) as f:
        text = f.read()
    return re.findall(r"```python\n(.*?)```", text, re.S)


def run(code):
    env = {"__name__": "docs_example"}
    cwd = os.getcwd()
    os.chdir(source_dir())
    try:
        exec(compile(code, "docs/python.md", "exec"), env)
    finally:
        os.chdir(cwd)
    return env


def test_docs_have_the_feature_examples():
    heads = [b.split("\n", 3)[:3] for b in blocks()]
    assert len(blocks()) >= 4, heads


@pytest.mark.parametrize("index", range(4))
def test_docs_example_runs(index):
    import semgraph
    if "load_urdf" in blocks()[index] and not semgraph._semgraph._has_models:
        pytest.skip("built without the models layer")
    run(blocks()[index])


def test_docs_time_example_values():
    env = run(next(b for b in blocks() if "sample_capacity=256" in b))
    X, g = env["X"], env["g"]
    assert X.time.time == 0.45 and (X.time.oldest, X.time.newest) == (0.4, 0.5)
    assert g.pose(of="obj", wrt="cam", at="latest").time.newest == 1.1  # after the example's set_pose
    assert env["q"].evaluate(at=0.45).time.time_ns == 450_000_000
    assert g.pose(of="obj", wrt="cam", at="latest_common").time.time == 1.1
    w = g.twist(point="obj", ref_body="World", expressed_in="obj", at=0.45, source="poses").angular
    assert abs(w[2] - 0.8) < 1e-9 and abs(w[0]) < 1e-9


def test_docs_repair_example_values():
    env = run(next(b for b in blocks() if "Fig. 4" in b))
    assert env["r"].applied == "inverted"
    assert env["r"].change == "added the inverse: pose of {f} wrt {c2}"
    g, X, semgraph = env["g"], env["X"], env["semgraph"]
    with pytest.raises(semgraph.RejectedError) as e:  # the example's refusal, again
        g.add_pose(of="f", wrt="d", position=X.position + [0.003, 0, 0], quaternion=X.quaternion,
                   repair=semgraph.RepairPolicy(position_tolerance=1e-3, angle_tolerance=1e-3))
    assert e.value.code == "multiple_pose_parents"
    assert e.value.discrepancy[0] == pytest.approx(0.003, abs=1e-12)
    assert e.value.discrepancy[1] < 1e-12


@pytest.mark.skipif(not __import__("semgraph")._semgraph._has_models, reason="built without the models layer")
def test_docs_kinematics_example_values():
    env = run(next(b for b in blocks() if "planar arm" in b))
    assert env["J"].joints == ["j1", "j2"] and env["J"].matrix.shape == (6, 2)
    with pytest.raises(env["semgraph"].RejectedError) as e:
        env["arm"].set_joints({"r/elbow_joint": 4.0})
    assert e.value.code == "joint_limit"
    assert env["jac"].evaluate().joints == env["robot"].joints
    assert env["robot"].root == "r/base_link"
