"""simulate() of a beam on a free-floating bus: momentum conservation and the bus-frame outputs.

References: the system's linear and angular momentum about its centre of mass (Pinocchio's
centroidal momentum, computed from the bodies' velocities, not from the equations the integrator
steps), which no internal force changes; the member's tip in the clamp frame (the bus frame
moved to the root) from the whole system's frame placements (oM_clamp^-1 oM_tip).
"""

import numpy as np
import pinocchio as pin
import pytest
from paths import ROOT
from tolerances import EPS

from prbdm_pin import BeamInputError, build_model, simulate, spatial_stiffness
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.model.supports import FreeBus

BEAM = load_beam(ROOT / "examples/beams/reference-random.json")
LENGTHS = np.array([0.15, 0.3, 0.2, 0.35]) * BEAM.length_m
SPRINGS = np.array([400.0, 150.0, 60.0])
BUS = FreeBus(15.0, [[0.4, 0.02, 0.0], [0.02, 0.5, 0.01], [0.0, 0.01, 0.6]],
              com_m=[-0.1, 0.05, 0.02], root_m=[0.25, 0.0, -0.05])
# a tumbling, drifting start with the member swinging (attitude well away from pitch 90 deg)
V0 = np.r_[0.2, -0.1, 0.3, 0.4, -0.3, 0.5, 2.0, -1.0, 3.0]


def _momentum(model, Q, V):
    pm = model.pin_model
    data = pm.createData()
    return np.array([pin.computeCentroidalMomentum(pm, data, q, v).vector for q, v in
                     zip(Q, V, strict=True)])


@pytest.mark.parametrize("method,kw,rtol", [
    ("DOP853", dict(rtol=1e-11), 1e-10),  # its rtol over ~470 steps (3e-13 measured)
    ("exponential", {}, 1e-5),  # its step tolerance 3e-4 of the motion (1.7e-6 measured)
])
def test_momentum_about_the_centre_of_mass_is_conserved(method, kw, rtol):
    model = build_model(BEAM, LENGTHS, SPRINGS, support=BUS)
    T = 3 * 2 * np.pi / model.natural_frequencies()[6]  # three periods of the first mode
    r = simulate(model, T, v0=V0, damping_ratio=0.03, method=method, output_dt_s=T / 30, **kw)
    h = _momentum(model, r.q_rad, r.v_rad_s)
    scale = np.abs(h).max()
    assert np.abs(r.q_rad[:, 6:]).max() > 0.01  # the member bends
    assert np.abs(r.q_rad[:, 3:6]).max() > 0.1  # the bus turns
    assert np.abs(h - h[0]).max() <= rtol * scale
    # the damping only takes the flexible modes' energy: the rigid motion keeps its momentum


def test_a_spatial_member_on_a_bus_conserves_momentum(tapered):
    lengths = np.array([0.3, 0.4, 0.3]) * tapered.length_m
    model = build_model(tapered, lengths, spatial_stiffness(tapered, lengths, "xyz"),
                        axes="xyz", support=FreeBus(5.0, [0.1, 0.2, 0.3], root_m=[0.1, 0, 0]))
    v0 = np.zeros(model.pin_model.nv)
    v0[:6] = [0.1, 0.0, 0.0, 0.3, 0.2, -0.1]
    v0[6], v0[8] = 1.0, -0.5  # the member bends in and out of plane
    r = simulate(model, 0.3, v0=v0, method="DOP853", rtol=1e-11, output_dt_s=0.03)
    h = _momentum(model, r.q_rad, r.v_rad_s)
    assert np.abs(r.q_rad[:, 6:]).max() > 1e-3
    assert np.abs(h - h[0]).max() <= 1e-10 * np.abs(h).max()  # its rtol (3e-15 measured)


