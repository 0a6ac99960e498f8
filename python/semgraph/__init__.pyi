# Type stubs of semgraph (the public API; the implementation is the C++ extension _semgraph).
# Names are keyword-only roles; numbers are lists, tuples or numpy arrays, results numpy float64.
import os
from typing import Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
Vector = np.ndarray  # shape (3,), float64
Name = Optional[str]
# A time: int = nanoseconds (exact), float = seconds (rounded to the nearest ns). Also durations.
Time = Union[int, float]
# A query's at=: a time, "latest" (each edge's newest sample) or "latest_common" (tf2's Time(0)).
At = Union[int, float, str, None]

class Error(Exception):
    """Base class of semgraph's errors."""

class RejectedError(Error):
    """A build-time operation was refused; nothing changed."""
    code: str  # snake_case error code, e.g. "multiple_pose_parents"
    message: str
    discrepancy: Optional[Tuple[float, float]]  # repair's refused consistency check: (position, angle)
    def __init__(self, code: str, message: str, discrepancy: Optional[Tuple[float, float]] = ...) -> None: ...

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

class TimeReport:
    """What a timed query read. Times in float seconds; *_ns: exact int nanoseconds."""
    @property
    def time(self) -> Optional[float]:
        """The time answered (at=; latest_common when a stamped edge was used)."""
    @property
    def time_ns(self) -> Optional[int]: ...
    @property
    def ref_time(self) -> Optional[float]:
        """Time travel: the reference side's time."""
    @property
    def ref_time_ns(self) -> Optional[int]: ...
    @property
    def oldest(self) -> Optional[float]:
        """The oldest stamp of the samples read (None: only timeless edges)."""
    @property
    def oldest_ns(self) -> Optional[int]: ...
    @property
    def newest(self) -> Optional[float]:
        """The newest stamp of the samples read."""
    @property
    def newest_ns(self) -> Optional[int]: ...
    @property
    def extrapolated(self) -> bool:
        """An edge was extrapolated (at= with max_extrapolation=)."""

class EdgeUse:
    """One edge a query uses (explain_pose / explain_twist)."""
    kind: str  # "pose", "twist" or "pose_derivative"
    of: str  # head frame
    relative_to: str  # tail frame (pose) or tail body (twist)
    stamped: bool
    extrapolated: bool
    @property
    def first(self) -> Optional[float]:
        """The edge's oldest sample (s); None when timeless."""
    @property
    def first_ns(self) -> Optional[int]: ...
    @property
    def last(self) -> Optional[float]: ...
    @property
    def last_ns(self) -> Optional[int]: ...
    @property
    def read_from(self) -> Optional[float]:
        """The samples read: one stamp (read_from == read_to) or the bracket around the time."""
    @property
    def read_from_ns(self) -> Optional[int]: ...
    @property
    def read_to(self) -> Optional[float]: ...
    @property
    def read_to_ns(self) -> Optional[int]: ...

class RepairPolicy:
    """How add_pose / add_twist(..., repair=) repairs a rejected relation (docs/repair.md)."""
    invert: bool
    reroot: bool
    check_consistency: bool
    position_tolerance: float  # m (m/s for twists)
    angle_tolerance: float  # rad (rad/s for twists)
    def __init__(self, *, invert: bool = True, reroot: bool = True, check_consistency: bool = True,
                 position_tolerance: float = 1e-9, angle_tolerance: float = 1e-9) -> None: ...

class RepairReport:
    """What a repairing add did."""
    @property
    def applied(self) -> str:
        """'none', 'inverted', 'rerooted' or 'consistent'."""
    change: str  # the relation actually added, or why it was a no-op
    reversed_edges: int  # 'rerooted': pose edges reversed
    @property
    def discrepancy(self) -> Optional[Tuple[float, float]]:
        """'consistent': (position, angle) measured; None otherwise."""

class JointGroup:
    """A joint-state layout: these joints in this order."""
    names: List[str]
    def __len__(self) -> int: ...

