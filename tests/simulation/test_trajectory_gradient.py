"""Trajectory gradients (``trajectory_gradient``) against central differences of the cost over
whole re-simulated trajectories, and the cost itself against scipy's DOP853 on an independent
right-hand side (Pinocchio's ABA and frame kinematics, the cost integrated as an extra state).

The runs of a central difference take the same fixed steps as the gradient's, so J(p) is the
same smooth function of p on both sides: the difference is off from the gradient only by its own
truncation and rounding (bounded by ``central_difference``: |D(h) - D(2h)| plus 2 noise / h),
plus, for the joint stations, the vector field's own central difference inside the gradient
(``STATION_STEP``: about 1e-10 of the acceleration, bounded below by FIELD_REL)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from central_differences import central_difference
from tolerances import EPS, REFERENCE_ATOL, REFERENCE_RTOL
from trajectory_reference import dop853_cost

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError, InputTypeError

# a tapered strip: the links' masses and inertias move non-linearly with the stations
BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.03, 0.02], thickness_m=0.01)
# the field's station difference: truncation (h / l_min)^2 / 6 with h = EPS^(1/3) m and the
# shortest link l_min = 0.2 m is 1.5e-10, its rounding EPS^(2/3) 4e-11; both relative to the
# accelerations, carried into the gradient with the sensitivities' own amplification (a few)
FIELD_REL = 1e-8


def _rounding(g: pp.TrajectoryGradient) -> float:
    """Absolute rounding of one J: each step's increment rounded at a few EPS of J."""
    return 4.0 * g.trajectory.steps * EPS * abs(g.cost)


def _two_r():
    L, k = np.array([0.2, 0.5, 0.3]), np.array([2500.0, 1200.0])
    return L, k, pp.build_model(BEAM, L, k)


def _three_r():
    L, k = np.array([0.2, 0.3, 0.25, 0.25]), np.array([2500.0, 1200.0, 800.0])
    return L, k, pp.build_model(BEAM, L, k)


COST = pp.QuadraticCost(tip_weight_per_m2=1e4, state_weight=[1.0, 1.0, 1e-4, 1e-4])


def test_damped_release_gradient_in_springs_stations_and_damping_matches_differences():
    L, k, model = _two_r()
    kw = dict(q0=[0.02, -0.01], beta_s=2e-3, joint_damping_Nms_per_rad=[0.3, 0.1], dt_s=5e-4)
    T = 0.06
    g = pp.trajectory_gradient(model, T, COST, parameters=("springs", "stations", "beta",
                                                             "dampers"), **kw)
    assert g.parameter_names == ("k[0]", "k[1]", "x[1]", "x[2]", "beta", "c[0]", "c[1]")
    assert g.parameter_units[:5] == ("N m/rad",) * 2 + ("m",) * 2 + ("s",)

    def J(model=model, **change):
        return pp.trajectory_gradient(model, T, COST, parameters=(), **{**kw, **change}).cost

    # steps of 1e-4 of the springs, stations and beta, 1e-3 of the dampers and gains: where the
    # difference's bound (its truncation, (h/p)^2 (omega T)^2 as J's phase moves with the
    # springs, plus its rounding, 1e-13 J / h) was smallest over steps of 1e-3, 1e-4, 1e-5
    fd, bound = central_difference(lambda kk: J(pp.build_model(BEAM, L, kk)), k, 1e-4 * k,
                                   _rounding(g))
    assert np.all(np.abs(g.gradient[:2] - fd) <= bound), (g.gradient[:2], fd, bound)

    def at_stations(x):
        lengths = np.diff(np.concatenate(([0.0], x, [1.0])))
        return J(pp.build_model(BEAM, lengths, k))

    x = np.cumsum(L)[:-1]
    fd, bound = central_difference(at_stations, x, 2e-5, _rounding(g))  # 1e-4 of 0.2 m
    err = np.abs(g.gradient[2:4] - fd)
    assert np.all(err <= bound + FIELD_REL * np.abs(fd)), (g.gradient[2:4], fd, err, bound)
    fd, bound = central_difference(lambda b: J(beta_s=float(b[0])), [2e-3], 2e-7,
                                   _rounding(g))
    assert abs(g.gradient[4] - fd[0]) <= bound[0], (g.gradient[4], fd, bound)
    fd, bound = central_difference(lambda c: J(joint_damping_Nms_per_rad=c), [0.3, 0.1],
                                   [3e-4, 1e-4], _rounding(g))
    assert np.all(np.abs(g.gradient[5:] - fd) <= bound), (g.gradient[5:], fd, bound)


