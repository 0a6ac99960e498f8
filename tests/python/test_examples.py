"""examples/spray_painting.py (the example of docs/python.md) runs and prints what it says."""

import os
import subprocess
import sys

from conftest import source_dir


def test_spray_painting_example_runs():
    path = os.path.join(source_dir(), "examples", "spray_painting.py")
    done = subprocess.run([sys.executable, path], capture_output=True, text=True, env=dict(os.environ))
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0].startswith("SceneGraph(representation='quaternion', frames=6")
    assert lines[1].startswith("Pose(PoseCoord({f1}|O1, {o2}|O2, [o2]), position=[")
    assert lines[-2].startswith("multiple_pose_parents - pose of {o1}|O1 wrt {e}|E rejected")
    assert lines[-1].startswith("frame_body_mismatch wrt - ")