class Jacobian:
    """Jacobian(e|C, D, [r]): TwistCoord(e|C, D, [r]) = J qdot + non-joint twists."""
    @property
    def matrix(self) -> np.ndarray:
        """(6, n): rows v_x v_y v_z then w_x w_y w_z; column i is joints[i]."""
    @property
    def linear(self) -> np.ndarray:
        """(3, n): the velocity rows."""
    @property
    def angular(self) -> np.ndarray:
        """(3, n): the angular velocity rows."""
    joints: List[str]
    @property
    def semantics(self) -> str: ...

class CompiledJacobian:
    """A compiled Jacobian query; keeps its graph alive."""
    def evaluate(self) -> Jacobian: ...
    joints: List[str]
    @property
    def is_valid(self) -> bool: ...

class Robot:
    """What load_urdf created (prefixed names)."""
    name: str
    prefix: str
    root: str
    links: List[str]
    joints: List[str]
    mimic_joints: List[str]
    fixed_joints: List[str]
    floating_joints: List[str]
    group: JointGroup

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
    @property
    def time(self) -> Optional[TimeReport]:
        """What a timed query read; None without time keywords."""

class Position:
    """PositionCoord(e|C, f|D, [r])."""
    @property
    def position(self) -> np.ndarray: ...
    @property
    def semantics(self) -> str: ...
    @property
    def time(self) -> Optional[TimeReport]:
        """What a timed query read; None without time keywords."""

class Orientation:
    """OrientationCoord([a]|C, [b]|D, [r])."""
    @property
    def quaternion(self) -> np.ndarray: ...
    @property
    def rotation_matrix(self) -> np.ndarray: ...
    @property
    def semantics(self) -> str: ...
    @property
    def time(self) -> Optional[TimeReport]:
        """What a timed query read; None without time keywords."""

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
    @property
    def time(self) -> Optional[TimeReport]:
        """What a timed query read; None without time keywords."""

class LinearVelocity:
    """LinearVelocityCoord(e|C, D, [r])."""
    @property
    def linear(self) -> np.ndarray: ...
    @property
    def semantics(self) -> str: ...
    @property
    def time(self) -> Optional[TimeReport]:
        """What a timed query read; None without time keywords."""

class AngularVelocity:
    """AngularVelocityCoord(C, D, [r])."""
    @property
    def angular(self) -> np.ndarray: ...
    @property
    def semantics(self) -> str: ...
    @property
    def time(self) -> Optional[TimeReport]:
        """What a timed query read; None without time keywords."""

class Wrench:
    """WrenchCoord(e|C, D, [r]): the wrench on body C by body D (or by several: a net wrench),
    moment about e's origin, in [r]."""
    @property
    def force(self) -> np.ndarray: ...
    @property
    def moment(self) -> np.ndarray: ...
    @property
    def semantics(self) -> str: ...
    @property
    def time(self) -> Optional[TimeReport]:
        """What a timed query read, or None for a query without time keywords."""

class CompiledPose:
    """A compiled pose query; keeps its graph alive."""
    def evaluate(self, *, at: At = None, max_extrapolation: Optional[Time] = None, not_before: Optional[Time] = None) -> Pose:
        """The pose now, or under a time policy (as SceneGraph.pose). QueryError('query_invalidated')
        once an edge it reads was removed; extrapolation / stale / invalid_number under a policy."""
    @property
    def is_valid(self) -> bool: ...
    @property
    def num_pose_edges(self) -> int: ...

class CompiledPosition:
    def evaluate(self, *, at: At = None, max_extrapolation: Optional[Time] = None, not_before: Optional[Time] = None) -> Position: ...
    @property
    def is_valid(self) -> bool: ...
    @property
    def num_pose_edges(self) -> int: ...