def test_closed_loop_gradient_in_gain_springs_and_stations_under_a_step_load():
    L, k, model = _three_r()
    G = np.array([[40.0, 10.0, -5.0, 3.0, 0.5, 0.2]])  # N m/rad, N m s/rad on joint 0
    cost = pp.QuadraticCost(tip_weight_per_m2=1e4, effort_weight=1e-2,
                            terminal_tip_weight_per_m2=30.0)
    kw = dict(q0=[0.01, 0.0, -0.01], tip_force=[0.0, 0.0, -3.0],
              inputs=("joint_torque[0]",), beta_s=1e-3, dt_s=4e-4)
    T = 0.04
    g = pp.trajectory_gradient(model, T, cost, feedback=pp.StateFeedback(G),
                               parameters=("springs", "stations", "gain"), **kw)
    assert g.parameter_names[6] == "G[joint_torque[0],q[0]]"
    assert g.parameter_units[6:8] == ("N m/rad", "N m/rad")
    assert g.parameter_units[9] == "N m s/rad"

    def J(model=model, gain=G):
        return pp.trajectory_gradient(model, T, cost, feedback=pp.StateFeedback(gain),
                                      parameters=(), **kw).cost

    assert g.cost == pytest.approx(J(), rel=100 * EPS)  # the same run without sensitivities
    fd, bound = central_difference(lambda kk: J(pp.build_model(BEAM, L, kk)), k, 1e-4 * k,
                                   _rounding(g))
    assert np.all(np.abs(g.gradient[:3] - fd) <= bound), (g.gradient[:3], fd, bound)

    def at_stations(x):
        return J(pp.build_model(BEAM, np.diff(np.concatenate(([0.0], x, [1.0]))), k))

    fd, bound = central_difference(at_stations, np.cumsum(L)[:-1], 2e-5, _rounding(g))
    err = np.abs(g.gradient[3:6] - fd)
    assert np.all(err <= bound + FIELD_REL * np.abs(fd)), (g.gradient[3:6], fd, err, bound)
    steps = 1e-3 * np.maximum(np.abs(G[0]), 1.0)  # 1e-3 of each gain
    fd, bound = central_difference(lambda row: J(gain=row[None]), G[0], steps, _rounding(g))
    assert np.all(np.abs(g.gradient[6:] - fd) <= bound), (g.gradient[6:], fd, bound)


def test_strain_patch_gain_and_stations_match_differences():
    # the patch's map onto the joints moves with the stations
    L, k, model = _two_r()
    patch = pp.StrainActuator(x_start_m=0.1, x_end_m=0.45)
    G = np.array([[2.0, 0.0, 0.5, 0.1]])
    kw = dict(q0=[0.015, 0.0], inputs=("strain[0]",), actuators=(patch,),
              joint_damping_Nms_per_rad=[0.2, 0.2], dt_s=5e-4)
    cost = pp.QuadraticCost(tip_weight_per_m2=1e4, effort_weight=0.1)
    T = 0.05
    x_ref = [0.005, -0.002, 0.0, 0.0]  # a reference pose: u = -G (x - x_ref)
    g = pp.trajectory_gradient(model, T, cost, feedback=pp.StateFeedback(G, x_ref=x_ref),
                               parameters=("stations", "gain"), **kw)

    def J(model=model, gain=G):
        return pp.trajectory_gradient(model, T, cost,
                                      feedback=pp.StateFeedback(gain, x_ref=x_ref),
                                      parameters=(), **kw).cost

    def at_stations(x):
        return J(pp.build_model(BEAM, np.diff(np.concatenate(([0.0], x, [1.0]))), k))

    fd, bound = central_difference(at_stations, np.cumsum(L)[:-1], 2e-5, _rounding(g))
    err = np.abs(g.gradient[:2] - fd)
    assert np.all(err <= bound + FIELD_REL * np.abs(fd)), (g.gradient[:2], fd, err, bound)
    fd, bound = central_difference(lambda row: J(gain=row[None]), G[0], 1e-3, _rounding(g))
    assert np.all(np.abs(g.gradient[2:] - fd) <= bound), (g.gradient[2:], fd, bound)


