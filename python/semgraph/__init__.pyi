# Type stubs of semgraph (the public API; the implementation is the C++ extension _semgraph).
# Names are keyword-only roles; numbers are lists, tuples or numpy arrays, results numpy float64.
import os
from typing import List, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
Vector = np.ndarray  # shape (3,), float64
Name = Optional[str]

class Error(Exception):
    """Base class of semgraph's errors."""

class RejectedError(Error):
    """A build-time operation was refused; nothing changed."""
    code: str  # snake_case error code, e.g. "multiple_pose_parents"
    message: str
    def __init__(self, code: str, message: str) -> None: ...

class QueryError(Error):
    """A query has no answer."""
    code: str  # e.g. "unknown_frame", "no_pose_path", "query_invalidated"
    message: str
    field: Optional[str]  # role at fault: "point", "ref_body", "coordinate_frame", ...
    argument: Optional[str]  # keyword that supplied it: "of", "wrt", "expressed_in", ...
    def __init__(self, code: str, message: str, field: Optional[str] = ..., argument: Optional[str] = ...) -> None: ...

class ScriptError(Error, ValueError):
    """A malformed scene script; str() is "FILE:LINE:COLUMN: message"."""
    line: int
    column: int
    message: str
    def __init__(self, text: str, line: int, column: int, message: str) -> None: ...

class Pose:
    """PoseCoord((e,[a])|C, (f,[b])|D, [r])."""
    @property
    def position(self) -> np.ndarray:
        """(3,): position of the point e relative to the reference point f, in [r]."""
    @property
    def quaternion(self) -> np.ndarray:
        """(4,) (w, x, y, z), w >= 0: orientation of [a] relative to [b] as an operator in [r]."""
    @property
    def rotation_matrix(self) -> np.ndarray:
        """(3, 3): the same rotation as a matrix."""
    @property
    def matrix(self) -> np.ndarray:
        """(4, 4): the homogeneous matrix [R p; 0 0 0 1]."""
    @property
    def semantics(self) -> str:
        """The relation in the paper's notation, e.g. 'PoseCoord({f1}|O1, {o2}|O2, [o2])'."""

class Position:
    """PositionCoord(e|C, f|D, [r])."""
    @property
    def position(self) -> np.ndarray: ...
    @property
    def semantics(self) -> str: ...

class Orientation:
    """OrientationCoord([a]|C, [b]|D, [r])."""
    @property
    def quaternion(self) -> np.ndarray: ...
    @property
    def rotation_matrix(self) -> np.ndarray: ...
    @property
    def semantics(self) -> str: ...

class Twist:
    """TwistCoord(e|C, D, [r])."""
    @property
    def linear(self) -> np.ndarray:
        """(3,): velocity of the point of body C at e relative to body D, in [r]."""
    @property
    def angular(self) -> np.ndarray:
        """(3,): angular velocity of C relative to D, in [r]."""
    @property
    def semantics(self) -> str: ...

class LinearVelocity:
    """LinearVelocityCoord(e|C, D, [r])."""
    @property
    def linear(self) -> np.ndarray: ...
    @property
    def semantics(self) -> str: ...

class AngularVelocity:
    """AngularVelocityCoord(C, D, [r])."""
    @property
    def angular(self) -> np.ndarray: ...
    @property
    def semantics(self) -> str: ...

class CompiledPose:
    """A compiled pose query; keeps its graph alive."""
    def evaluate(self) -> Pose:
        """The pose now. QueryError('query_invalidated') once an edge it reads was removed."""
    @property
    def is_valid(self) -> bool: ...
    @property
    def num_pose_edges(self) -> int: ...

class CompiledPosition:
    def evaluate(self) -> Position: ...
    @property
    def is_valid(self) -> bool: ...
    @property
    def num_pose_edges(self) -> int: ...

class CompiledOrientation:
    def evaluate(self) -> Orientation: ...
    @property
    def is_valid(self) -> bool: ...
    @property
    def num_pose_edges(self) -> int: ...

