"""The type stubs (semgraph/__init__.pyi) and docstrings cover the whole public API, so that IDEs
and help() show every argument: a stub that lags behind the module fails here."""

import ast
import inspect
import os

import semgraph


def stub_tree():
    path = os.path.join(os.path.dirname(semgraph.__file__), "__init__.pyi")
    with open(path) as f:
        return ast.parse(f.read())


def stub_members(tree):
    classes = {}
    functions = set()
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            classes[node.name] = ({n.name for n in node.body if isinstance(n, ast.FunctionDef)} |
                                  {n.target.id for n in node.body if isinstance(n, ast.AnnAssign)})
        elif isinstance(node, ast.FunctionDef):
            functions.add(node.name)
    return classes, functions


def test_every_public_name_has_a_stub():
    classes, functions = stub_members(stub_tree())
    for name in semgraph.__all__:
        assert name in classes or name in functions, name


def test_every_public_member_has_a_stub_and_a_docstring():
    classes, _ = stub_members(stub_tree())
    for name in semgraph.__all__:
        obj = getattr(semgraph, name)
        if not inspect.isclass(obj) or issubclass(obj, BaseException) or name == "ScriptRun":
            continue
        assert obj.__doc__, name
        public = {m for m in dir(obj) if not m.startswith("_")}
        assert public <= classes[name], (name, public - classes[name])


def test_scene_graph_methods_document_their_keywords():
    doc = semgraph.SceneGraph.add_pose.__doc__
    for word in ["of", "wrt", "expressed_in", "quaternion", "rotation_matrix", "rpy", "RejectedError"]:
        assert word in doc, word
    assert "QueryError" in semgraph.SceneGraph.pose.__doc__
    assert "expressed_in" in semgraph.SceneGraph.twist.__doc__


def pybind_keywords(doc):
    """The parameter names of a pybind11 signature line 'name(self: T, *, a: object = None) -> R'."""
    import re
    line = doc.splitlines()[0]
    inner = line[line.index("(") + 1:line.rindex(")")]
    return [m.group(1) for m in re.finditer(r"(?:^|, )(\w+): ", inner) if m.group(1) != "self"]


def stub_signatures(tree, class_name):
    for node in tree.body:
        if isinstance(node, ast.ClassDef) and node.name == class_name:
            out = {}
            for f in node.body:
                if isinstance(f, ast.FunctionDef) and not any(
                        isinstance(d, ast.Name) and d.id == "property" for d in f.decorator_list):
                    a = f.args
                    out[f.name] = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs if x.arg != "self"]
            return out
    raise KeyError(class_name)


def test_stub_signatures_match_the_module():
    """Every keyword of every method (the time, repair and joint keywords included) is in the
    stub, in the module's order, so that the stubs cannot lag behind the module."""
    tree = stub_tree()
    checked = 0
    for class_name in ["SceneGraph", "CompiledPose", "CompiledPosition", "CompiledOrientation", "CompiledTwist",
                       "CompiledPoseWithCovariance", "CompiledPositionWithCovariance",
                       "CompiledOrientationWithCovariance", "CompiledTwistWithCovariance",
                       "CompiledAcceleration", "CompiledJacobian", "RepairPolicy", "PoseBatch", "TwistBatch"]:
        cls = getattr(semgraph, class_name)
        for name, stub_args in stub_signatures(tree, class_name).items():
            if name.startswith("__") and name != "__init__":
                continue
            doc = getattr(cls, name).__doc__
            if not doc or "Overloaded function" in doc:
                continue
            assert pybind_keywords(doc) == stub_args, (class_name, name)
            checked += 1
    assert checked > 40


def test_time_kinematics_and_repair_keywords_are_documented():
    g = semgraph.SceneGraph
    for word in ["at", "max_extrapolation", "not_before", "latest_common", "ref_at", "fixed", "TimeReport",
                 "nanoseconds", "seconds", "extrapolation", "stale"]:
        assert word in g.pose.__doc__, word
    for word in ["source", "poses", "twists"]:
        assert word in g.twist.__doc__, word
    for word in ["stamp", "repair", "RepairPolicy", "RepairReport", "discrepancy"]:
        assert word in g.add_pose.__doc__, word
    for word in ["window", "interpolation", "screw", "linear", "duplicate_stamp", "sample_capacity"]:
        assert word in g.__init__.__doc__, word
    for word in ["revolute", "prismatic", "continuous", "fixed", "axis", "lower", "upper", "mimic", "multiplier"]:
        assert word in g.add_joint.__doc__, word
    for word in ["6 x n", "joints", "expressed_in"]:
        assert word in g.jacobian.__doc__, word
    assert "without the GIL" in g.load_urdf.__doc__


def ros_module():
    import pytest
    if not semgraph._semgraph._has_ros:
        pytest.skip("built without the ROS layer")
    import importlib
    ros = importlib.import_module("semgraph.ros")
    path = os.path.join(os.path.dirname(semgraph.__file__), "ros.pyi")
    with open(path) as f:
        return ros, ast.parse(f.read())


def test_ros_stubs_cover_the_submodule():
    ros, tree = ros_module()
    classes, functions = stub_members(tree)
    for name in ros.__all__:
        assert name in classes or name in functions, name
        obj = getattr(ros, name)
        if inspect.isclass(obj) and not issubclass(obj, BaseException):
            assert obj.__doc__, name
            public = {m for m in dir(obj) if not m.startswith("_")}
            assert public <= classes[name], (name, public - classes[name])
        elif not inspect.isclass(obj):
            assert obj.__doc__ and len(obj.__doc__) > 200, name


def test_ros_stub_signatures_match_the_module():
    ros, tree = ros_module()
    checked = 0
    for node in tree.body:
        if isinstance(node, ast.FunctionDef) and hasattr(ros, node.name):
            a = node.args
            stub_args = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs]
            assert pybind_keywords(getattr(ros, node.name).__doc__) == stub_args, node.name
            checked += 1
    for class_name in ["Listener", "Broadcaster"]:
        if not hasattr(ros, class_name):
            continue
        cls = getattr(ros, class_name)
        for name, stub_args in stub_signatures(tree, class_name).items():
            if name.startswith("__") and name != "__init__":
                continue
            assert pybind_keywords(getattr(cls, name).__doc__) == stub_args, (class_name, name)
            checked += 1
    assert checked >= 4
    for word in ["same_body", "own_body", "bodies", "urdf", "BagError", "byte offset", "GIL", "window"]:
        assert word in ros.load_bag.__doc__, word
    assert "streaming" in ros.read_bag.__doc__