def test_cost_matches_dop853_within_rk4_richardson_estimate():
    _, _, model = _three_r()
    G = np.array([[40.0, 10.0, -5.0, 3.0, 0.5, 0.2]])
    args = dict(q0=[0.01, 0.0, -0.01], tip_force=[0.0, 0.0, -3.0], inputs=("joint_torque[0]",),
                feedback=pp.StateFeedback(G), beta_s=1e-3,
                joint_damping_Nms_per_rad=[0.1, 0.0, 0.05])
    cost = pp.QuadraticCost(tip_weight_per_m2=1e4, effort_weight=1e-2)
    T = 0.05
    coarse = pp.trajectory_gradient(model, T, cost, parameters=(), **args)
    fine = pp.trajectory_gradient(model, T, cost, parameters=(), dt_s=0.5 * coarse.dt_s,
                                  **args)
    B = np.zeros((3, 1))
    B[0, 0] = 1.0  # joint_torque[0]
    ref = dop853_cost(model, T, [0.01, 0.0, -0.01], B=B, G=G, beta=1e-3, c=[0.1, 0.0, 0.05],
                      force=[0.0, 0.0, -3.0], w_z=1e4, r=1e-2, cost_scale=abs(coarse.cost))
    # RK4's error falls as h^4: |J_h - J| = 16/15 |J_h - J_h/2| to higher order; a factor 2
    # for the next order, plus the reference's own tolerance
    err_estimate = 16.0 / 15.0 * abs(coarse.cost - fine.cost)
    assert abs(coarse.cost - ref) <= 2.0 * err_estimate + 10 * REFERENCE_RTOL * abs(ref), (
        coarse.cost, fine.cost, ref)
    # and the default step is accurate: 1e-4 relative in J at 40 steps per fastest period
    assert abs(coarse.cost - ref) <= 1e-4 * abs(ref)


def test_trajectory_matches_simulate_with_the_same_closed_loop():
    # simulate's DOP853 run of the same loop (dampers as a rate feedback, no own damping)
    _, k, model = _two_r()
    G = np.array([[2.0, 0.0, 0.5, 0.0]])
    g = pp.trajectory_gradient(model, 0.05, COST, q0=[0.02, 0.0], inputs=("joint_torque[0]",),
                               feedback=pp.StateFeedback(G), parameters=(),
                               dt_s=1e-4)
    run = pp.simulate(model, 0.05, q0=[0.02, 0.0], inputs=("joint_torque[0]",),
                      u=pp.StateFeedback(G), damping_ratio=0.0, method="DOP853",
                      rtol=REFERENCE_RTOL, atol=REFERENCE_ATOL)
    tip = g.trajectory.tip_position_m[-1]
    # RK4 at h = 1e-4 s, omega_max h = 0.03: relative error ~ (omega h)^4 T omega / 120 ~ 1e-7
    assert np.allclose(tip, run.tip_position_m[-1], rtol=0.0, atol=1e-7 * 0.02)
    assert np.allclose(g.trajectory.input("joint_torque[0]")[-1],
                       run.input("joint_torque[0]")[-1], rtol=1e-5)  # of the 1e-7 above, over G


def test_start_state_gradient_matches_differences():
    _, _, model = _two_r()
    q0, v0 = np.array([0.02, -0.01]), np.array([0.3, -0.2])
    kw = dict(tip_force=[0.0, 0.0, -1.0], beta_s=1e-3, dt_s=5e-4)
    T = 0.05
    g = pp.trajectory_gradient(model, T, COST, q0=q0, v0=v0, parameters=("initial",), **kw)
    assert g.parameter_names == ("q0[0]", "q0[1]", "v0[0]", "v0[1]")
    assert g.parameter_units == ("rad", "rad", "rad/s", "rad/s")

    def J(x):
        return pp.trajectory_gradient(model, T, COST, q0=x[:2], v0=x[2:], parameters=(),
                                      **kw).cost

    # 1e-6 rad and 1e-5 rad/s: 1e-4 of the start, whose nonlinearity's scale is 1e-2 rad
    fd, bound = central_difference(J, np.concatenate((q0, v0)), [1e-6, 1e-6, 1e-5, 1e-5],
                                   _rounding(g))
    assert np.all(np.abs(g.gradient - fd) <= bound), (g.gradient, fd, bound)


class _NanCost(pp.TrajectoryCost):
    def running(self, t, x, u, z):
        return float("nan") if t > 0.01 else z * z

    def running_partials(self, t, x, u, z):
        return np.zeros_like(x), np.zeros_like(u), 2.0 * z