class CompiledTwist:
    """A compiled twist, linear velocity or angular velocity query."""
    def evaluate(self) -> Union[Twist, LinearVelocity, AngularVelocity]: ...
    @property
    def is_valid(self) -> bool: ...
    @property
    def num_pose_edges(self) -> int: ...
    @property
    def num_twist_edges(self) -> int: ...

class PoseHandle:
    """The resolved pose edge {wrt} -> {of}; keeps its graph alive."""
    @property
    def of(self) -> str: ...
    @property
    def wrt(self) -> str: ...
    @property
    def is_valid(self) -> bool: ...

class TwistHandle:
    """The resolved twist edge ref_body -> {point}; keeps its graph alive."""
    @property
    def point(self) -> str: ...
    @property
    def ref_body(self) -> str: ...
    @property
    def is_valid(self) -> bool: ...

class PoseBatch:
    def set(self, values: ArrayLike) -> None:
        """values: (N, 7) rows [x, y, z, qw, qx, qy, qz] or (N, 4, 4); checked first, atomic,
        without the GIL. RejectedError naming the row."""
    def __len__(self) -> int: ...

class TwistBatch:
    def set(self, values: ArrayLike) -> None:
        """values: (N, 6) rows [vx, vy, vz, wx, wy, wz] in [head]; checked first, atomic."""
    def __len__(self) -> int: ...