def test_member_outputs_are_in_the_clamp_frame():
    model = build_model(BEAM, LENGTHS, SPRINGS, support=BUS)
    r = simulate(model, 0.3, v0=V0, damping_ratio=0.0, method="DOP853", output_dt_s=0.05,
                 outputs=("tip_z", "tip_x", "q[1]", "bus_attitude_y", "bus_position_x",
                          "bus_rate_z"))
    pm = model.pin_model
    data = pm.createData()
    fid = pm.getFrameId("bus")
    clamp = pin.SE3(np.eye(3), np.array(BUS.root_m))
    for k, q in enumerate(r.q_rad):
        pin.framesForwardKinematics(pm, data, q)
        tip = ((data.oMf[fid] * clamp).inverse() * data.oMf[model.tip_frame_id]).translation
        # two kinematic paths (planar closed form vs Pinocchio's placements through the bus's
        # six joints and its inverse): roundings of positions ~1 m (kept: 1e-13)
        np.testing.assert_allclose(r.tip_position_m[k], tip, rtol=0, atol=500 * EPS)
        np.testing.assert_allclose(r.output_values[k, :2], tip[[2, 0]], rtol=0, atol=500 * EPS)
    np.testing.assert_array_equal(r.output_values[:, 2], r.q_rad[:, 7])
    np.testing.assert_array_equal(r.output_values[:, 3], r.q_rad[:, 4])  # pitch
    np.testing.assert_array_equal(r.output_values[:, 4], r.q_rad[:, 0])
    assert r.output_units == ("m", "m", "rad", "rad", "m", "rad/s")


def test_plant_inputs_and_gravity_on_a_bus_obey_newtons_laws():
    model = build_model(BEAM, LENGTHS, SPRINGS, support=BUS)
    T = 0.4
    F = np.array([0.0, 0.0, 3.0])  # N, world, at the tip
    kw = dict(method="DOP853", rtol=1e-11, output_dt_s=T / 8, damping_ratio=0.02)
    # an internal torque between two links: the momentum stays zero
    r = simulate(model, T, inputs=("joint_torque[1]",), u=lambda t: [2.0 * np.sin(9.0 * t)],
                 **kw)
    h = _momentum(model, r.q_rad, r.v_rad_s)
    assert np.abs(r.q_rad[:, 3:6]).max() > 1e-4  # the bus reacts
    # kg m/s and kg m^2/s: DOP853's rtol 1e-11 on momenta ~0.1 (1.6e-15 measured)
    assert np.abs(h).max() <= 1e-11
    # a tip force: the linear momentum grows as F t, whatever the member does
    r = simulate(model, T, inputs=("tip_force_z",), u=[F[2]], outputs=("tip_z",), **kw)
    h = _momentum(model, r.q_rad, r.v_rad_s)
    # DOP853's rtol 1e-11 (2e-15 of F T measured)
    np.testing.assert_allclose(h[:, :3], np.outer(r.t_s, F), rtol=0, atol=1e-11 * F[2] * T)
    np.testing.assert_array_equal(r.input_values[:, 0], F[2])
    # gravity: the linear momentum grows as (total mass) g t, the angular one about the centre
    # of mass stays (a uniform field has no moment about it)
    g = np.array([0.0, -2.0, -9.81])
    r = simulate(model, T, v0=V0, gravity_m_s2=g, **kw)
    h, h0 = _momentum(model, r.q_rad, r.v_rad_s), _momentum(model, [np.zeros(9)], [V0])[0]
    mass = BUS.mass_kg + float(np.sum(model.sections.mass_kg))
    scale = np.abs(h).max()
    # DOP853's rtol 1e-11 (2e-14 and 7e-16 of the momentum measured)
    assert np.abs(h[:, :3] - (h0[:3] + mass * np.outer(r.t_s, g))).max() <= 1e-11 * scale
    assert np.abs(h[:, 3:] - h0[3:]).max() <= 1e-11 * scale


def test_bad_runs_on_a_bus_are_refused():
    model = build_model(BEAM, LENGTHS, SPRINGS, support=BUS)
    with pytest.raises(BeamInputError, match="outputs"):
        simulate(model, 0.1, outputs=("hub_angle",))
    with pytest.raises(BeamInputError, match="inputs"):
        simulate(model, 0.1, inputs=("hub_torque",))
    with pytest.raises(BeamInputError, match="q0"):
        simulate(model, 0.1, q0=np.zeros(3))
