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