class SceneGraph:
    """A constraint-checking scene graph of poses and twists of rigid bodies.

    representation: "quaternion" (default) or "homogeneous" (poses between frame origins,
    expressed in the reference orientation frame only).
    """
    def __init__(self, representation: str = "quaternion") -> None: ...
    @property
    def representation(self) -> str: ...
    @property
    def num_frames(self) -> int: ...
    @property
    def num_bodies(self) -> int: ...
    @property
    def num_pose_edges(self) -> int: ...
    @property
    def num_twist_edges(self) -> int: ...
    @property
    def frames(self) -> List[str]: ...
    @property
    def bodies(self) -> List[str]: ...
    def body_of(self, frame: str) -> Optional[str]: ...

    def add_body(self, name: str) -> None:
        """RejectedError: invalid_name, duplicate_body."""
    def add_frame(self, name: str, body: str) -> None:
        """RejectedError: invalid_name, frame_without_body, duplicate_frame, unknown_body."""
    def add_pose(self, *, of: Name = None, body: Name = None, wrt: Name = None, ref_body: Name = None,
                 point: Name = None, orientation: Name = None, ref_point: Name = None,
                 ref_orientation: Name = None, expressed_in: Name = None,
                 position: Optional[ArrayLike] = None, rotation: Optional[ArrayLike] = None,
                 quaternion: Optional[ArrayLike] = None, rotation_matrix: Optional[ArrayLike] = None,
                 rpy: Optional[ArrayLike] = None) -> None:
        """Adds (or updates) the pose of `of` relative to `wrt` as the edge {wrt} -> {of}.

        position: of's origin relative to wrt's origin in [expressed_in or wrt], default 0.
        At most one rotation form: rotation (4 numbers = quaternion, 3x3 = matrix),
        quaternion (w, x, y, z), rotation_matrix (3x3), rpy (roll, pitch, yaw; R = Rz Ry Rx).
        RejectedError on any violated rule; the graph is then unchanged."""
    def add_twist(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                  expressed_in: Name = None, linear: Optional[ArrayLike] = None,
                  angular: Optional[ArrayLike] = None) -> None:
        """Adds (or updates) the twist of `body` (default: point's body) relative to `ref_body`
        as the edge ref_body -> {point}; linear/angular in [expressed_in]."""
    def remove_pose(self, *, of: str, wrt: str) -> None: ...
    def remove_twist(self, *, point: str, ref_body: str) -> None: ...

    def pose(self, *, of: Name = None, body: Name = None, wrt: Name = None, ref_body: Name = None,
             point: Name = None, orientation: Name = None, ref_point: Name = None,
             ref_orientation: Name = None, expressed_in: Name = None) -> Pose:
        """The pose of `of` relative to `wrt`, in `expressed_in` (default [wrt]). QueryError."""
    def position(self, *, of: Name = None, body: Name = None, wrt: Name = None, ref_body: Name = None,
                 point: Name = None, orientation: Name = None, ref_point: Name = None,
                 ref_orientation: Name = None, expressed_in: Name = None) -> Position: ...
    def orientation(self, *, of: Name = None, body: Name = None, wrt: Name = None, ref_body: Name = None,
                    point: Name = None, orientation: Name = None, ref_point: Name = None,
                    ref_orientation: Name = None, expressed_in: Name = None) -> Orientation: ...
    def twist(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
              expressed_in: Name = None) -> Twist: ...
    def linear_velocity(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                        expressed_in: Name = None) -> LinearVelocity: ...
    def angular_velocity(self, *, body: Name = None, ref_body: Name = None,
                         expressed_in: Name = None) -> AngularVelocity: ...

    def compile_pose(self, *, of: Name = None, body: Name = None, wrt: Name = None, ref_body: Name = None,
                     point: Name = None, orientation: Name = None, ref_point: Name = None,
                     ref_orientation: Name = None, expressed_in: Name = None) -> CompiledPose: ...
    def compile_position(self, *, of: Name = None, body: Name = None, wrt: Name = None, ref_body: Name = None,
                         point: Name = None, orientation: Name = None, ref_point: Name = None,
                         ref_orientation: Name = None, expressed_in: Name = None) -> CompiledPosition: ...
    def compile_orientation(self, *, of: Name = None, body: Name = None, wrt: Name = None, ref_body: Name = None,
                            point: Name = None, orientation: Name = None, ref_point: Name = None,
                            ref_orientation: Name = None, expressed_in: Name = None) -> CompiledOrientation: ...
    def compile_twist(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                      expressed_in: Name = None) -> CompiledTwist: ...
    def compile_linear_velocity(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                                expressed_in: Name = None) -> CompiledTwist: ...
    def compile_angular_velocity(self, *, body: Name = None, ref_body: Name = None,
                                 expressed_in: Name = None) -> CompiledTwist: ...

    def pose_handle(self, *, of: str, wrt: str) -> PoseHandle: ...
    def twist_handle(self, *, point: str, ref_body: str) -> TwistHandle: ...
    def set_pose(self, handle: PoseHandle, *, position: Optional[ArrayLike] = None,
                 rotation: Optional[ArrayLike] = None, quaternion: Optional[ArrayLike] = None,
                 rotation_matrix: Optional[ArrayLike] = None, rpy: Optional[ArrayLike] = None) -> None: ...
    def set_twist(self, handle: TwistHandle, *, linear: Optional[ArrayLike] = None,
                  angular: Optional[ArrayLike] = None) -> None: ...
    def pose_batch(self, handles: Sequence[PoseHandle]) -> PoseBatch: ...
    def twist_batch(self, handles: Sequence[TwistHandle]) -> TwistBatch: ...

    def dump(self) -> str: ...
    def check_invariants(self) -> str: ...
    def dot(self) -> str:
        """Graphviz DOT in the style of the paper's Fig. 8."""
    def to_script(self) -> str:
        """The graph as a scene script that rebuilds it (same names, ids, edges, values)."""

class ScriptRun:
    graph: SceneGraph
    json_lines: List[str]
    outcomes: List[dict]
    ok: bool

def run_script(path: Union[str, "os.PathLike[str]"]) -> ScriptRun:
    """Applies a scene script file like `semgraph run FILE`. ScriptError when malformed."""

def run_script_text(text: Union[str, bytes], file_name: str = ..., base_dir: str = ...) -> ScriptRun: ...