class CompiledOrientation:
    def evaluate(self, *, at: At = None, max_extrapolation: Optional[Time] = None, not_before: Optional[Time] = None) -> Orientation: ...
    @property
    def is_valid(self) -> bool: ...
    @property
    def num_pose_edges(self) -> int: ...

class CompiledTwist:
    """A compiled twist, linear velocity or angular velocity query."""
    def evaluate(self, *, at: At = None, max_extrapolation: Optional[Time] = None, not_before: Optional[Time] = None) -> Union[Twist, LinearVelocity, AngularVelocity]: ...
    @property
    def is_valid(self) -> bool: ...
    @property
    def num_pose_edges(self) -> int: ...
    @property
    def num_twist_edges(self) -> int: ...

class CompiledPoseWithCovariance:
    """A compiled pose query with covariance (SceneGraph.compile_pose_with_covariance); keeps its
    graph alive. covariance_order was fixed at compile time."""
    def evaluate(self, *, at: At = None, max_extrapolation: Optional[Time] = None,
                 not_before: Optional[Time] = None) -> Tuple[Pose, np.ndarray]:
        """(Pose, (6, 6) covariance) now, or under a time policy: what pose_with_covariance()
        answers with the same keywords (no time travel). QueryError('query_invalidated') once an
        edge it reads was removed; extrapolation / stale / invalid_number under a policy."""

class CompiledPositionWithCovariance:
    """A compiled position query with covariance."""
    def evaluate(self, *, at: At = None, max_extrapolation: Optional[Time] = None,
                 not_before: Optional[Time] = None) -> Tuple[Position, np.ndarray]:
        """(Position, (3, 3) covariance); as CompiledPoseWithCovariance.evaluate."""

class CompiledOrientationWithCovariance:
    """A compiled orientation query with covariance."""
    def evaluate(self, *, at: At = None, max_extrapolation: Optional[Time] = None,
                 not_before: Optional[Time] = None) -> Tuple[Orientation, np.ndarray]:
        """(Orientation, (3, 3) covariance); as CompiledPoseWithCovariance.evaluate."""

class CompiledTwistWithCovariance:
    """A compiled twist, linear velocity or angular velocity query with covariance."""
    def evaluate(self, *, at: At = None, max_extrapolation: Optional[Time] = None,
                 not_before: Optional[Time] = None) -> Tuple[Union[Twist, LinearVelocity, AngularVelocity], np.ndarray]:
        """(Twist, (6, 6)), (LinearVelocity, (3, 3)) or (AngularVelocity, (3, 3)), as compiled;
        as CompiledPoseWithCovariance.evaluate."""

class Acceleration:
    """AccelerationCoord(e|C, D, [r])."""
    @property
    def linear(self) -> np.ndarray:
        """(3,): classical acceleration of the point of body C at e relative to body D, in [r]."""
    @property
    def angular(self) -> np.ndarray:
        """(3,): angular acceleration of C relative to D, in [r]."""
    @property
    def semantics(self) -> str: ...
    @property
    def time(self) -> Optional[TimeReport]:
        """The TimeReport of a query given a time (at=, not_before=), else None."""

