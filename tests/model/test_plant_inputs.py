"""Strain actuators by virtual work, the patch-end rule, and refused inputs and outputs."""


import numpy as np
import pinocchio as pin
import pytest
from paths import ROOT
from tolerances import EPS

from prbdm_pin import BeamInputError, Hub, StrainActuator, build_model, linearize
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.model.inputs import joint_stations, strain_map

BEAM = load_beam(ROOT / "examples/beams/reference-random.json")
L = BEAM.length_m
LENGTHS = np.array([0.15, 0.3, 0.2, 0.35]) * L  # joints at 0.15, 0.45, 0.65 L
SPRINGS = np.array([400.0, 150.0, 60.0])


@pytest.fixture(scope="module")
def model():
    return build_model(BEAM, LENGTHS, SPRINGS)


def _section_rotation(pm, data, lengths, q, x):
    """World rotation about +y of the section at station x (m), in the sense of the joint
    angles, from the chain's kinematics: the rotation of the link the station lies on."""
    pin.forwardKinematics(pm, data, q)
    link = min(int(np.searchsorted(np.cumsum(lengths), x, side="right")), lengths.size - 1)
    R = data.oMi[link].rotation  # joint `link` moves link `link` (joint 0: the world)
    return float(np.arctan2(R[0, 2], R[0, 0]))


# a patch holding no joint ([0.5, 0.6] L) is refused: tests/project/test_public_doors.py
@pytest.mark.parametrize("xa,xb", [(0.05, 0.5), (0.2, 0.9), (0.0, 1.0)])
def test_virtual_work_of_the_moment_pair(model, xa, xb):
    pm, data = model.pin_model, model.pin_model.createData()
    a, b = xa * L, xb * L
    M = 3.7
    rng = np.random.default_rng(1)
    h = 1e-6
    for q in (np.zeros(3), rng.uniform(-0.8, 0.8, 3)):
        def work(q):
            return M * (_section_rotation(pm, data, LENGTHS, q, b)
                        - _section_rotation(pm, data, LENGTHS, q, a))
        grad = np.array([(work(q + h * e) - work(q - h * e)) / (2 * h) for e in np.eye(3)])
        lin = linearize(model, inputs=("strain[0]",), q_eq=q,
                        actuators=[StrainActuator(a, b)])
        np.testing.assert_allclose(M * lin.input_map[:, 0], grad, atol=1e-8)


def test_static_response_equals_joint_torques_inside_the_span(model):
    patch = StrainActuator(0.1 * L, 0.6 * L)  # joints 0 and 1
    lin = linearize(model, inputs=("strain[0]", "joint_torque[0]", "joint_torque[1]"),
                    outputs=("tip_z", "tip_x", "q[0]", "q[1]", "q[2]", "spring_torque[1]"),
                    actuators=[patch], load_N=[0.0, 0.0, -20.0])
    dc = np.asarray(lin.to_control().dcgain())
    # atol: gains of one solve of the loaded stiffness, their superposition cancelling to a
    # few EPS of the largest gain (25 EPS measured); kept: the test's 1e-12 of it
    np.testing.assert_allclose(dc[:, 0], dc[:, 1] + dc[:, 2], rtol=1e-10,
                               atol=5000 * EPS * np.max(np.abs(dc)))
    # and nonlinearly: K q = M on the inside joints, the outside joint unloaded
    Mpatch = 2.0
    q = np.linalg.solve(np.diag(SPRINGS), Mpatch * np.array([1.0, 1.0, 0.0]))
    lin0 = linearize(model, inputs=("strain[0]",), outputs=("q[0]", "q[1]", "q[2]"),
                     actuators=[patch])
    # a solve of a diagonal stiffness either side (8 EPS of the gains measured); kept: the
    # test's 1e-12 and 1e-15 rad
    np.testing.assert_allclose(Mpatch * np.asarray(lin0.to_control().dcgain()).ravel(), q,
                               rtol=5000 * EPS, atol=5 * EPS)


