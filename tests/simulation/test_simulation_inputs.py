"""simulate(..., inputs=...): the plant's inputs, open loop and in closed loop, on a hub or
clamped, checked against physics the code does not use (angular momentum of a free hub, the
static angles of a spring chain), the exact response of the linear plant and another integrator.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

import prbdm_pin as pp
from prbdm_pin.model.inputs import StrainActuator

BEAM = pp.load_beam("examples/beams/uniform-narrow.json")
LENGTHS = np.full(4, 0.25)
SPRINGS = pp.finite_segment_stiffness(BEAM, LENGTHS)
PATCH = (StrainActuator(0.0, 0.3),)


def _hub_model(inertia=0.05):
    return pp.build_model(BEAM, LENGTHS, SPRINGS, hub=pp.Hub(inertia, 0.05))


def _peak_error(a, ref):
    return np.abs(a - ref).max(axis=0) / np.abs(ref).max(axis=0)


def test_hub_torque_gives_angular_momentum_torque_times_time_at_large_motion():
    # the hub coordinate is the absolute rotation of the whole body: its generalized momentum
    # (M v)[0] is the angular momentum about the hub axis, which a hub torque T changes at the
    # rate T whatever the panel does, and an internal strain moment does not change at all
    model = _hub_model()
    # a moment that bends the first joint ~0.2 rad; a torque that turns the hub ~2 rad in 1 s
    T, Mp = 4.0 * model.mass_matrix()[0, 0], 0.2 * SPRINGS[0]
    # DOP853 at rtol 1e-11 keeps it to rounding; the exponential integrator to its step
    # control's tolerance (3e-4 of the motion per step; measured 4e-5 of the final momentum)
    for method, tol in (("DOP853", 1e-10), ("exponential", 1e-4)):
        tr = pp.simulate(model, 1.0, inputs=("hub_torque", "strain[0]"), u=np.array([T, Mp]),
                         actuators=PATCH, output_dt_s=0.01, method=method, rtol=1e-11)
        p_hub = np.array([(model.mass_matrix(q) @ v)[0]
                          for q, v in zip(tr.q_rad, tr.v_rad_s, strict=True)])
        assert np.abs(tr.q_rad[:, 1:]).max() > 0.05  # the panel bends a lot
        assert tr.q_rad[-1, 0] > 1.0  # and the hub turns far
        assert np.abs(p_hub - T * tr.t_s).max() < tol * T * tr.t_s[-1]
        free = pp.simulate(model, 1.0, inputs=("strain[0]",), u=np.array([Mp]),
                           actuators=PATCH, output_dt_s=0.01, method=method, rtol=1e-11)
        p_free = np.array([(model.mass_matrix(q) @ v)[0]
                           for q, v in zip(free.q_rad, free.v_rad_s, strict=True)])
        # the hub recoils: its own momentum is what the panel's must cancel
        recoil = np.abs(model.mass_matrix()[0, 0] * free.v_rad_s[:, 0]).max()
        assert np.abs(free.q_rad[:, 1:]).max() > 0.05 and recoil > 0.0
        assert np.abs(p_free).max() < tol * recoil


def test_joint_torques_and_a_patch_settle_at_the_spring_chains_static_angles():
    # clamped chain, no geometric load: K q = B u exactly, whatever the deflection
    model = pp.build_model(BEAM, LENGTHS, SPRINGS)
    u = np.array([0.2, -0.1, 0.5]) * SPRINGS[0]
    tr = pp.simulate(model, 4.0, inputs=("joint_torque[0]", "joint_torque[2]", "strain[0]"),
                     u=u, actuators=(StrainActuator(0.1, 0.5),), damping_ratio=0.3,
                     output_dt_s=0.1)
    # patch 0.1..0.5 m covers joints at 0.25 and 0.5 (an end: half the moment)
    tau = np.array([0.2 + 0.5, 0.5 * 0.5, -0.1]) * SPRINGS[0]
    assert np.allclose(tr.q_rad[-1], tau / SPRINGS, rtol=1e-6)
    assert np.allclose(tr.input_values, u)


def test_small_slew_under_state_feedback_follows_the_exact_linear_closed_loop():
    control = pytest.importorskip("control")
    model = _hub_model()
    lin = pp.linearize(model, inputs=("hub_torque", "strain[0]"), outputs=("hub_angle",),
                       actuators=PATCH, damping_ratio=0.02)
    K, _, _ = control.lqr(lin.to_control(), np.diag([100.0] + [1.0] * 7), np.eye(2))
    x_ref = np.zeros(8)
    x_ref[0] = 1e-4  # small: the nonlinear response is the linear one to ~1e-8
    fb = pp.StateFeedback(K, x_ref=x_ref)
    tr = pp.simulate(model, 2.0, inputs=("hub_torque", "strain[0]"), u=fb, actuators=PATCH,
                     outputs=("hub_angle", "tip_z"), output_dt_s=0.02, damping_ratio=0.02)
    Acl = lin.A - lin.B @ K
    Bcl = lin.B @ K @ x_ref
    x = np.array([scipy.linalg.expm(Acl * t) @ np.linalg.solve(Acl, Bcl) for t in tr.t_s])
    x -= np.linalg.solve(Acl, Bcl)  # x(t) = (e^{At} - I) A^-1 b from rest
    # measured 3e-6 (q) and 1e-5 (v) of each peak, the same at 1e-6 rad: the integrator's
    # error, not the nonlinearity
    assert _peak_error(tr.q_rad, x[:, :4]).max() < 1e-5
    assert _peak_error(tr.v_rad_s, x[:, 4:]).max() < 3e-5
    # the recorded inputs are the controller's at each sample
    assert np.allclose(tr.input_values, -(np.hstack([tr.q_rad, tr.v_rad_s]) - x_ref) @ K.T)


@pytest.mark.parametrize("signal", ["constant", "time", "controller", "feedback"])
def test_exponential_matches_dop853_at_large_motion(signal):
    model = _hub_model()
    J, k = model.mass_matrix()[0, 0], SPRINGS[0]
    K = np.zeros((2, 8))
    # hub servo at about 5 rad/s, damped; a patch moment against joint 0's bending
    K[0, 0], K[0, 4], K[1, 1] = 25.0 * J, 5.0 * J, 0.5 * k
    u0 = np.array([4.0 * J, 0.2 * k])
    u = {"constant": u0,
         "time": lambda t: u0 * np.array([np.sin(20 * t), np.cos(30 * t)]),
         "controller": pp.Controller(lambda t, q, v: -K @ np.concatenate([q, v]) + u0),
         "feedback": pp.StateFeedback(K, u_ref=u0)}[signal]
    kw = dict(inputs=("hub_torque", "strain[0]"), u=u, actuators=PATCH, damping_ratio=0.02,
              outputs=("hub_angle", "tip_z", "q[0]"), output_dt_s=0.01)
    tr = pp.simulate(model, 0.5, **kw)
    ref = pp.simulate(model, 0.5, method="DOP853", rtol=1e-11, **kw)
    assert np.abs(ref.output_values[:, 2]).max() > 0.01
    assert _peak_error(tr.output_values, ref.output_values).max() < 1e-3


def test_recorded_outputs_are_the_tip_and_its_rate():
    model = _hub_model()
    tr = pp.simulate(model, 0.3, inputs=("tip_force_z",), u=lambda t: np.array([np.sin(9 * t)]),
                     outputs=("tip_z", "tip_z_rate", "hub_rate", "spring_torque[1]"),
                     output_dt_s=1e-3, method="DOP853", rtol=1e-11)
    assert np.array_equal(tr.output("tip_z"), tr.tip_position_m[:, 2])
    rate = np.gradient(tr.output("tip_z"), tr.t_s, edge_order=2)
    assert np.abs(tr.output("tip_z_rate") - rate).max() < 1e-4 * np.abs(rate).max()
    assert np.array_equal(tr.output("hub_rate"), tr.v_rad_s[:, 0])
    assert np.allclose(tr.output("spring_torque[1]"), SPRINGS[1] * tr.q_rad[:, 2])
    assert tr.output_units == ("m", "m/s", "rad/s", "N m")


def test_a_tip_force_input_settles_at_the_large_deflection_statics():
    # a dead tip load through the input path, heavily damped, ends at the equilibrium the
    # statics solver (Newton on the planar potential, another algorithm) finds
    model = pp.build_model(BEAM, LENGTHS, SPRINGS)
    F = np.array([0.0, 0.0, -0.3 * SPRINGS[0] / 0.5])  # about 0.3 rad at the root
    tr = pp.simulate(model, 3.0, inputs=("tip_force_z",), u=np.array([F[2]]),
                     damping_ratio=0.5, output_dt_s=0.05, outputs=("tip_z",))
    q_static, tip_static = model.static_deflection(F)
    assert np.abs(q_static).max() > 0.1
    np.testing.assert_allclose(tr.q_rad[-1], q_static, rtol=1e-6, atol=1e-9)
    assert tr.output("tip_z")[-1] == pytest.approx(tip_static[2], rel=1e-6)


@pytest.mark.parametrize("kwargs, field", [
    (dict(u=np.ones(1)), "u: given without inputs"),
    (dict(inputs=("hub_torque",), u=np.ones(2)), "u = "),
    (dict(inputs=("hub_torq",)), "inputs[0]"),
    (dict(inputs=("strain[0]",)), "inputs[0]"),
    (dict(inputs=("strain[0]",), actuators=(StrainActuator(0.5, 2.0),)), "actuators[0]"),
    (dict(inputs=("hub_torque",), u=lambda t: np.array([np.nan])), "u(0"),
    (dict(inputs=("hub_torque",), u=pp.Controller(lambda t, q, v: [1.0, 2.0])), "controller"),
    (dict(inputs=("hub_torque",), u=pp.StateFeedback(np.ones((1, 3)))), "StateFeedback gain"),
    (dict(inputs=("hub_torque",), method="gauss"), "gauss"),
    (dict(outputs=("tip_w",)), "outputs[0]"),
    (dict(actuators=[1.0]), "actuators"),
])
def test_bad_plant_arguments_are_named(kwargs, field):
    with pytest.raises(pp.BeamInputError) as exc:
        pp.simulate(_hub_model(), 0.1, **kwargs)
    assert field in str(exc.value)
