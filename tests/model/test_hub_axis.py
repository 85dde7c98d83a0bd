"""The hub about world x, y or z: its mass matrix against the Lagrangian by hand, its files (URDF
through Pinocchio's parser, the model JSON, MuJoCo's MJCF) carrying the axis, a loaded hub about z
against the clamped chain's planar statics, and the refusals."""

from __future__ import annotations

import json

import numpy as np
import pinocchio as pin
import pytest
from paths import BEAMS
from tolerances import EPS

from prbdm_pin import BeamInputError, Hub, build_model, linearize, load_urdf
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.files.export import mjcf_text, read_model_json
from prbdm_pin.files.model_json import model_dict

BEAM = load_beam(BEAMS / "reference-random.json")
L = BEAM.length_m
LENGTHS = np.array([0.15, 0.3, 0.2, 0.35]) * L
SPRINGS = np.array([400.0, 150.0, 60.0])
AXIS = {"x": np.array([1.0, 0.0, 0.0]), "y": np.array([0.0, 1.0, 0.0]),
        "z": np.array([0.0, 0.0, 1.0])}


def _ry(t: float) -> np.ndarray:
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_one_joint_hub_mass_matrix_is_its_lagrangian(axis):
    J, r, q = 50.0, 0.12, 0.7
    lengths = np.array([0.4, 0.6]) * L
    model = build_model(BEAM, lengths, [90.0], hub=Hub(J, r, axis))
    s = model.sections
    a, y = AXIS[axis], AXIS["y"]
    # link 0 fixed to the hub at radius r along x; link 1 pitched by q about y at r + L_0
    p1 = np.array([r + lengths[0], 0.0, 0.0])
    c = [np.array([r, 0.0, 0.0]) + s.com_m[0] - [s.start_m[0], 0.0, 0.0],
         p1 + _ry(q) @ (s.com_m[1] - [s.start_m[1], 0.0, 0.0])]
    I = [s.inertia_com_kg_m2[0], _ry(q) @ s.inertia_com_kg_m2[1] @ _ry(q).T]
    m = s.mass_kg
    # T = 1/2 v^T M v: the hub turns both links about a, the joint link 1 about y through p1
    Mhh = J + sum(a @ I[i] @ a + m[i] * np.cross(a, c[i]) @ np.cross(a, c[i]) for i in range(2))
    Mhq = a @ I[1] @ y + m[1] * np.cross(a, c[1]) @ np.cross(y, c[1] - p1)
    Mqq = y @ I[1] @ y + m[1] * np.cross(y, c[1] - p1) @ np.cross(y, c[1] - p1)
    # CRBA against the hand sums: a few roundings of terms of the size of M_hh
    np.testing.assert_allclose(model.mass_matrix(np.array([0.4, q])),
                               [[Mhh, Mhq], [Mhq, Mqq]], rtol=0.0, atol=100 * EPS * Mhh)


@pytest.mark.parametrize("axis", ["x", "z"])
def test_urdf_carries_the_axis_through_pinocchio_parser(axis, tmp_path):
    model = build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(2.0, 0.1, axis))
    path = model.write_urdf(tmp_path / "hub.urdf")
    parsed = pin.buildModelFromUrdf(str(path))
    assert parsed.joints[1].shortname() == f"JointModelR{axis.upper()}"
    loaded = load_urdf(path)
    assert loaded.hub == model.hub
    pose = np.array([0.3, 0.4, -0.2, 0.5])
    # the same bodies through the parser: equal but for the rounding of repr'd placements
    np.testing.assert_allclose(loaded.mass_matrix(pose), model.mass_matrix(pose), rtol=0.0,
                               atol=100 * EPS * model.mass_matrix(pose)[0, 0])
    bad = tmp_path / "tilted.urdf"
    unit = " ".join("1" if a == axis else "0" for a in "xyz")
    bad.write_text(model.urdf.replace(f'<axis xyz="{unit}"/>', '<axis xyz="0.6 0.8 0"/>', 1))
    with pytest.raises(BeamInputError, match="'hub'.*axis"):
        load_urdf(bad)


