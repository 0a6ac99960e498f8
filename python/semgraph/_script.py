"""semgraph.run_script: scene scripts (the semgraph tool's YAML) from Python."""

import json
import os
from typing import List, Union

from . import _semgraph
from ._errors import ScriptError


class ScriptRun:
    """The outcome of a scene script.

    outcomes:   one dict per op, exactly the JSON objects `semgraph run` prints
                ({"op": i, "ok": True, "position": [...], "quaternion": [...]}, ...)
    json_lines: the same as the tool's output lines (str, without newline)
    ok:         True when every op succeeded (the tool's exit status 0)
    graph:      the SceneGraph the ops were applied to, for further queries
    """

    def __init__(self, graph: "_semgraph.SceneGraph", json_lines: List[str], ok: bool) -> None:
        self.graph = graph
        self.json_lines = json_lines
        self.outcomes = [json.loads(line) for line in json_lines]
        self.ok = ok

    def __repr__(self) -> str:
        failed = sum(1 for o in self.outcomes if not o["ok"])
        return f"ScriptRun(ops={len(self.outcomes)}, failed={failed}, graph={self.graph!r})"


def run_script_text(text: Union[str, bytes], file_name: str = "<string>", base_dir: str = "") -> ScriptRun:
    """Applies a scene script given as text; see run_script. `base_dir` is the folder a
    relative `urdf` file is read from (empty: the working folder)."""
    if isinstance(text, str):
        text = text.encode("utf-8")
    elif not isinstance(text, (bytes, bytearray)):
        raise TypeError(f"run_script_text(): text must be a str or bytes, not {type(text).__name__}")
    if not isinstance(file_name, str):
        raise TypeError(f"run_script_text(): file_name must be a str, not {type(file_name).__name__}")
    if not isinstance(base_dir, str):
        raise TypeError(f"run_script_text(): base_dir must be a str, not {type(base_dir).__name__}")
    result = _semgraph._run_script_text(bytes(text), file_name, base_dir)
    if not result[0]:
        _, line, column, message, formatted = result
        raise ScriptError(formatted, line, column, message)
    _, graph, lines, ok = result
    return ScriptRun(graph, lines, ok)


def run_script(path: Union[str, "os.PathLike[str]"]) -> ScriptRun:
    """Applies the scene script at `path` (YAML, the format of the semgraph tool) to a new
    SceneGraph, op by op, as `semgraph run FILE` does; returns a ScriptRun whose outcomes are the
    tool's JSON lines. A rejected op or failed query does not stop the run (see ScriptRun.ok).
    Raises ScriptError for a malformed script (nothing applied) and OSError when the file cannot
    be read. Runs without the GIL.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"run_script(): path must be a str or os.PathLike, not {type(path).__name__}")
    with open(path, "rb") as f:
        text = f.read()
    # A relative `urdf` file is read from the script's folder, as the tool does.
    return run_script_text(text, os.fspath(path), os.path.dirname(os.fspath(path)))
