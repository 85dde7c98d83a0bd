"""The compiled batch stepping in blocks of designs (prbdm_pin.simulation.batch_rk and its
kernels) against independent references: each design against its own run of the ordinary
simulate on Pinocchio's dynamics with scipy's DOP853 at the reference tolerances, with blocks of
two designs so that a batch is cut into several blocks stepped apart, the last one padded
(step loads and releases, undamped and damped, both Runge-Kutta pairs, state-feedback gains);
the block order against Pinocchio's frequencies; the polynomial sine and cosine against the C
library's; the compiled tip positions against Pinocchio's frame placements."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from tolerances import EPS, REFERENCE_ATOL, REFERENCE_RTOL

import prbdm_pin as pp
from prbdm_pin.errors import SolveError

BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.03, 0.02], thickness_m=[0.012, 0.006])
RTOL = 1e-8  # the batch's tolerance in these tests
# the global error of a run whose steps each keep rtol (of the peak): the local errors add up
# over the run's periods. On these designs scipy's own DOP853 and RK45, one design at a time,
# land 3.3-8.0 and 6.7-10.3 rtol off the reference; the batch in blocks 1.2-6.4 rtol (a block
# steps no longer than its designs' own runs): bounded at 10 rtol, as test_simulate_batch
BOUND = 10 * RTOL


@pytest.fixture
def blocks_of_two(monkeypatch):
    """Blocks of two designs: five designs make three blocks, the last one padded."""
    from prbdm_pin.simulation import batch_rk

    monkeypatch.setattr(batch_rk, "BLOCK", 2)


def _designs():
    return [pp.build_model(BEAM, lengths, springs) for lengths, springs in (
        ([0.2, 0.3, 0.3, 0.2], [900.0, 1500.0, 700.0]),
        ([0.1, 0.4, 0.3, 0.2], [1200.0, 1000.0, 900.0]),
        ([0.2, 0.2, 0.4, 0.2], [800.0, 2000.0, 600.0]),
        ([0.3, 0.3, 0.2, 0.2], [3000.0, 1100.0, 500.0]),
        ([0.2, 0.3, 0.3, 0.2], [400.0, 700.0, 300.0]))]


def _peak_error(batch, ref):
    return float(np.abs(batch - ref).max() / np.abs(ref).max())


def _check(runs, models, duration, **kw):
    assert runs.vectorised
    for b, m in enumerate(models):
        ref = pp.simulate(m, duration, method="DOP853", rtol=REFERENCE_RTOL,
                          atol=REFERENCE_ATOL, **kw)
        assert np.array_equal(runs.t_s, ref.t_s)
        assert _peak_error(runs.q_rad[b], ref.q_rad) <= BOUND
        assert _peak_error(runs.v_rad_s[b], ref.v_rad_s) <= BOUND
        assert _peak_error(runs.tip_displacement_m[b], ref.tip_displacement_m) <= BOUND


@pytest.mark.parametrize(("method", "damping"), [("DOP853", 0.0), ("DOP853", 0.02),
                                                 ("RK45", 0.02)])
def test_a_step_load_in_blocks_matches_each_designs_own_run(blocks_of_two, method, damping):
    models = _designs()
    kw = dict(tip_force=np.array([0.0, 0.0, -20.0]), output_dt_s=5e-3, damping_ratio=damping)
    runs = pp.simulate_batch(models, 0.1, rtol=RTOL, method=method, **kw)
    _check(runs, models, 0.1, **kw)
    # the blocks step apart: their step counts differ (the softest designs take fewer)
    assert len(set(runs.steps.tolist())) > 1


def test_a_release_in_blocks_matches_each_designs_own_run(blocks_of_two):
    models = _designs()
    kw = dict(q0=[0.1, 0.1, 0.1], output_dt_s=4e-3, damping_ratio=0.0)
    _check(pp.simulate_batch(models, 0.1, rtol=RTOL, **kw), models, 0.1, **kw)


@pytest.mark.parametrize("n", [1, 8])
def test_one_joint_and_eight_joints_match_each_designs_own_run(blocks_of_two, n):
    rng = np.random.default_rng(n)
    models = []
    for _ in range(3):
        w = rng.uniform(0.5, 1.5, n + 1)
        models.append(pp.build_model(BEAM, w / w.sum(), rng.uniform(500.0, 5000.0, n)))
    kw = dict(tip_force=np.array([3.0, 0.0, -20.0]), q0=[0.05] * n, output_dt_s=5e-3,
              damping_ratio=0.02)
    runs = pp.simulate_batch(models, 0.05, rtol=RTOL, **kw)
    for b, m in enumerate(models):
        ref = pp.simulate(m, 0.05, method="DOP853", rtol=REFERENCE_RTOL, atol=REFERENCE_ATOL,
                          **kw)
        alone = pp.simulate(m, 0.05, method="DOP853", rtol=RTOL, **kw)
        for name in ("q_rad", "v_rad_s", "tip_displacement_m"):
            err = _peak_error(getattr(runs, name)[b], getattr(ref, name))
            # the 8R's velocities run more periods of its highest modes: scipy's own DOP853
            # at the same rtol lands up to 11.6 rtol off there (the batch 11.5). A block steps
            # no longer than the design's own run: within 1.5 times its error, or BOUND
            own = _peak_error(getattr(alone, name), getattr(ref, name))
            assert err <= max(BOUND, 1.5 * own)


def test_a_load_varying_in_time_in_blocks_matches_each_designs_own_run(blocks_of_two):
    # a shared function of time: each attempt's stage times evaluated between compiled calls
    models = _designs()[:3]
    kw = dict(tip_force=lambda t: [0.0, 0.0, -200.0 * t], output_dt_s=5e-3,
              damping_ratio=0.02)
    _check(pp.simulate_batch(models, 0.05, rtol=RTOL, **kw), models, 0.05, **kw)


def test_state_feedback_gains_in_blocks_match_each_gains_own_run(blocks_of_two):
    model = _designs()[0]
    gains = [pp.StateFeedback(np.array([[0.0, 0.0, 0.0, g, 0.0, 0.0]]), u_ref=[u])
             for g, u in ((0.0, 1.0), (5.0, 0.0), (20.0, -2.0))]
    kw = dict(q0=[0.05, 0.0, 0.0], inputs=("joint_torque[0]",), damping_ratio=0.02,
              output_dt_s=0.01)
    runs = pp.simulate_batch(model, 0.1, u=gains, rtol=RTOL, **kw)
    assert runs.vectorised
    for b, law in enumerate(gains):
        ref = pp.simulate(model, 0.1, u=law, method="DOP853", rtol=REFERENCE_RTOL,
                          atol=REFERENCE_ATOL, **kw)
        assert _peak_error(runs.q_rad[b], ref.q_rad) <= BOUND


def test_the_blocks_are_ordered_by_the_highest_natural_frequency():
    from prbdm_pin.simulation.batch_rhs import vectorised_plant

    models = _designs()
    n = models[0].n_joints
    o = pp.SimulationOptions(method="DOP853", damping_ratio=0.0)
    plant = vectorised_plant(models, np.zeros((5, n)), o, (), [None] * 5, (), None)
    # Pinocchio's frequencies at the straight pose (crba and a generalised eigensolve)
    top = pp.frequencies_batch(models)[:, -1]
    assert plant.stiffness_order(np.zeros((5, 2 * n))).tolist() == np.argsort(top).tolist()


def test_a_run_that_blows_up_is_refused_at_the_time_it_does():
    models = _designs()[:2]
    with pytest.raises(SolveError, match="no longer finite at t = 0 s"):
        pp.simulate_batch(models, 0.1, v0=[1e200, 0.0, 0.0], output_dt_s=0.01)


def test_a_run_over_its_step_cap_is_refused_naming_it(blocks_of_two):
    with pytest.raises(SolveError, match=r"5 steps reached at t = .* \(max_steps\)"):
        pp.simulate_batch(_designs(), 0.1, tip_force=[0.0, 0.0, -20.0], output_dt_s=0.01,
                          max_steps=5)


def test_the_polynomial_sine_and_cosine_match_the_c_librarys():
    from prbdm_pin.chain.planar_batch_kernel import sincos

    x = np.concatenate((np.linspace(-20.0, 20.0, 4001), [0.0, np.pi / 4, -np.pi / 2, np.pi,
                                                         1e4 + 0.3, -3e5]))
    s, c = np.array([sincos(v) for v in x]).T
    # the Horner sums of terms below 1 and the reduction by pi/2 in two parts: a few roundings
    # of a number below 1 (absolute; near a zero a relative bound means nothing)
    assert np.abs(s - np.sin(x)).max() <= 4 * EPS
    assert np.abs(c - np.cos(x)).max() <= 4 * EPS


def test_the_compiled_tips_match_pinocchios_frame_placements():
    from prbdm_pin.chain.planar_batch_tip import batch_tips

    models = _designs()
    n = models[0].n_joints
    Y = np.random.default_rng(3).uniform(-1.0, 1.0, (5, 4, 2 * n))
    tips = batch_tips(np.array([m.lengths_m for m in models]), Y)
    for b, m in enumerate(models):
        d = m.new_data()
        for t in range(4):
            pin.framesForwardKinematics(m.pin_model, d, Y[b, t, :n])
            ref = d.oMf[m.tip_frame_id].translation
            # a sum of n + 1 lever arms under 1 m each: n + 1 roundings, x4 for sin and cos
            assert np.abs(tips[b, t] - ref).max() <= 4 * (n + 1) * EPS
