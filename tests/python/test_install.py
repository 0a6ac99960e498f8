"""The installed module: `cmake --install` of the build tree into a temporary prefix, then
`import semgraph` from a clean interpreter (this one, by path) that sees only that prefix."""

import os
import subprocess
import sys
import textwrap

import pytest

BUILD_DIR = os.environ.get("SEMGRAPH_BUILD_DIR")
INSTALL_DIR = os.environ.get("SEMGRAPH_PYTHON_INSTALL_DIR")
CMAKE = os.environ.get("SEMGRAPH_CMAKE", "cmake")

pytestmark = pytest.mark.skipif(not BUILD_DIR or not INSTALL_DIR,
                                reason="needs SEMGRAPH_BUILD_DIR and SEMGRAPH_PYTHON_INSTALL_DIR (set by ctest)")


def test_installed_module_imports_from_a_clean_interpreter(tmp_path):
    prefix = tmp_path / "prefix"
    env = dict(os.environ)
    if os.path.isabs(INSTALL_DIR):  # outside any prefix: stage it with DESTDIR instead
        env["DESTDIR"] = str(tmp_path / "stage")
        site = str(tmp_path / "stage") + INSTALL_DIR
        cmd = [CMAKE, "--install", BUILD_DIR, "--component", "python"]
    else:
        site = str(prefix / INSTALL_DIR)
        cmd = [CMAKE, "--install", BUILD_DIR, "--component", "python", "--prefix", str(prefix)]
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    files = sorted(os.listdir(os.path.join(site, "semgraph")))
    assert "__init__.py" in files and "__init__.pyi" in files and "py.typed" in files
    assert any(f.startswith("_semgraph") and f.endswith(".so") for f in files), files

    script = textwrap.dedent("""
        import sys
        import semgraph
        assert semgraph.__file__.startswith(sys.argv[1]), semgraph.__file__
        g = semgraph.SceneGraph()
        g.add_pose(of="c", body="C", wrt="b", ref_body="B", position=[1, 2, 3])
        print(list(g.pose(of="b", wrt="c").position), semgraph.__version__)
    """)
    clean = {"PATH": os.environ.get("PATH", ""), "PYTHONPATH": site}
    # -s: no user site-packages; run from an empty directory so the source tree is not on sys.path.
    done = subprocess.run([sys.executable, "-s", "-c", script, site], env=clean, cwd=tmp_path,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.split()[:3] == ["[-1.0,", "-2.0,", "-3.0]"]
