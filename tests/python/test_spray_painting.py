"""The paper's spray-painting scene (De Laet et al., IROS 2013, section V) through the Python
module, every number checked against the numpy/scipy oracle of conftest.World."""

import numpy as np
import pytest

import semgraph
from conftest import BODY, assert_rotation, build_spray_painting


def test_scene_shape(spray):
    assert spray.num_frames == 6 and spray.num_bodies == 5
    assert spray.num_pose_edges == 5 and spray.num_twist_edges == 4
    assert sorted(spray.frames) == ["b", "c", "e", "f1", "o1", "o2"]
    assert sorted(spray.bodies) == ["B", "C", "E", "O1", "O2"]
    assert spray.body_of("f1") == "O1" and spray.body_of("nope") is None
    assert spray.check_invariants() == ""
    assert repr(spray) == ("SceneGraph(representation='quaternion', frames=6, bodies=5, "
                           "pose_edges=5, twist_edges=4)")


def test_listing_2_pose_of_paint_point_wrt_gun(spray, world):
    X = spray.pose(of="f1", body="O1", wrt="o2", ref_body="O2")
    p, R = world.pose("f1", "f1", "o2", "o2", "o2")
    np.testing.assert_allclose(X.position, p, atol=1e-12, rtol=0)
    assert_rotation(X.quaternion, R)
    np.testing.assert_allclose(X.rotation_matrix, R, atol=1e-12, rtol=0)
    T = X.matrix
    np.testing.assert_allclose(T[:3, :3], R, atol=1e-12, rtol=0)
    np.testing.assert_allclose(T[:3, 3], p, atol=1e-12, rtol=0)
    np.testing.assert_array_equal(T[3], [0, 0, 0, 1])
    assert X.semantics == "PoseCoord({f1}|O1, {o2}|O2, [o2])"
    assert repr(X).startswith("Pose(PoseCoord({f1}|O1, {o2}|O2, [o2]), position=[")


def test_listing_2_twist_of_paint_point_wrt_gun(spray, world):
    V = spray.twist(point="f1", body="O1", ref_body="O2", expressed_in="o2")
    v, w = world.twist("f1", "O1", "O2", "o2")
    np.testing.assert_allclose(V.linear, v, atol=1e-12, rtol=0)
    np.testing.assert_allclose(V.angular, w, atol=1e-12, rtol=0)
    assert V.semantics == "TwistCoord(f1|O1, O2, [o2])"
    assert "linear=[" in repr(V) and "angular=[" in repr(V)


@pytest.mark.parametrize("e", ["f1", "o1", "c", "e", "o2", "b"])
@pytest.mark.parametrize("f", ["b", "o2", "f1"])
@pytest.mark.parametrize("r", ["b", "c", "o1", "o2"])
def test_every_pose_between_frames_in_every_frame(spray, world, e, f, r):
    X = spray.pose(of=e, wrt=f, expressed_in=r)
    p, R = world.pose(e, e, f, f, r)
    np.testing.assert_allclose(X.position, p, atol=1e-12, rtol=0)
    assert_rotation(X.quaternion, R)


def test_pose_with_point_ref_point_and_frame_changed(spray, world):
    X = spray.pose(of="o1", body="O1", wrt="o2", ref_body="O2", point="f1", ref_point="o2",
                   expressed_in="c")
    p, R = world.pose("f1", "o1", "o2", "o2", "c")
    np.testing.assert_allclose(X.position, p, atol=1e-12, rtol=0)
    assert_rotation(X.quaternion, R)
    assert X.semantics == "PoseCoord((f1,[o1])|O1, {o2}|O2, [c])"


def test_position_and_orientation(spray, world):
    P = spray.position(of="f1", wrt="o2", expressed_in="c")
    p, _ = world.pose("f1", "f1", "o2", "o2", "c")
    np.testing.assert_allclose(P.position, p, atol=1e-12, rtol=0)
    assert P.semantics == "PositionCoord(f1|O1, o2|O2, [c])"
    O = spray.orientation(of="o1", wrt="e", expressed_in="b")
    _, R = world.pose("o1", "o1", "e", "e", "b")
    assert_rotation(O.quaternion, R)
    np.testing.assert_allclose(O.rotation_matrix, R, atol=1e-12, rtol=0)
    assert O.semantics == "OrientationCoord([o1]|O1, [e]|E, [b])"


@pytest.mark.parametrize("point", ["f1", "o2", "e", "c", "b"])
@pytest.mark.parametrize("frame", ["b", "c", "o1", "f1", "e", "o2"])
def test_velocities_at_coincident_points_in_every_frame(spray, world, point, frame):
    V = spray.twist(point=point, body="O1", ref_body="E", expressed_in=frame)
    v, w = world.twist(point, "O1", "E", frame)
    np.testing.assert_allclose(V.linear, v, atol=1e-12, rtol=0)
    np.testing.assert_allclose(V.angular, w, atol=1e-12, rtol=0)
    lv = spray.linear_velocity(point=point, body="C", ref_body="O2", expressed_in=frame)
    v, w = world.twist(point, "C", "O2", frame)
    np.testing.assert_allclose(lv.linear, v, atol=1e-12, rtol=0)
    av = spray.angular_velocity(body="C", ref_body="O2", expressed_in=frame)
    np.testing.assert_allclose(av.angular, w, atol=1e-12, rtol=0)