def test_model_json_carries_the_axis(tmp_path):
    model = build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(50.0, 0.1, "z"))
    d = model_dict(model)
    assert d["hub"] == {"inertia_kg_m2": 50.0, "radius_m": 0.1, "axis": "z"}
    path = tmp_path / "m.json"
    path.write_text(json.dumps(d))
    assert read_model_json(path).hub == Hub(50.0, 0.1, "z")
    del d["hub"]["axis"]  # a file from before the axis: the hub about y
    path.write_text(json.dumps(d))
    assert read_model_json(path).hub == Hub(50.0, 0.1, "y")
    d["hub"]["axis"] = "w"
    path.write_text(json.dumps(d))
    with pytest.raises(BeamInputError, match="hub.axis = 'w'"):
        read_model_json(path)


def test_mjcf_hub_about_z_is_the_same_chain():
    mujoco = pytest.importorskip("mujoco")
    model = build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(50.0, 0.1, "z"))
    text = mjcf_text(model, 0.02, inputs=("hub_torque",))
    assert 'joint name="hub" type="hinge" axis="0 0 1"' in text
    m = mujoco.MjModel.from_xml_string(text)
    d = mujoco.MjData(m)
    pose = np.array([0.3, 0.4, -0.2, 0.5])
    d.qpos[:] = pose
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    # MuJoCo's composite-rigid-body sums from the MJCF's 17-digit numbers: a few roundings
    np.testing.assert_allclose(M, model.mass_matrix(pose), rtol=0.0,
                               atol=1000 * EPS * M[0, 0])


def test_loaded_hub_about_z_balances_as_the_clamped_chain():
    # a tip force along z has no moment about the z axis: the hub needs no trim and the beam
    # joints balance as the clamped chain's (its planar statics, another solver and tangent)
    F = np.array([0.0, 0.0, -30.0])
    hub = build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(50.0, 0.1, "z"))
    clamped = build_model(BEAM, LENGTHS, SPRINGS)
    lin = linearize(hub, inputs=("hub_torque",), outputs=("tip_z",), load_N=F)
    ref = linearize(clamped, inputs=("tip_force_z",), outputs=("tip_z",), load_N=F)
    # both solved to the statics' rtol 1e-10 (relative to the spring torques)
    np.testing.assert_allclose(lin.q_eq[1:], ref.q_eq, rtol=1e-9)
    assert lin.q_eq[0] == 0.0 and abs(lin.u_eq[0]) < 1e-9 * np.abs(F).max() * L
    # the load stiffness by the serial chain's tangent against the planar closed form
    np.testing.assert_allclose(lin.stiffness_Nm_per_rad[1:, 1:], ref.stiffness_Nm_per_rad,
                               rtol=1e-8, atol=1e-8 * SPRINGS.max())


@pytest.mark.parametrize("bad", ["w", "Y", 3, None])
def test_hub_axis_refusals(bad):
    with pytest.raises(BeamInputError, match="Hub axis"):
        Hub(1.0, 0.1, bad)


@pytest.mark.parametrize("axis", ["x", "z"])
def test_hub_out_of_the_bending_plane_leaves_the_clamped_modes(axis):
    # a hub about x or z moves the beam along y, which no bending joint (about y) does, and
    # turns it about an axis orthogonal to theirs: at the straight pose M_hf = 0, so the
    # flexible modes are the clamped chain's (its own scaled eigensolver; a few roundings of
    # the spread (w_max / w_min)^2 = 1e3 apart)
    hub = build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(50.0, 0.1, axis))
    clamped = build_model(BEAM, LENGTHS, SPRINGS)
    assert not np.any(hub.mass_matrix()[0, 1:])
    w = hub.natural_frequencies()
    w_c = clamped.natural_frequencies()
    assert w[0] == 0.0
    np.testing.assert_allclose(w[1:], w_c, rtol=5000 * EPS * (w_c[-1] / w_c[0]) ** 2)
    omega, Phi = hub.modes()
    np.testing.assert_allclose(Phi.T @ hub.mass_matrix() @ Phi, np.eye(4), atol=5000 * EPS)
    np.testing.assert_allclose(omega, w, rtol=5000 * EPS * (w_c[-1] / w_c[0]) ** 2)