def test_patch_end_on_a_joint_gives_half_the_moment():
    x = joint_stations(LENGTHS)
    on = strain_map(LENGTHS, StrainActuator(x[0], x[2]))
    np.testing.assert_array_equal(on, [0.5, 1.0, 0.5])
    # the midpoint of the jump as an end moves across the joint
    eps = 1e-6 * L
    before = strain_map(LENGTHS, StrainActuator(x[0] - eps, x[2]))
    after = strain_map(LENGTHS, StrainActuator(x[0] + eps, x[2]))
    np.testing.assert_array_equal(before, [1.0, 1.0, 0.5])
    np.testing.assert_array_equal(after, [0.0, 1.0, 0.5])
    np.testing.assert_allclose(on, 0.5 * (before + after))
    # two patches end to end add up to the patch covering both
    left = strain_map(LENGTHS, StrainActuator(0.0, x[1]))
    right = strain_map(LENGTHS, StrainActuator(x[1], L))
    np.testing.assert_allclose(left + right, strain_map(LENGTHS, StrainActuator(0.0, L)))
    # rounding of the stations does not move a joint out of "on"
    np.testing.assert_array_equal(
        strain_map(LENGTHS, StrainActuator(0.0, x[1] * (1 + 1e-14))), [1.0, 0.5, 0.0])


# a patch starting before the root is refused when made; one ending beyond the tip when used
@pytest.mark.parametrize("xa,xb,field", [(-0.1, 0.5, "StrainActuator x_start_m"),
                                         (0.2, 1.2, r"actuators\[0\] x_end_m")])
def test_patch_outside_the_beam_is_refused(model, xa, xb, field):
    with pytest.raises(BeamInputError, match=rf"{field} ="):
        linearize(model, inputs=("strain[0]",), actuators=[StrainActuator(xa * L, xb * L)])


@pytest.mark.parametrize("xa,xb", [(0.5, 0.5), (0.6, 0.2)])
def test_empty_or_reversed_patch_is_refused(xa, xb):
    with pytest.raises(BeamInputError, match="x_start_m"):
        StrainActuator(xa, xb)
    with pytest.raises(BeamInputError, match="x_end_m"):
        StrainActuator(0.1, float("nan"))


@pytest.mark.parametrize("kw,pattern", [
    ({"inputs": ("tip_force_q",)}, r"inputs\[0\] = 'tip_force_q': unknown"),
    ({"inputs": ("tip_force_z", "strain[0]")}, r"inputs\[1\] = 'strain\[0\]'"),
    ({"inputs": ("joint_torque[3]",)}, r"inputs\[0\] = 'joint_torque\[3\]': index 3"),
    ({"inputs": ("hub_torque",)}, r"inputs\[0\] = 'hub_torque': unknown"),
    ({"inputs": "tip_force_z"}, r"inputs = 'tip_force_z'"),
    ({"outputs": ("tip_z", "tip_w")}, r"outputs\[1\] = 'tip_w': unknown"),
    ({"outputs": ("q[-1]",)}, r"outputs\[0\] = 'q\[-1\]'"),
    ({"outputs": ("tip_z", "tip_z")}, r"outputs = .*twice"),
    ({"load_N": [0.0, 1.0]}, r"load_N = \[0.0, 1.0\]"),
    ({"gravity_m_s2": [0.0, 0.0, float("inf")]}, r"gravity_m_s2 ="),
    ({"damping": "viscous"}, r"damping = 'viscous'"),
    ({"damping_ratio": -0.1}, r"damping_ratio = -0.1"),
    ({"q_eq": [0.0, 0.0]}, r"q_eq = \[0.0, 0.0\]"),
    ({"actuators": [(0.1, 0.2)]}, r"actuators\[0\] = \(0.1, 0.2\)"),
])
def test_bad_arguments_are_refused_by_name(model, kw, pattern):
    with pytest.raises(BeamInputError, match=pattern):
        linearize(model, **kw)


@pytest.mark.parametrize("J,r,field", [(-1.0, 0.1, "inertia_kg_m2"), (0.0, 0.1, "inertia_kg_m2"),
                                       (1.0, -0.1, "radius_m"), (float("nan"), 0.0,
                                                                 "inertia_kg_m2"),
                                       (True, 0.0, "inertia_kg_m2")])
def test_bad_hub_is_refused(J, r, field):
    with pytest.raises(BeamInputError, match=f"Hub {field} ="):
        Hub(J, r)


def test_hub_only_names_need_a_hub(model):
    with pytest.raises(BeamInputError, match=r"outputs\[0\] = 'hub_angle': unknown"):
        linearize(model, outputs=("hub_angle",))
    with pytest.raises(BeamInputError, match="hub = 'big'"):
        build_model(BEAM, LENGTHS, SPRINGS, hub="big")
