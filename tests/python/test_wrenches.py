"""The wrenches of the graph from Python (SceneGraph.add_wrench, wrench, force, moment,
remove_wrench; docs/dynamics.md §7): values against an independent numpy oracle (world poses
composed with scipy's Rotation; a wrench moved with m_q = m_p + (p - q) x f and rotated), the
reaction and the net wrench, and every error raised with its code, leaving the graph unchanged
(its canonical dump, which lists the wrenches, compared before and after).

Legend: world {w}|W; {a}|A on {w}; {b}|B on {a}; {b2}|B on {b} (same body); {c}|C on {w};
a lone {iso}|Iso. X_W[f] = (R_Wf, p_Wf) the pose of frame f in [w]."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import semgraph

# (of, body, wrt, ref_body, rotation vector, position): the edges X_PF in [P].
POSES = [
    ("a", "A", "w", "W", (0.3, -0.2, 0.9), (1.0, 0.5, -0.2)),
    ("b", "B", "a", "A", (-0.7, 0.4, 0.1), (0.2, -1.1, 0.6)),
    ("b2", "B", "b", "B", (0.0, 1.2, -0.5), (0.4, 0.3, 0.0)),
    ("c", "C", "w", "W", (1.1, 0.2, -0.3), (-0.5, 0.8, 1.4)),
]


def wxyz(rotation):
    x, y, z, w = rotation.as_quat()
    return [w, x, y, z]


def world_poses():
    """{frame: (R_Wf as a scipy Rotation, p_Wf)}, composed here, not by semgraph."""
    X = {"w": (Rotation.identity(), np.zeros(3))}
    for of, _, wrt, _, rv, p in POSES:
        R_P, p_P = X[wrt]
        X[of] = (R_P * Rotation.from_rotvec(rv), p_P + R_P.apply(p))
    return X


X_W = world_poses()


def to_world(point, coord, f, m):
    """A wrench about point's origin in [coord] -> (f, m about point's origin) in [w]."""
    R = X_W[coord][0]
    return R.apply(f), R.apply(m)


def move(f_W, m_W, p, q):
    """Change of point in [w]: m_q = m_p + (p - q) x f."""
    return f_W, m_W + np.cross(X_W[p][1] - X_W[q][1], f_W)


def expressed(coord, f_W, m_W):
    R = X_W[coord][0].inv()
    return R.apply(f_W), R.apply(m_W)


@pytest.fixture(params=["quaternion", "homogeneous"])
def graph(request):
    g = semgraph.SceneGraph(request.param)
    for of, body, wrt, ref_body, rv, p in POSES:
        g.add_pose(of=of, body=body, wrt=wrt, ref_body=ref_body, position=p,
                   quaternion=wxyz(Rotation.from_rotvec(rv)))
    g.add_body("Iso")
    g.add_frame("iso", "Iso")
    return g


F1, M1 = np.array([1.0, -2.0, 3.0]), np.array([0.5, 0.25, -1.5])  # on B by A, about {a} in [c]
F2, M2 = np.array([-4.0, 0.5, 2.0]), np.array([0.0, 1.0, 0.75])  # on B by C, about {c} in [c]


def expected(point, coord, terms):
    """The sum of (sign, given point, given coord, f, m), moved to point, in [coord]."""
    f_sum, m_sum = np.zeros(3), np.zeros(3)
    for sign, p, r, f, m in terms:
        f_W, m_W = move(*to_world(p, r, f, m), p, point)
        f_sum += sign * f_W
        m_sum += sign * m_W
    return expressed(coord, f_sum, m_sum)


def assert_wrench(result, f, m):
    np.testing.assert_allclose(result.force, f, atol=1e-12)
    np.testing.assert_allclose(result.moment, m, atol=1e-12)


def test_a_wrench_moves_to_another_point_and_frame(graph):
    graph.add_wrench(on="B", by="A", point="a", expressed_in="c", force=F1, moment=M1)
    assert graph.num_wrenches == 1
    for point, coord in [("b2", "w"), ("b2", "b"), ("w", "c"), ("a", "a"), ("c", None)]:
        f, m = expected(point, coord or point, [(1, "a", "c", F1, M1)])
        assert_wrench(graph.wrench(on="B", by="A", point=point, expressed_in=coord), f, m)
        np.testing.assert_allclose(graph.force(on="B", by="A", point=point, expressed_in=coord),
                                   f, atol=1e-12)
        np.testing.assert_allclose(graph.moment(on="B", by="A", point=point, expressed_in=coord),
                                   m, atol=1e-12)


def test_the_reaction_is_the_negation(graph):
    graph.add_wrench(on="B", by="A", point="a", expressed_in="c", force=F1, moment=M1)
    f, m = expected("b", "w", [(-1, "a", "c", F1, M1)])
    r = graph.wrench(on="A", by="B", point="b", expressed_in="w")
    assert_wrench(r, f, m)
    assert "A" in r.semantics and "B" in r.semantics
    assert repr(r).startswith("Wrench(")


def test_the_net_wrench_sums_the_wrenches_on_and_the_reactions_of_those_by(graph):
    graph.add_wrench(on="B", by="A", point="a", expressed_in="c", force=F1, moment=M1)
    graph.add_wrench(on="B", by="C", point="c", force=F2, moment=M2)
    f, m = expected("b2", "a", [(1, "a", "c", F1, M1), (1, "c", "c", F2, M2)])
    assert_wrench(graph.wrench(on="B", point="b2", expressed_in="a"), f, m)
    # Net on A: the reaction of the wrench on B by A only.
    f, m = expected("w", "w", [(-1, "a", "c", F1, M1)])
    assert_wrench(graph.wrench(on="A", point="w"), f, m)


def test_an_update_replaces_the_value_and_a_removal_forgets_it(graph):
    graph.add_wrench(on="B", by="A", point="a", expressed_in="c", force=F1, moment=M1)
    graph.add_wrench(on="B", by="A", point="b", force=F2)  # moment defaults to zero
    assert graph.num_wrenches == 1
    f, m = expected("w", "w", [(1, "b", "b", F2, np.zeros(3))])
    assert_wrench(graph.wrench(on="B", by="A", point="w"), f, m)
    graph.remove_wrench(on="B", by="A")
    assert graph.num_wrenches == 0
    with pytest.raises(semgraph.QueryError) as e:
        graph.wrench(on="B", by="A", point="w")
    assert e.value.code == "no_wrench"


# (code, operation): refused adds and removals; the graph holds the wrench on B by A.
REJECTIONS = [
    ("invalid_name", lambda g: g.add_wrench(on="", by="A", point="b")),
    ("invalid_number", lambda g: g.add_wrench(on="B", by="C", point="b", force=[0, math.nan, 0])),
    ("invalid_number", lambda g: g.add_wrench(on="B", by="C", point="b", moment=[math.inf, 0, 0])),
    ("unknown_frame", lambda g: g.add_wrench(on="B", by="C", point="nowhere")),
    ("unknown_frame", lambda g: g.add_wrench(on="B", by="C", point="b", expressed_in="nowhere")),
    ("unknown_body", lambda g: g.add_wrench(on="NOPE", by="C", point="b")),
    ("unknown_body", lambda g: g.add_wrench(on="B", by="NOPE", point="b")),
    ("self_wrench", lambda g: g.add_wrench(on="B", by="B", point="b", force=[1, 0, 0])),
    ("wrench_not_convertible", lambda g: g.add_wrench(on="Iso", by="A", point="a", force=[1, 0, 0])),
    ("wrench_not_convertible", lambda g: g.add_wrench(on="B", by="C", point="iso", force=[1, 0, 0])),
    ("duplicate_wrench", lambda g: g.add_wrench(on="A", by="B", point="a", force=[1, 0, 0])),
    ("no_wrench", lambda g: g.remove_wrench(on="B", by="C")),
    ("no_wrench", lambda g: g.remove_wrench(on="A", by="B")),  # the reaction is not stored
    ("unknown_body", lambda g: g.remove_wrench(on="B", by="NOPE")),
    ("self_wrench", lambda g: g.remove_wrench(on="B", by="B")),
]


@pytest.mark.parametrize("code, operation", REJECTIONS)
def test_a_refused_add_or_removal_raises_its_code_and_changes_nothing(graph, code, operation):
    graph.add_wrench(on="B", by="A", point="a", expressed_in="c", force=F1, moment=M1)
    before = graph.dump()
    assert "wrench on B by A" in before
    with pytest.raises(semgraph.RejectedError) as e:
        operation(graph)
    assert e.value.code == code, e.value.message
    assert graph.dump() == before
    assert graph.num_wrenches == 1
    f, m = expected("w", "w", [(1, "a", "c", F1, M1)])
    assert_wrench(graph.wrench(on="B", by="A", point="w"), f, m)


# (code, argument at fault, keywords of the query); the graph holds the wrench on B by A.
QUERY_ERRORS = [
    ("invalid_name", "on", dict(on="", point="w")),
    ("unknown_frame", "point", dict(on="B", point="nowhere")),
    ("unknown_frame", "expressed_in", dict(on="B", point="w", expressed_in="nowhere")),
    ("unknown_body", "on", dict(on="NOPE", point="w")),
    ("unknown_body", "by", dict(on="B", by="NOPE", point="w")),
    ("self_wrench", None, dict(on="B", by="B", point="w")),
    ("no_wrench", None, dict(on="B", by="C", point="w")),
    ("no_wrench", None, dict(on="C", point="w")),
    ("no_pose_path", None, dict(on="B", point="iso")),
]


@pytest.mark.parametrize("code, argument, keywords", QUERY_ERRORS)
@pytest.mark.parametrize("query", ["wrench", "force", "moment"])
def test_a_failed_query_raises_its_code(graph, query, code, argument, keywords):
    graph.add_wrench(on="B", by="A", point="a", expressed_in="c", force=F1, moment=M1)
    with pytest.raises(semgraph.QueryError) as e:
        getattr(graph, query)(**keywords)
    assert e.value.code == code, e.value.message
    assert e.value.argument == argument


def test_wrong_python_arguments_are_type_errors(graph):
    with pytest.raises((TypeError, ValueError)):
        graph.add_wrench(on="B", by="A", point="a", force=[1, 2])
    with pytest.raises(TypeError):
        graph.add_wrench(on=3, by="A", point="a")
    assert graph.num_wrenches == 0