class CompiledAcceleration:
    """A compiled acceleration query (evaluate() raises QueryError no_acceleration while an edge
    of the path carries none, query_invalidated after an edge it reads was removed)."""
    def evaluate(self) -> Acceleration: ...
    @property
    def is_valid(self) -> bool: ...
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
    def __init__(self, representation: str = "quaternion", *, window: Optional[Time] = None,
                 interpolation: Optional[str] = None, duplicate_stamp: Optional[str] = None,
                 sample_capacity: Optional[int] = None) -> None:
        """window: history per stamped edge (default 10 s); interpolation: "screw" (default) or
        "linear" (tf2's); duplicate_stamp: "replace" (default) or "reject"; sample_capacity:
        samples per stamped edge (default 1024). RejectedError invalid_number: window <= 0,
        sample_capacity < 2."""
    @property
    def time_options(self) -> Dict[str, Union[float, int, str]]:
        """window (s), window_ns, interpolation, duplicate_stamp, sample_capacity."""
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
                 rpy: Optional[ArrayLike] = None, stamp: Optional[Time] = None,
                 repair: Union[bool, RepairPolicy, None] = None,
                 covariance: Optional[ArrayLike] = None, covariance_order: Optional[str] = None,
                 convention: Optional[str] = None) -> Optional[RepairReport]:
        """Adds (or updates) the pose of `of` relative to `wrt` as the edge {wrt} -> {of}.

        position: of's origin relative to wrt's origin in [expressed_in or wrt], default 0.
        At most one rotation form: rotation (4 numbers = quaternion, 3x3 = matrix),
        quaternion (w, x, y, z), rotation_matrix (3x3), rpy (roll, pitch, yaw; R = Rz Ry Rx).
        stamp: a stamped sample (int ns or float s). repair: True or a RepairPolicy: repair a
        P1 / pose_cycle rejection and return a RepairReport (None without repair).
        covariance: the value's (6, 6) covariance (docs/uncertainty.md), rows (dp, dtheta);
        covariance_order "linear_angular" (default) or "angular_linear"; convention
        "coordinates" (default) or "body" (edge form only). Not with stamp or repair.
        RejectedError on any violated rule; the graph is then unchanged."""
    def add_twist(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                  expressed_in: Name = None, linear: Optional[ArrayLike] = None,
                  angular: Optional[ArrayLike] = None, stamp: Optional[Time] = None,
                  repair: Union[bool, RepairPolicy, None] = None,
                  covariance: Optional[ArrayLike] = None,
                  covariance_order: Optional[str] = None,
                  linear_acceleration: Optional[ArrayLike] = None,
                  angular_acceleration: Optional[ArrayLike] = None) -> Optional[RepairReport]:
        """Adds (or updates) the twist of `body` (default: point's body) relative to `ref_body`
        as the edge ref_body -> {point}; linear/angular in [expressed_in]. stamp, repair: as
        add_pose (repair: W1 by the inverse twist, duplicate_twist_path by consistency).
        covariance: (6, 6), rows (dv, dw) (covariance_order as add_pose).
        linear_acceleration / angular_acceleration: the edge's acceleration (same point and
        frame), stored with the twist (with stamp: the sample's); without them the edge (or the
        sample) carries none. Not with repair or covariance."""
    def remove_pose(self, *, of: str, wrt: str) -> None: ...
    def remove_twist(self, *, point: str, ref_body: str) -> None: ...

    @property
    def num_wrenches(self) -> int: ...
    def add_wrench(self, *, on: Name = None, by: Name = None, point: Name = None,
                   expressed_in: Name = None, force: Optional[ArrayLike] = None,
                   moment: Optional[ArrayLike] = None, stamp: Optional[Time] = None) -> None:
        """Adds (or updates) the wrench on body `on` by body `by`: force and moment (about
        point's origin) in [expressed_in] (default [point]); with `stamp`, a sample at that time
        converted with the poses there. RejectedError: invalid_name, invalid_number,
        unknown_frame, unknown_body, self_wrench, wrench_not_convertible, extrapolation,
        duplicate_wrench, stamp_mismatch, stamp_too_old, duplicate_stamp; the graph is
        unchanged."""
    def remove_wrench(self, *, on: str, by: str) -> None: ...
    def wrench(self, *, on: Name = None, by: Name = None, point: Name = None,
               expressed_in: Name = None, at: At = None,
               max_extrapolation: Optional[Time] = None,
               not_before: Optional[Time] = None) -> Wrench:
        """The wrench on `on` by `by` (or the net wrench on `on` without `by`), about `point`, in
        [expressed_in] (default [point]); with a time keyword, the wrenches and poses at that
        time (as twist queries). QueryError: invalid_name, invalid_number, unknown_frame,
        unknown_body, self_wrench, no_wrench, no_pose_path, extrapolation, stale."""
    def force(self, *, on: Name = None, by: Name = None, point: Name = None,
              expressed_in: Name = None, at: At = None,
              max_extrapolation: Optional[Time] = None,
              not_before: Optional[Time] = None) -> np.ndarray: ...
    def moment(self, *, on: Name = None, by: Name = None, point: Name = None,
               expressed_in: Name = None, at: At = None,
               max_extrapolation: Optional[Time] = None,
               not_before: Optional[Time] = None) -> np.ndarray: ...

    def add_acceleration(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                         expressed_in: Name = None, linear: Optional[ArrayLike] = None,
                         angular: Optional[ArrayLike] = None, stamp: Optional[Time] = None) -> None:
        """Sets the acceleration of the existing twist edge ref_body -> body: a of the point of
        `body` at point's origin and alpha, in [expressed_in]; on a stamped edge, with stamp=,
        that of its twist sample at the stamp. RejectedError: invalid_name, invalid_number,
        unknown_frame, unknown_body, no_such_edge, joint_edge, stamp_mismatch,
        acceleration_not_convertible, duplicate_stamp; the graph is unchanged."""
    def set_acceleration(self, handle: TwistHandle, *, linear: Optional[ArrayLike] = None,
                         angular: Optional[ArrayLike] = None, stamp: Optional[Time] = None) -> None:
        """O(1): the acceleration of the handle's edge in its form (at and in its head frame);
        stamp=: of its twist sample at that stamp."""
    def acceleration(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                     expressed_in: Name = None, at: At = None,
                     max_extrapolation: Optional[Time] = None,
                     not_before: Optional[Time] = None) -> Acceleration:
        """The acceleration of `body` at `point` relative to `ref_body`, in [expressed_in], at the
        time asked (at=, as twist()). QueryError: invalid_name, unknown_frame, unknown_body,
        frame_body_mismatch, no_pose_path, no_twist_path, no_acceleration, extrapolation, stale."""
    def linear_acceleration(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                            expressed_in: Name = None, at: At = None,
                            max_extrapolation: Optional[Time] = None,
                            not_before: Optional[Time] = None) -> np.ndarray: ...
    def angular_acceleration(self, *, body: Name = None, ref_body: Name = None,
                             expressed_in: Name = None, at: At = None,
                             max_extrapolation: Optional[Time] = None,
                             not_before: Optional[Time] = None) -> np.ndarray: ...
    def compile_acceleration(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                             expressed_in: Name = None) -> CompiledAcceleration: ...

    def pose(self, *, of: Name = None, body: Name = None, wrt: Name = None, ref_body: Name = None,
             point: Name = None, orientation: Name = None, ref_point: Name = None,
             ref_orientation: Name = None, expressed_in: Name = None, at: At = None,
             max_extrapolation: Optional[Time] = None, not_before: Optional[Time] = None,
             ref_at: Optional[Time] = None, fixed: Name = None) -> Pose:
        """The pose of `of` relative to `wrt`, in `expressed_in` (default [wrt]). QueryError.

        Time (times: int ns or float s): at= a time, "latest" or "latest_common";
        max_extrapolation= with at=<time>; not_before= (stale); time travel: at=, ref_at=,
        fixed=. The result's .time is then a TimeReport."""
    def position(self, *, of: Name = None, body: Name = None, wrt: Name = None, ref_body: Name = None,
                 point: Name = None, orientation: Name = None, ref_point: Name = None,
                 ref_orientation: Name = None, expressed_in: Name = None, at: At = None,
                 max_extrapolation: Optional[Time] = None, not_before: Optional[Time] = None,
                 ref_at: Optional[Time] = None, fixed: Name = None) -> Position: ...
    def orientation(self, *, of: Name = None, body: Name = None, wrt: Name = None, ref_body: Name = None,
                    point: Name = None, orientation: Name = None, ref_point: Name = None,
                 ref_orientation: Name = None, expressed_in: Name = None, at: At = None,
                    max_extrapolation: Optional[Time] = None, not_before: Optional[Time] = None,
                    ref_at: Optional[Time] = None, fixed: Name = None) -> Orientation: ...
    def twist(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
              expressed_in: Name = None, at: At = None, max_extrapolation: Optional[Time] = None,
              not_before: Optional[Time] = None, source: Optional[str] = None) -> Twist:
        """source: "twists" (default) or "poses" (the pose history's time derivative)."""
    def linear_velocity(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                        expressed_in: Name = None, at: At = None, max_extrapolation: Optional[Time] = None,
                        not_before: Optional[Time] = None, source: Optional[str] = None) -> LinearVelocity: ...
    def angular_velocity(self, *, body: Name = None, ref_body: Name = None,
                         expressed_in: Name = None, at: At = None, max_extrapolation: Optional[Time] = None,
                         not_before: Optional[Time] = None, source: Optional[str] = None) -> AngularVelocity: ...

    def pose_with_covariance(self, *, of: Name = None, body: Name = None, wrt: Name = None,
                             ref_body: Name = None, point: Name = None, orientation: Name = None,
                             ref_point: Name = None, ref_orientation: Name = None,
                             expressed_in: Name = None, covariance_order: Optional[str] = None,
                             at: At = None, max_extrapolation: Optional[Time] = None,
                             not_before: Optional[Time] = None, ref_at: Optional[Time] = None,
                             fixed: Name = None) -> Tuple[Pose, np.ndarray]:
        """pose() and the (6, 6) first-order covariance of its coordinates (dp, dtheta), from
        the covariances of the edges it uses (docs/uncertainty.md). The time keywords of pose():
        the answer at that time (result.time its TimeReport) with each edge's covariance at
        the time it is read; a time travel's two sides independent."""
    def position_with_covariance(self, *, of: Name = None, body: Name = None, wrt: Name = None,
                                 ref_body: Name = None, point: Name = None,
                                 orientation: Name = None, ref_point: Name = None,
                                 ref_orientation: Name = None, expressed_in: Name = None,
                                 at: At = None, max_extrapolation: Optional[Time] = None,
                                 not_before: Optional[Time] = None, ref_at: Optional[Time] = None,
                                 fixed: Name = None) -> Tuple[Position, np.ndarray]:
        """position() and its (3, 3) covariance; time keywords as pose_with_covariance."""
    def orientation_with_covariance(self, *, of: Name = None, body: Name = None, wrt: Name = None,
                                    ref_body: Name = None, point: Name = None,
                                    orientation: Name = None, ref_point: Name = None,
                                    ref_orientation: Name = None, expressed_in: Name = None,
                                    at: At = None, max_extrapolation: Optional[Time] = None,
                                    not_before: Optional[Time] = None,
                                    ref_at: Optional[Time] = None,
                                    fixed: Name = None) -> Tuple[Orientation, np.ndarray]:
        """orientation() and its (3, 3) covariance (dtheta); time keywords as
        pose_with_covariance."""
    def twist_with_covariance(self, *, point: Name = None, body: Name = None,
                              ref_body: Name = None, expressed_in: Name = None,
                              covariance_order: Optional[str] = None, at: At = None,
                              max_extrapolation: Optional[Time] = None,
                              not_before: Optional[Time] = None,
                              source: Optional[str] = None) -> Tuple[Twist, np.ndarray]:
        """twist() and its (6, 6) covariance (dv, dw); at= / max_extrapolation= / not_before=
        / source= as twist() (source="poses": from the bracketing samples' covariances; no
        time travel)."""
    def linear_velocity_with_covariance(
            self, *, point: Name = None, body: Name = None, ref_body: Name = None,
            expressed_in: Name = None, at: At = None, max_extrapolation: Optional[Time] = None,
            not_before: Optional[Time] = None,
            source: Optional[str] = None) -> Tuple[LinearVelocity, np.ndarray]:
        """linear_velocity() and its (3, 3) covariance; time keywords as twist_with_covariance."""
    def angular_velocity_with_covariance(
            self, *, body: Name = None, ref_body: Name = None, expressed_in: Name = None,
            at: At = None, max_extrapolation: Optional[Time] = None,
            not_before: Optional[Time] = None,
            source: Optional[str] = None) -> Tuple[AngularVelocity, np.ndarray]:
        """angular_velocity() and its (3, 3) covariance; time keywords as
        twist_with_covariance."""

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
                      expressed_in: Name = None, source: Optional[str] = None) -> CompiledTwist: ...
    def compile_linear_velocity(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                                expressed_in: Name = None, source: Optional[str] = None) -> CompiledTwist: ...
    def compile_angular_velocity(self, *, body: Name = None, ref_body: Name = None,
                                 expressed_in: Name = None, source: Optional[str] = None) -> CompiledTwist: ...

    def compile_pose_with_covariance(self, *, of: Name = None, body: Name = None, wrt: Name = None,
                                     ref_body: Name = None, point: Name = None,
                                     orientation: Name = None, ref_point: Name = None,
                                     ref_orientation: Name = None, expressed_in: Name = None,
                                     covariance_order: Optional[str] = None) -> CompiledPoseWithCovariance:
        """The query of pose_with_covariance(), compiled; covariance_order fixes the rows of
        every evaluation's (6, 6) covariance."""
    def compile_position_with_covariance(self, *, of: Name = None, body: Name = None, wrt: Name = None,
                                         ref_body: Name = None, point: Name = None,
                                         orientation: Name = None, ref_point: Name = None,
                                         ref_orientation: Name = None,
                                         expressed_in: Name = None) -> CompiledPositionWithCovariance: ...
    def compile_orientation_with_covariance(self, *, of: Name = None, body: Name = None, wrt: Name = None,
                                            ref_body: Name = None, point: Name = None,
                                            orientation: Name = None, ref_point: Name = None,
                                            ref_orientation: Name = None,
                                            expressed_in: Name = None) -> CompiledOrientationWithCovariance: ...
    def compile_twist_with_covariance(self, *, point: Name = None, body: Name = None,
                                      ref_body: Name = None, expressed_in: Name = None,
                                      covariance_order: Optional[str] = None,
                                      source: Optional[str] = None) -> CompiledTwistWithCovariance:
        """The query of twist_with_covariance(), compiled; source as compile_twist."""
    def compile_linear_velocity_with_covariance(
            self, *, point: Name = None, body: Name = None, ref_body: Name = None,
            expressed_in: Name = None, source: Optional[str] = None) -> CompiledTwistWithCovariance: ...
    def compile_angular_velocity_with_covariance(
            self, *, body: Name = None, ref_body: Name = None, expressed_in: Name = None,
            source: Optional[str] = None) -> CompiledTwistWithCovariance: ...

    def pose_handle(self, *, of: str, wrt: str) -> PoseHandle: ...
    def twist_handle(self, *, point: str, ref_body: str) -> TwistHandle: ...
    def set_pose(self, handle: PoseHandle, *, position: Optional[ArrayLike] = None,
                 rotation: Optional[ArrayLike] = None, quaternion: Optional[ArrayLike] = None,
                 rotation_matrix: Optional[ArrayLike] = None, rpy: Optional[ArrayLike] = None,
                 stamp: Optional[Time] = None, covariance: Optional[ArrayLike] = None,
                 covariance_order: Optional[str] = None,
                 convention: Optional[str] = None) -> None:
        """stamp: a new sample of a stamped edge (int ns or float s); covariance: its 6x6
        covariance, as add_pose takes it."""
    def set_twist(self, handle: TwistHandle, *, linear: Optional[ArrayLike] = None,
                  angular: Optional[ArrayLike] = None, stamp: Optional[Time] = None,
                  covariance: Optional[ArrayLike] = None,
                  covariance_order: Optional[str] = None) -> None: ...
    def pose_batch(self, handles: Sequence[PoseHandle]) -> PoseBatch: ...
    def twist_batch(self, handles: Sequence[TwistHandle]) -> TwistBatch: ...

    def explain_pose(self, *, of: Name = None, body: Name = None, wrt: Name = None, ref_body: Name = None,
                     point: Name = None, orientation: Name = None, ref_point: Name = None,
                     ref_orientation: Name = None, expressed_in: Name = None, at: At = None,
                     max_extrapolation: Optional[Time] = None,
                     not_before: Optional[Time] = None) -> List[EdgeUse]:
        """The edges pose(...) uses with their samples and the ones read (also when it fails)."""
    def explain_twist(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                      expressed_in: Name = None, at: At = None, max_extrapolation: Optional[Time] = None,
                      not_before: Optional[Time] = None, source: Optional[str] = None) -> List[EdgeUse]: ...

    def add_joint(self, name: str, *, type: str, parent: str, child: str, parent_body: Name = None,
                  child_body: Name = None, position: Optional[ArrayLike] = None,
                  rotation: Optional[ArrayLike] = None, quaternion: Optional[ArrayLike] = None,
                  rotation_matrix: Optional[ArrayLike] = None, rpy: Optional[ArrayLike] = None,
                  axis: Optional[ArrayLike] = None, lower: Optional[float] = None,
                  upper: Optional[float] = None, mimic: Name = None, multiplier: Optional[float] = None,
                  offset: Optional[float] = None) -> None:
        """type: "revolute", "continuous", "prismatic" or "fixed". X_origin (position, rotation):
        child relative to parent at q = 0; axis in [child] (default x); mimic: q = multiplier *
        q_master + offset. RejectedError (invalid_model, duplicate_joint, ...)."""
    @property
    def num_joints(self) -> int: ...
    @property
    def joint_names(self) -> List[str]:
        """Independent movable joints in add order: the default array layout."""
    def joint_group(self, names: Sequence[str]) -> JointGroup: ...
    def set_joints(self, positions: Union[ArrayLike, Mapping[str, float], None] = None,
                   velocities: Union[ArrayLike, Mapping[str, float], None] = None,
                   accelerations: Union[ArrayLike, Mapping[str, float], None] = None, *,
                   names: Union[Sequence[str], JointGroup, None] = None,
                   stamp: Optional[Time] = None) -> None:
        """Arrays in the layout of `names` (default joint_names), or dicts by joint name.
        stamp: a sample at that time (a field not given keeps the newest sample's).
        All or nothing: invalid_number, unknown_joint, mimic_joint, joint_limit; with or
        without a stamp against the joint's first state: stamp_mismatch; stamp_too_old,
        duplicate_stamp."""
    def joint_positions(self, names: Union[Sequence[str], JointGroup, None] = None) -> np.ndarray: ...
    def joint_velocities(self, names: Union[Sequence[str], JointGroup, None] = None) -> np.ndarray: ...
    def joint_accelerations(self, names: Union[Sequence[str], JointGroup, None] = None) -> np.ndarray:
        """NaN for a joint whose acceleration was never given."""
    def jacobian(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                 expressed_in: Name = None) -> Jacobian:
        """Jacobian of TwistCoord(point|body, ref_body, [expressed_in]) at the current state."""
    def compile_jacobian(self, *, point: Name = None, body: Name = None, ref_body: Name = None,
                         expressed_in: Name = None) -> CompiledJacobian: ...
    def load_urdf(self, path: Union[str, "os.PathLike[str]"], *, prefix: str = "") -> Robot:
        """Loads a URDF file (atomic; without the GIL). RejectedError invalid_model, ..."""
    def load_urdf_string(self, xml: str, *, prefix: str = "") -> Robot: ...

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