class _NanPartials(_NanCost):
    def running(self, t, x, u, z):
        return z * z

    def running_partials(self, t, x, u, z):
        return np.full_like(x, np.nan if t > 0.01 else 0.0), np.zeros_like(u), 2.0 * z


def test_bad_input_is_refused_by_name():
    _, _, model = _two_r()
    with pytest.raises(BeamInputError, match="cost = .*running value .*must be finite"):
        pp.trajectory_gradient(model, 0.02, _NanCost(), q0=[0.01, 0.0])
    with pytest.raises(BeamInputError, match="cost = .*running_partials .*must be finite"):
        pp.trajectory_gradient(model, 0.02, _NanPartials(), q0=[0.01, 0.0])
    with pytest.raises(BeamInputError, match="duration_s"):
        pp.trajectory_gradient(model, 0.0, COST)
    with pytest.raises(BeamInputError, match="dt_s"):
        pp.trajectory_gradient(model, 0.02, COST, dt_s=-1e-3)
    with pytest.raises(BeamInputError, match="steps_per_period"):
        pp.trajectory_gradient(model, 0.02, COST, steps_per_period=2.0)
    with pytest.raises(BeamInputError, match="dt_s = .*more than"):
        pp.trajectory_gradient(model, 10.0, COST, dt_s=1e-6)
    with pytest.raises(BeamInputError, match=r"parameters\[1\] = 'lengths'"):
        pp.trajectory_gradient(model, 0.02, COST, parameters=("springs", "lengths"))
    with pytest.raises(BeamInputError, match="StateFeedback gain"):
        pp.trajectory_gradient(model, 0.02, COST, inputs=("joint_torque[0]",),
                               feedback=pp.StateFeedback(np.ones((1, 3))),
                               parameters=("gain",))
    with pytest.raises(BeamInputError, match="'gain' needs a feedback"):
        pp.trajectory_gradient(model, 0.02, COST, parameters=("gain",))
    with pytest.raises(InputTypeError, match="cost"):
        pp.trajectory_gradient(model, 0.02, lambda t: 0.0)
    with pytest.raises(InputTypeError, match="parameters"):
        pp.trajectory_gradient(model, 0.02, COST, parameters="springs")
    with pytest.raises(BeamInputError, match="inputs .*constant map"):
        pp.trajectory_gradient(model, 0.02, COST, inputs=("tip_force_z",))
    with pytest.raises(BeamInputError, match="model: .*clamped planar"):
        pp.trajectory_gradient(pp.build_model(BEAM, [0.2, 0.5, 0.3], [2500.0, 1200.0],
                                              hub=pp.Hub(5.0, 0.1)), 0.02, COST)
    with pytest.raises(BeamInputError, match="joint_damping_Nms_per_rad"):
        pp.trajectory_gradient(model, 0.02, COST, joint_damping_Nms_per_rad=[-1.0, 0.0])
    with pytest.raises(BeamInputError, match="QuadraticCost state_weight"):
        pp.QuadraticCost(state_weight=[[1.0, 2.0], [0.0, 1.0]])
    with pytest.raises(BeamInputError, match="parameter 'k\\[5\\]'"):
        pp.trajectory_gradient(model, 0.01, COST, q0=[0.01, 0.0]).of("k[5]")


def test_chains_at_one_pose_match_pinocchio_per_chain():
    # the moved chains' tips and J^T F in one call, against each chain's Pinocchio frame
    from prbdm_pin.chain.planar import chains_at_pose

    lengths = np.array([[0.2, 0.3, 0.25, 0.25], [0.25, 0.25, 0.3, 0.2], [0.3, 0.2, 0.2, 0.3]])
    q, F = np.array([0.3, -0.5, 0.8]), np.array([1.5, 0.0, -2.0])
    z, jtf = chains_at_pose(lengths, q, F)
    for i, L in enumerate(lengths):
        m = pp.build_model(BEAM, L, [2500.0, 1200.0, 800.0])
        data = m.pin_model.createData()
        pin.framesForwardKinematics(m.pin_model, data, q)
        J = pin.computeFrameJacobian(m.pin_model, data, q, m.tip_frame_id,
                                     pin.LOCAL_WORLD_ALIGNED)[:3]
        # a sum of n terms of order 1 m (1 N m): a few roundings each
        assert abs(z[i] - data.oMf[m.tip_frame_id].translation[2]) <= 16 * EPS
        assert np.allclose(jtf[i], J.T @ F, rtol=0.0, atol=64 * EPS)
