"""Stamped wrenches from Python (SceneGraph.add_wrench(stamp=), wrench / force / moment with the
time keywords; docs/dynamics.md, "Stamped wrenches"), against a numpy oracle: the samples'
linear interpolation in the stored form, moved with m_q = m_p + (p - q) x f and rotated with
scipy's Rotation; a stamped value converted with the poses at its stamp; the policies and the
errors, the graph unchanged (its dump) after a refused add.

Legend: world {w}|W; {c}|C slides along x of [w] with a constant rotation Rz(0.5):
p_Wc(t) = (2 (t - 1), 0, 0), sampled at 1 s and 2 s (screw and linear interpolation agree);
{d}|D fixed at (0, 1, 0)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import semgraph

R_WC = Rotation.from_euler("z", 0.5)


def p_WC(t):
    return np.array([2.0 * (t - 1.0), 0.0, 0.0])


def wxyz(rotation):
    x, y, z, w = rotation.as_quat()
    return [w, x, y, z]


# The samples of the wrench on C by D, about c in [c] (its storage frame).
SAMPLES = {1.0: ([1.0, 0.0, 0.0], [0.0, 0.0, 0.0]), 2.0: ([3.0, 2.0, 0.0], [0.0, 0.0, 4.0])}


@pytest.fixture
def graph():
    g = semgraph.SceneGraph()
    for t in (1.0, 2.0):
        g.add_pose(of="c", body="C", wrt="w", ref_body="W", position=p_WC(t),
                   quaternion=wxyz(R_WC), stamp=t)
    g.add_pose(of="d", body="D", wrt="w", ref_body="W", position=[0.0, 1.0, 0.0])
    for k, (t, (f, m)) in enumerate(SAMPLES.items()):
        stamp = round(t * 1e9) if k % 2 == 0 else t  # int nanoseconds or float seconds
        g.add_wrench(on="C", by="D", point="c", force=f, moment=m, stamp=stamp)
    return g


def lerp(t):
    l = t - 1.0
    (f0, m0), (f1, m1) = SAMPLES[1.0], SAMPLES[2.0]
    return ((1 - l) * np.array(f0) + l * np.array(f1), (1 - l) * np.array(m0) + l * np.array(m1))


def test_samples_are_interpolated_linearly_and_moved_with_the_poses_at_the_query_time(graph):
    t = 1.25
    f_c, m_c = lerp(t)
    W = graph.wrench(on="C", by="D", point="c", at=t)
    np.testing.assert_allclose(W.force, f_c, atol=1e-12)
    np.testing.assert_allclose(W.moment, m_c, atol=1e-12)
    assert W.time.time == t and W.time.oldest == 1.0 and W.time.newest == 2.0
    f_w = R_WC.apply(f_c)
    m_w = R_WC.apply(m_c) + np.cross(p_WC(t), f_w)  # m_w = m_c + (c - w) x f
    W = graph.wrench(on="C", by="D", point="w", at=t)
    np.testing.assert_allclose(W.force, f_w, atol=1e-12)
    np.testing.assert_allclose(W.moment, m_w, atol=1e-12)
    np.testing.assert_allclose(graph.force(on="C", point="w", at=t), f_w, atol=1e-12)
    # The reaction about d in [w]: -(f, m_w + (w - d) x f).
    m_d = m_w + np.cross(-np.array([0.0, 1.0, 0.0]), f_w)
    np.testing.assert_allclose(graph.moment(on="D", by="C", point="d", expressed_in="w", at=t),
                               -m_d, atol=1e-12)
    # Without a time keyword: the newest sample, no report.
    W = graph.wrench(on="C", by="D", point="c")
    np.testing.assert_allclose(W.force, SAMPLES[2.0][0], atol=0)
    assert W.time is None


def test_a_stamped_value_is_converted_with_the_poses_at_its_stamp(graph):
    f_w = np.array([0.0, 0.0, -2.0])
    graph.add_wrench(on="C", by="W", point="w", force=f_w, stamp=1.5)
    # Stored about c in [c] with the pose at 1.5 s: f_c = R^T f, m_c = R^T ((w - c) x f).
    f_c = R_WC.inv().apply(f_w)
    m_c = R_WC.inv().apply(np.cross(-p_WC(1.5), f_w))
    W = graph.wrench(on="C", by="W", point="c", at=1.5)
    np.testing.assert_allclose(W.force, f_c, atol=1e-12)
    np.testing.assert_allclose(W.moment, m_c, atol=1e-12)
    # Where the poses have no sample the add fails, and nothing changes.
    before = graph.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        graph.add_wrench(on="C", by="W", point="w", force=f_w, stamp=3.0)
    assert e.value.code == "extrapolation", e.value.message
    assert graph.dump() == before


def test_policies_and_their_errors(graph):
    W = graph.wrench(on="C", by="D", point="c", at="latest")
    np.testing.assert_allclose(W.force, SAMPLES[2.0][0], atol=0)
    assert W.time.newest == 2.0
    W = graph.wrench(on="C", point="w", at="latest_common")
    assert W.time.time == 2.0
    W = graph.wrench(on="C", by="D", point="c", at=2.5, max_extrapolation=1.0)
    np.testing.assert_allclose(W.moment, SAMPLES[2.0][1], atol=0)
    assert W.time.extrapolated
    with pytest.raises(semgraph.QueryError) as e:
        graph.wrench(on="C", by="D", point="c", at=4.0)
    assert e.value.code == "extrapolation"
    assert "the wrench on C by D has samples in [1.000, 2.000] s" in e.value.message
    with pytest.raises(semgraph.QueryError) as e:
        graph.moment(on="C", by="D", point="c", not_before=3.0)
    assert e.value.code == "stale"
    with pytest.raises(ValueError):
        graph.force(on="C", point="c", max_extrapolation=1.0)  # needs at=


def test_stamped_and_timeless_values_do_not_mix(graph):
    before = graph.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        graph.add_wrench(on="C", by="D", point="c", force=[1.0, 0.0, 0.0])
    assert e.value.code == "stamp_mismatch"
    assert graph.dump() == before
    graph.add_wrench(on="D", by="W", point="d", force=[1.0, 0.0, 0.0])
    before = graph.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        graph.add_wrench(on="D", by="W", point="d", force=[2.0, 0.0, 0.0], stamp=1.0)
    assert e.value.code == "stamp_mismatch"
    assert graph.dump() == before
