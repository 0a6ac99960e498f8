"""semgraph: a constraint-checking scene graph of poses and twists of rigid bodies.

Founded on the geometric relations semantics of De Laet et al. (IROS 2013): every relation
names its point, orientation frame, body, reference point, reference orientation frame,
reference body and coordinate frame, and every operation on relations is checked.

    import semgraph
    g = semgraph.SceneGraph()
    g.add_pose(of="c", body="C", wrt="b", ref_body="B", position=[1.2, 0.4, 0.9], rpy=[0, 0.35, 2.36])
    g.pose(of="c", wrt="b").position

The numbers are computed by the C++ library (semgraph._semgraph); see docs/python.md.
"""

from ._errors import Error, QueryError, RejectedError, ScriptError
from ._semgraph import (
    Acceleration,
    AngularVelocity,
    CompiledAcceleration,
    CompiledJacobian,
    CompiledOrientation,
    CompiledOrientationWithCovariance,
    CompiledPose,
    CompiledPoseWithCovariance,
    CompiledPosition,
    CompiledPositionWithCovariance,
    CompiledTwist,
    CompiledTwistWithCovariance,
    EdgeUse,
    Jacobian,
    JointGroup,
    LinearVelocity,
    Orientation,
    Pose,
    PoseBatch,
    PoseHandle,
    Position,
    RepairPolicy,
    RepairReport,
    Robot,
    SceneGraph,
    TimeReport,
    Twist,
    TwistBatch,
    TwistHandle,
    Wrench,
    __version__,
)
from ._script import ScriptRun, run_script, run_script_text

__all__ = [
    "Acceleration",
    "AngularVelocity",
    "CompiledAcceleration",
    "CompiledJacobian",
    "CompiledOrientation",
    "CompiledOrientationWithCovariance",
    "CompiledPose",
    "CompiledPoseWithCovariance",
    "CompiledPosition",
    "CompiledPositionWithCovariance",
    "CompiledTwist",
    "CompiledTwistWithCovariance",
    "EdgeUse",
    "Error",
    "Jacobian",
    "JointGroup",
    "LinearVelocity",
    "Orientation",
    "Pose",
    "PoseBatch",
    "PoseHandle",
    "Position",
    "QueryError",
    "RejectedError",
    "RepairPolicy",
    "RepairReport",
    "Robot",
    "SceneGraph",
    "ScriptError",
    "ScriptRun",
    "TimeReport",
    "Twist",
    "TwistBatch",
    "TwistHandle",
    "Wrench",
    "run_script",
    "run_script_text",
]
