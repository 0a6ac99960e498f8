"""The accelerations on twist edges from Python (SceneGraph.add_twist with linear_acceleration= /
angular_acceleration=, add_acceleration, set_acceleration, acceleration, linear_acceleration,
angular_acceleration, compile_acceleration; docs/dynamics.md §7). Values against oracles
computed here, independently of semgraph: a spinning disc (centripetal -w^2 r, tangential
alpha x r), a slider on a turning arm (the polar-coordinate formulas r'' - r th'^2 and
r th'' + 2 r' th', the Coriolis term), and a 3D two-joint motion differentiated numerically
(central differences of the point's world position and of the angular velocity). Every error
is raised with its code, leaving the graph unchanged (its canonical dump, which lists the
accelerations, compared before and after).

Legend: world {w}|W; the disc {disc}|Disc on {w} turned by TH about z, its rim {rim}|Disc at
R_RIM in [disc]; the arm {arm}|Arm on {w} turned by TH, the slider {s}|S on {arm} at X_S along
the arm's x; a lone {iso}|Iso."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import semgraph

TH = 0.7                       # the disc's and the arm's angle about z in [w]
R_RIM = np.array([0.5, 0.2, 0.0])
W_DISC, AL_DISC = 4.0, 2.0     # disc: angular velocity and acceleration about z
X_S = 1.5                      # slider: distance along the arm
W_ARM, AL_ARM = 0.8, -0.3      # arm: th', th''
U_S, UD_S = 0.4, 1.1           # slider: r', r''


def wxyz(rotation):
    x, y, z, w = rotation.as_quat()
    return [w, x, y, z]


def Rz(angle):
    return Rotation.from_rotvec([0, 0, angle])


@pytest.fixture(params=["quaternion", "homogeneous"])
def graph(request):
    g = semgraph.SceneGraph(request.param)
    g.add_pose(of="disc", body="Disc", wrt="w", ref_body="W", quaternion=wxyz(Rz(TH)))
    g.add_pose(of="rim", body="Disc", wrt="disc", position=R_RIM)
    g.add_pose(of="arm", body="Arm", wrt="w", ref_body="W", quaternion=wxyz(Rz(TH)))
    g.add_pose(of="s", body="S", wrt="arm", ref_body="Arm", position=[X_S, 0, 0])
    g.add_body("Iso")
    g.add_frame("iso", "Iso")
    return g


def spin(g):
    g.add_twist(point="disc", ref_body="W", expressed_in="disc", angular=[0, 0, W_DISC],
                angular_acceleration=[0, 0, AL_DISC])


def slide(g):
    g.add_twist(point="arm", ref_body="W", expressed_in="arm", angular=[0, 0, W_ARM],
                angular_acceleration=[0, 0, AL_ARM])
    g.add_twist(point="s", ref_body="Arm", expressed_in="arm", linear=[U_S, 0, 0],
                linear_acceleration=[UD_S, 0, 0])


def rim_acceleration_in_disc():
    """a of the rim point in [disc]: alpha x r + w x (w x r), by components."""
    x, y, _ = R_RIM
    return np.array([-W_DISC**2 * x - AL_DISC * y, -W_DISC**2 * y + AL_DISC * x, 0.0])


def test_a_spinning_disc_has_centripetal_and_tangential_acceleration(graph):
    spin(graph)
    a_disc = rim_acceleration_in_disc()
    a_w = Rz(TH).apply(a_disc)
    r = graph.acceleration(point="rim", ref_body="W", expressed_in="w")
    np.testing.assert_allclose(r.linear, a_w, atol=1e-12)
    np.testing.assert_allclose(r.angular, [0, 0, AL_DISC], atol=1e-12)
    assert "rim" in r.semantics and repr(r).startswith("Acceleration(")
    np.testing.assert_allclose(
        graph.linear_acceleration(point="rim", ref_body="W", expressed_in="disc"), a_disc,
        atol=1e-12)
    np.testing.assert_allclose(
        graph.angular_acceleration(body="Disc", ref_body="W", expressed_in="w"), [0, 0, AL_DISC],
        atol=1e-12)
    # The centre is on the axis: no acceleration.
    np.testing.assert_allclose(
        graph.linear_acceleration(point="disc", ref_body="W", expressed_in="w"), np.zeros(3),
        atol=1e-12)


def test_a_slider_on_a_turning_arm_has_the_coriolis_term(graph):
    slide(graph)
    # Polar coordinates: radial r'' - r th'^2, transverse r th'' + 2 r' th'.
    a_arm = np.array([UD_S - X_S * W_ARM**2, X_S * AL_ARM + 2 * U_S * W_ARM, 0.0])
    r = graph.acceleration(point="s", ref_body="W", expressed_in="w")
    np.testing.assert_allclose(r.linear, Rz(TH).apply(a_arm), atol=1e-12)
    np.testing.assert_allclose(r.angular, [0, 0, AL_ARM], atol=1e-12)
    np.testing.assert_allclose(
        graph.linear_acceleration(point="s", ref_body="W", expressed_in="arm"), a_arm, atol=1e-12)
    # Without the Coriolis term the transverse part would be X_S * AL_ARM only.
    assert abs(a_arm[1] - X_S * AL_ARM) > 0.5


# The 3D motion: A turns about the world axis N1 through O1 (angle th1(t)), B turns about N2 (in
# [a]) and its origin slides along D (in [a]) from P0; P is the point Q of B.
R10 = Rotation.from_rotvec([0.3, -0.5, 0.2])
O1 = np.array([0.4, -0.2, 1.0])
N1 = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
R20 = Rotation.from_rotvec([-0.6, 0.1, 0.9])
P0 = np.array([0.7, 0.3, -0.4])
N2 = np.array([0.2, -1.0, 0.6]) / np.linalg.norm([0.2, -1.0, 0.6])
D = np.array([0.0, 0.6, 0.8])
Q = np.array([0.3, -0.7, 0.5])
W1, AL1, W2, AL2, U, UD = 1.3, -0.4, -0.9, 0.7, 0.5, -1.2


def motion(t):
    """(R_WB, world position of P, world angular velocity of B) at time t, composed by hand."""
    R1 = Rotation.from_rotvec(N1 * (W1 * t + AL1 * t * t / 2)) * R10
    R2 = Rotation.from_rotvec(N2 * (W2 * t + AL2 * t * t / 2)) * R20
    p_AB = P0 + D * (U * t + UD * t * t / 2)
    p = O1 + R1.apply(p_AB + R2.apply(Q))
    w = N1 * (W1 + AL1 * t) + R1.apply(N2 * (W2 + AL2 * t))
    return R1 * R2, p, w


def numeric_acceleration():
    h = 1e-4
    (_, p_m, w_m), (_, p_0, _), (_, p_p, w_p) = motion(-h), motion(0.0), motion(h)
    return (p_p - 2 * p_0 + p_m) / h**2, (w_p - w_m) / (2 * h)


def tumbling_graph(backend):
    g = semgraph.SceneGraph(backend)
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=O1, quaternion=wxyz(R10))
    g.add_pose(of="b", body="B", wrt="a", ref_body="A", position=P0, quaternion=wxyz(R20))
    g.add_pose(of="p", body="B", wrt="b", position=Q)
    # Edge forms by hand: A at {a} in [a] (a on the axis: no linear terms); B at {b} in [b].
    Ri = R10.inv()
    g.add_twist(point="a", ref_body="W", expressed_in="a", angular=Ri.apply(N1 * W1),
                angular_acceleration=Ri.apply(N1 * AL1))
    R2i = R20.inv()
    g.add_twist(point="b", ref_body="A", expressed_in="b", linear=R2i.apply(D * U),
                angular=R2i.apply(N2 * W2), linear_acceleration=R2i.apply(D * UD),
                angular_acceleration=R2i.apply(N2 * AL2))
    return g


@pytest.mark.parametrize("backend", ["quaternion", "homogeneous"])
def test_a_3d_composition_matches_the_numeric_second_derivative(backend):
    g = tumbling_graph(backend)
    a_w, alpha_w = numeric_acceleration()
    r = g.acceleration(point="p", ref_body="W", expressed_in="w")
    np.testing.assert_allclose(r.linear, a_w, atol=1e-5)
    np.testing.assert_allclose(r.angular, alpha_w, atol=1e-6)
    # In [p] (= [b]): the same vectors rotated by R_WB^T.
    R_WB = motion(0.0)[0]
    np.testing.assert_allclose(g.linear_acceleration(point="p", ref_body="W", expressed_in="p"),
                               R_WB.inv().apply(a_w), atol=1e-5)
    np.testing.assert_allclose(g.angular_acceleration(body="B", ref_body="W", expressed_in="b"),
                               R_WB.inv().apply(alpha_w), atol=1e-6)
    c = g.compile_acceleration(point="p", ref_body="W", expressed_in="w")
    assert c.num_twist_edges == 2 and c.is_valid
    np.testing.assert_allclose(c.evaluate().linear, r.linear, atol=1e-12)
    np.testing.assert_allclose(c.evaluate().angular, r.angular, atol=1e-12)


def test_add_acceleration_converts_a_value_given_at_another_point_and_frame(graph):
    graph.add_twist(point="disc", ref_body="W", expressed_in="disc", angular=[0, 0, W_DISC])
    assert " a " not in graph.dump()
    # The rim's acceleration given in [w]: stored at {disc} in [disc], where it is zero (axis).
    graph.add_acceleration(point="rim", ref_body="W", expressed_in="w",
                           linear=Rz(TH).apply(rim_acceleration_in_disc()),
                           angular=[0, 0, AL_DISC])
    assert " alpha " in graph.dump()
    np.testing.assert_allclose(
        graph.linear_acceleration(point="disc", ref_body="W", expressed_in="w"), np.zeros(3),
        atol=1e-12)
    np.testing.assert_allclose(
        graph.linear_acceleration(point="rim", ref_body="W", expressed_in="disc"),
        rim_acceleration_in_disc(), atol=1e-12)


def test_a_compiled_query_sees_updates_and_reports_a_missing_acceleration(graph):
    spin(graph)
    c = graph.compile_acceleration(point="rim", ref_body="W", expressed_in="disc")
    assert "CompiledAcceleration(" in repr(c)
    np.testing.assert_allclose(c.evaluate().linear, rim_acceleration_in_disc(), atol=1e-12)
    # set_acceleration in the edge form ({disc}, [disc]): alpha only, tangential alpha x r.
    h = graph.twist_handle(point="disc", ref_body="W")
    graph.set_acceleration(h, angular=[0, 0, 3.0])
    x, y, _ = R_RIM
    np.testing.assert_allclose(c.evaluate().linear,
                               [-W_DISC**2 * x - 3.0 * y, -W_DISC**2 * y + 3.0 * x, 0], atol=1e-12)
    # A twist without an acceleration clears it.
    graph.add_twist(point="disc", ref_body="W", expressed_in="disc", angular=[0, 0, W_DISC])
    with pytest.raises(semgraph.QueryError) as e:
        c.evaluate()
    assert e.value.code == "no_acceleration"
    with pytest.raises(semgraph.QueryError) as e:
        graph.acceleration(point="rim", ref_body="W", expressed_in="disc")
    assert e.value.code == "no_acceleration" and "disc" in e.value.message
    graph.remove_twist(point="disc", ref_body="W")
    with pytest.raises(semgraph.QueryError) as e:
        c.evaluate()
    assert e.value.code == "query_invalidated"


# (code, operation): refused adds and updates; the graph holds the slider's accelerations and a
# stamped twist of Iso (its frame iso) relative to W.
def stamped(g):
    g.add_twist(point="iso", ref_body="W", expressed_in="iso", angular=[0, 0, 1], stamp=10)


REJECTIONS = [
    ("invalid_name", lambda g: g.add_acceleration(point="", ref_body="W", expressed_in="w")),
    ("invalid_number",
     lambda g: g.add_acceleration(point="s", ref_body="Arm", expressed_in="s",
                                  linear=[0, math.nan, 0])),
    ("invalid_number",
     lambda g: g.add_acceleration(point="s", ref_body="Arm", expressed_in="s",
                                  angular=[math.inf, 0, 0])),
    ("unknown_frame",
     lambda g: g.add_acceleration(point="nowhere", ref_body="Arm", expressed_in="s")),
    ("unknown_frame",
     lambda g: g.add_acceleration(point="s", ref_body="Arm", expressed_in="nowhere")),
    ("unknown_body",
     lambda g: g.add_acceleration(point="s", ref_body="NOPE", expressed_in="s")),
    ("no_such_edge", lambda g: g.add_acceleration(point="s", ref_body="W", expressed_in="s")),
    ("no_such_edge", lambda g: g.add_acceleration(point="rim", ref_body="W", expressed_in="w")),
    ("stamp_mismatch",
     lambda g: g.add_acceleration(point="iso", ref_body="W", expressed_in="iso", linear=[1, 0, 0])),
    ("acceleration_not_convertible",
     lambda g: g.add_acceleration(point="s", ref_body="Arm", expressed_in="iso")),
    # add_twist with a bad acceleration: neither the twist nor the acceleration is stored.
    ("invalid_number",
     lambda g: g.add_twist(point="disc", ref_body="W", expressed_in="disc", angular=[0, 0, 1],
                           linear_acceleration=[math.nan, 0, 0])),
    ("invalid_number",
     lambda g: g.add_twist(point="s", ref_body="Arm", expressed_in="s", linear=[9, 0, 0],
                           angular_acceleration=[0, 0, math.inf])),
    # set_acceleration through a handle.
    ("invalid_number",
     lambda g: g.set_acceleration(g.twist_handle(point="s", ref_body="Arm"),
                                  linear=[math.nan, 0, 0])),
    ("stamp_mismatch",
     lambda g: g.set_acceleration(g.twist_handle(point="iso", ref_body="W"), linear=[1, 0, 0])),
]


@pytest.mark.parametrize("code, operation", REJECTIONS)
def test_a_refused_add_or_update_raises_its_code_and_changes_nothing(graph, code, operation):
    slide(graph)
    stamped(graph)
    before = graph.dump()
    assert " alpha " in before
    with pytest.raises(semgraph.RejectedError) as e:
        operation(graph)
    assert e.value.code == code, e.value.message
    assert graph.dump() == before
    a_arm = np.array([UD_S - X_S * W_ARM**2, X_S * AL_ARM + 2 * U_S * W_ARM, 0.0])
    np.testing.assert_allclose(
        graph.linear_acceleration(point="s", ref_body="W", expressed_in="arm"), a_arm, atol=1e-12)


def test_set_acceleration_through_a_removed_handle_is_no_such_edge(graph):
    slide(graph)
    h = graph.twist_handle(point="s", ref_body="Arm")
    graph.remove_twist(point="s", ref_body="Arm")
    before = graph.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        graph.set_acceleration(h, linear=[1, 0, 0])
    assert e.value.code == "no_such_edge"
    assert graph.dump() == before


# (code, argument at fault, keywords); the graph holds the slider's accelerations, the disc's
# twist without one.
QUERY_ERRORS = [
    ("invalid_name", "point", dict(point="", ref_body="W", expressed_in="w")),
    ("unknown_frame", "point", dict(point="nowhere", ref_body="W", expressed_in="w")),
    ("unknown_frame", "expressed_in", dict(point="s", ref_body="W", expressed_in="nowhere")),
    ("unknown_body", "ref_body", dict(point="s", ref_body="NOPE", expressed_in="w")),
    ("unknown_body", "body", dict(point="s", body="NOPE", ref_body="W", expressed_in="w")),
    ("no_twist_path", None, dict(point="iso", ref_body="W", expressed_in="iso")),
    ("no_pose_path", None, dict(point="s", ref_body="W", expressed_in="iso")),
    ("no_acceleration", None, dict(point="rim", ref_body="W", expressed_in="w")),
]


@pytest.mark.parametrize("code, argument, keywords", QUERY_ERRORS)
@pytest.mark.parametrize("query", ["acceleration", "linear_acceleration", "compile_acceleration"])
def test_a_failed_query_raises_its_code(graph, query, code, argument, keywords):
    slide(graph)
    graph.add_twist(point="disc", ref_body="W", expressed_in="disc", angular=[0, 0, 1])
    if query == "compile_acceleration" and code == "no_acceleration":
        c = graph.compile_acceleration(**keywords)  # compiles: evaluate() reports it
        with pytest.raises(semgraph.QueryError) as e:
            c.evaluate()
        assert e.value.code == code
        return
    with pytest.raises(semgraph.QueryError) as e:
        getattr(graph, query)(**keywords)
    assert e.value.code == code, e.value.message
    assert e.value.argument == argument


def test_angular_acceleration_errors_name_their_keyword(graph):
    slide(graph)
    with pytest.raises(semgraph.QueryError) as e:
        graph.angular_acceleration(body="NOPE", ref_body="W", expressed_in="w")
    assert e.value.code == "unknown_body" and e.value.argument == "body"
    with pytest.raises(semgraph.QueryError) as e:
        graph.angular_acceleration(body="Disc", ref_body="W", expressed_in="w")
    assert e.value.code == "no_twist_path"


def test_wrong_python_arguments_raise_and_change_nothing(graph):
    slide(graph)
    before = graph.dump()
    with pytest.raises((TypeError, ValueError)):
        graph.add_acceleration(point="s", ref_body="Arm", expressed_in="s", linear=[1, 2])
    with pytest.raises(TypeError):
        graph.add_acceleration(point=3, ref_body="Arm", expressed_in="s")
    with pytest.raises(ValueError):  # not with repair / covariance in this version
        graph.add_twist(point="s", ref_body="Arm", expressed_in="s", repair=True,
                        linear_acceleration=[1, 0, 0])
    with pytest.raises(ValueError):
        graph.add_twist(point="s", ref_body="Arm", expressed_in="s", covariance=np.eye(6) * 1e-4,
                        angular_acceleration=[1, 0, 0])
    other = semgraph.SceneGraph()
    other.add_pose(of="s", body="S", wrt="arm", ref_body="Arm")
    other.add_twist(point="s", ref_body="Arm", expressed_in="s")
    with pytest.raises(ValueError):
        graph.set_acceleration(other.twist_handle(point="s", ref_body="Arm"), linear=[1, 0, 0])
    assert graph.dump() == before


def test_a_joints_edge_refuses_an_acceleration(graph):
    graph.add_joint("j", type="revolute", parent="w", child="link", parent_body="W",
                    child_body="L", axis=[0, 0, 1])
    before = graph.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        graph.add_acceleration(point="link", ref_body="W", expressed_in="link", angular=[0, 0, 1])
    assert e.value.code == "joint_edge"
    with pytest.raises(semgraph.RejectedError) as e:
        graph.set_acceleration(graph.twist_handle(point="link", ref_body="W"), angular=[0, 0, 1])
    assert e.value.code == "joint_edge"
    assert graph.dump() == before


def test_stamped_accelerations_interpolate_convert_at_their_stamp_and_are_never_implicit():
    """A disc turned by TH at 0 s and by TH + pi/2 at 2 s, its twist samples carrying
    accelerations (at the disc's origin, in [disc]); values by hand: halfway, the mean of the
    two samples; in [w], rotated by the disc's angle then; an acceleration given on its own in
    [w] at 2 s, rotated into [disc] with the angle at 2 s."""
    g = semgraph.SceneGraph()
    for t, angle in [(0, TH), (2, TH + math.pi / 2)]:
        g.add_pose(of="disc", body="Disc", wrt="w", ref_body="W", quaternion=wxyz(Rz(angle)),
                   stamp=float(t))
    g.add_twist(point="disc", ref_body="W", expressed_in="disc", angular=[0, 0, 1], stamp=0.0,
                linear_acceleration=[1, 0, 0], angular_acceleration=[0, 0, 0.5])
    g.add_twist(point="disc", ref_body="W", expressed_in="disc", angular=[0, 0, 2], stamp=2.0,
                linear_acceleration=[3, 0, 0], angular_acceleration=[0, 0, 0.5])
    A = g.acceleration(point="disc", ref_body="W", expressed_in="disc", at=1.0)
    np.testing.assert_allclose(A.linear, [2, 0, 0], atol=1e-12)
    np.testing.assert_allclose(A.angular, [0, 0, 0.5], atol=1e-12)
    assert A.time.time == 1.0 and A.time.oldest == 0.0 and A.time.newest == 2.0
    in_w = g.linear_acceleration(point="disc", ref_body="W", expressed_in="w", at=1.0)
    np.testing.assert_allclose(in_w, Rz(TH + math.pi / 4).apply([2, 0, 0]), atol=1e-12)
    a_w = np.array([0.3, -0.8, 0.1])
    g.add_acceleration(point="disc", ref_body="W", expressed_in="w", linear=a_w, stamp=2.0)
    np.testing.assert_allclose(
        g.linear_acceleration(point="disc", ref_body="W", expressed_in="disc", at=2.0),
        Rz(TH + math.pi / 2).inv().apply(a_w), atol=1e-12)
    np.testing.assert_allclose(
        g.angular_acceleration(body="Disc", ref_body="W", expressed_in="disc", at=2.0),
        [0, 0, 0], atol=1e-12)
    h = g.twist_handle(point="disc", ref_body="W")
    g.set_twist(h, angular=[0, 0, 2], stamp=3.0)  # a sample without an acceleration
    with pytest.raises(semgraph.QueryError) as e:
        g.acceleration(point="disc", ref_body="W", expressed_in="disc", at=2.5)
    assert e.value.code == "no_acceleration"
    g.set_acceleration(h, linear=[7, 0, 0], stamp=3.0)
    np.testing.assert_allclose(
        g.acceleration(point="disc", ref_body="W", expressed_in="disc").linear, [7, 0, 0])
    before = g.dump()
    for code, call in [
            ("acceleration_not_convertible",
             lambda: g.add_acceleration(point="disc", ref_body="W", expressed_in="disc",
                                        linear=[1, 0, 0], stamp=1.0)),
            ("stamp_mismatch", lambda: g.set_acceleration(h, linear=[1, 0, 0], stamp=1.5))]:
        with pytest.raises(semgraph.RejectedError) as e:
            call()
        assert e.value.code == code, e.value.message
    assert g.dump() == before


def test_stamped_joint_states_from_python_carry_their_accelerations():
    """A continuous joint about z, stamped from Python (arrays, then a dict): at the stamp 1 s the
    tool point 0.5 m out on the link has, in [w], alpha x r + w x (w x r) with w = qdot z,
    alpha = qddot z, r = Rz(q) (0.5, 0, 0) (by hand); halfway between the samples the angular
    acceleration is the mean of the two qddot; an unstamped state of the stamped joint is
    stamp_mismatch and changes nothing."""
    g = semgraph.SceneGraph()
    g.add_joint("j", type="continuous", parent="w", child="link", parent_body="W",
                child_body="L", axis=[0, 0, 1])
    g.add_pose(of="tool", body="L", wrt="link", ref_body="L", position=[0.5, 0, 0])
    g.set_joints([0.0], [1.0], [2.0], stamp=0.0)
    g.set_joints({"j": 0.7}, {"j": 3.0}, {"j": 4.0}, stamp=1.0)
    np.testing.assert_allclose(g.joint_positions(), [0.7])
    q, qd, qdd = 0.7, 3.0, 4.0
    r = np.array([0.5 * math.cos(q), 0.5 * math.sin(q), 0.0])
    w, alpha = np.array([0, 0, qd]), np.array([0, 0, qdd])
    expected = np.cross(alpha, r) + np.cross(w, np.cross(w, r))
    a = g.linear_acceleration(point="tool", body="L", ref_body="W", expressed_in="w", at=1.0)
    np.testing.assert_allclose(a, expected, atol=1e-12)
    half = g.angular_acceleration(body="L", ref_body="W", expressed_in="link", at=0.5)
    np.testing.assert_allclose(half, [0, 0, 3.0], atol=1e-12)
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        g.set_joints([0.1], [0.0])
    assert e.value.code == "stamp_mismatch"
    with pytest.raises(semgraph.RejectedError) as e:
        g.set_joints([float("nan")], stamp=2.0)
    assert e.value.code == "invalid_number"
    assert g.dump() == before