def test_twist_body_defaults_to_the_points_body(spray, world):
    V = spray.twist(point="f1", ref_body="B", expressed_in="b")
    v, w = world.twist("f1", BODY["f1"], "B", "b")
    np.testing.assert_allclose(V.linear, v, atol=1e-12, rtol=0)
    np.testing.assert_allclose(V.angular, w, atol=1e-12, rtol=0)


def test_angular_velocity_of_cylinder_in_base(spray, world):
    w = spray.angular_velocity(body="O1", ref_body="B", expressed_in="b")
    np.testing.assert_allclose(w.angular, world.V["O1"][0], atol=1e-12, rtol=0)
    assert w.semantics == "AngularVelocityCoord(O1, B, [b])"


def test_rotation_input_forms_agree(world):
    """rotation= (quaternion or matrix by shape), quaternion=, rotation_matrix=, rpy= and the
    default identity give the same stored pose as the oracle."""
    from conftest import rpy_rotation, wxyz
    angles = (0.3, -0.2, 1.1)
    rot = rpy_rotation(*angles)
    forms = [dict(rpy=angles), dict(quaternion=wxyz(rot)), dict(rotation=list(wxyz(rot))),
             dict(rotation_matrix=rot.as_matrix()), dict(rotation=rot.as_matrix().tolist()),
             dict(quaternion=tuple(-wxyz(rot)))]
    for form in forms:
        g = semgraph.SceneGraph()
        g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=(1, 2, 3), **form)
        X = g.pose(of="a", wrt="w")
        assert_rotation(X.quaternion, rot.as_matrix())
        np.testing.assert_array_equal(X.position, [1.0, 2.0, 3.0])
    g = semgraph.SceneGraph()
    g.add_pose(of="a", body="A", wrt="w", ref_body="W")
    X = g.pose(of="a", wrt="w")
    np.testing.assert_array_equal(X.quaternion, [1, 0, 0, 0])
    np.testing.assert_array_equal(X.position, [0, 0, 0])


def test_homogeneous_representation_matches_the_oracle(world):
    g = build_spray_painting("homogeneous")
    assert g.representation == "homogeneous"
    for e, f in [("f1", "o2"), ("o2", "f1"), ("c", "e"), ("f1", "b")]:
        X = g.pose(of=e, wrt=f)
        p, R = world.pose(e, e, f, f, f)
        np.testing.assert_allclose(X.position, p, atol=1e-12, rtol=0)
        assert_rotation(X.quaternion, R)
    V = g.twist(point="f1", ref_body="O2", expressed_in="o2")
    v, w = world.twist("f1", "O1", "O2", "o2")
    np.testing.assert_allclose(V.linear, v, atol=1e-12, rtol=0)
    np.testing.assert_allclose(V.angular, w, atol=1e-12, rtol=0)
    # A pose expressed in another frame cannot be held by a homogeneous matrix.
    with pytest.raises(semgraph.QueryError) as info:
        g.pose(of="f1", wrt="o2", expressed_in="c")
    assert info.value.code == "representation_constraint"
    assert "homogeneous" in info.value.message
    # Positions and twists are vectors: any frame.
    P = g.position(of="f1", wrt="o2", expressed_in="c")
    np.testing.assert_allclose(P.position, world.pose("f1", "f1", "o2", "o2", "c")[0], atol=1e-12, rtol=0)


@pytest.mark.skipif(not semgraph._semgraph._has_tools, reason="built without the tool library")
def test_dot_shows_every_body_frame_and_edge(spray):
    dot = spray.dot()
    assert dot.startswith("digraph")
    for name in ["{b}", "{c}", "{o1}", "{f1}", "{e}", "{o2}", "\"B\"", "\"O1\""]:
        assert name in dot
    assert dot.count("style=dashed") >= 4  # the twist edges


@pytest.mark.skipif(not semgraph._semgraph._has_tools, reason="built without the tool library")
def test_to_script_rebuilds_the_same_graph(spray):
    text = spray.to_script()
    assert text.splitlines()[2] == "representation: quaternion"
    rebuilt = semgraph.run_script_text(text)
    assert rebuilt.ok, rebuilt.json_lines
    assert rebuilt.graph.dump() == spray.dump()
    # A later change shows in the next script, and only there.
    spray.add_pose(of="o2", body="O2", wrt="e", ref_body="E", position=[0.125, 0, 0])
    assert semgraph.run_script_text(spray.to_script()).graph.dump() == spray.dump()
    assert rebuilt.graph.dump() != spray.dump()
