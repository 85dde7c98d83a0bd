"""simulate_batch against each design's own run: the ordinary simulate on Pinocchio's dynamics
with scipy's DOP853 at the reference tolerances, for batches of designs (springs, lengths),
of state-feedback gains and of start states; the loop over designs (hub models); bad input."""

from __future__ import annotations

import numpy as np
import pytest
from tolerances import REFERENCE_ATOL, REFERENCE_RTOL

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError, InputTypeError

BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.03, 0.02], thickness_m=[0.012, 0.006])
RTOL = 1e-8  # the batch's tolerance in these tests
# the global error of a run whose steps each keep rtol (of the peak): the local errors add up
# over the run's periods. scipy's own DOP853 at the same rtol (the loop over hub designs below)
# lands 2.8 rtol off its reference, the batch 1.2-1.3 rtol: bounded at 10 rtol
BOUND = 10 * RTOL


def _reference(model, duration, **kw):
    return pp.simulate(model, duration, method="DOP853", rtol=REFERENCE_RTOL,
                       atol=REFERENCE_ATOL, **kw)


def _designs():
    return [pp.build_model(BEAM, lengths, springs) for lengths, springs in (
        ([0.2, 0.3, 0.3, 0.2], [900.0, 1500.0, 700.0]),
        ([0.1, 0.4, 0.3, 0.2], [1200.0, 1000.0, 900.0]),
        ([0.2, 0.2, 0.4, 0.2], [800.0, 2000.0, 600.0]))]


def _peak_error(batch_q, ref_q):
    return float(np.abs(batch_q - ref_q).max() / np.abs(ref_q).max())


def test_each_design_of_a_batch_under_a_step_load_matches_its_own_run():
    models = _designs()
    F = np.array([0.0, 0.0, -20.0])
    runs = pp.simulate_batch(models, 0.1, tip_force=F, output_dt_s=5e-3, rtol=RTOL,
                             damping_ratio=0.02)
    assert runs.vectorised and runs.q_rad.shape == (3, 21, 3)
    for b, m in enumerate(models):
        ref = _reference(m, 0.1, tip_force=F, output_dt_s=5e-3, damping_ratio=0.02)
        assert np.array_equal(runs.t_s, ref.t_s)
        assert _peak_error(runs.q_rad[b], ref.q_rad) <= BOUND
        assert _peak_error(runs.v_rad_s[b], ref.v_rad_s) <= BOUND
        assert _peak_error(runs.tip_displacement_m[b], ref.tip_displacement_m) <= BOUND


def test_the_dormand_prince_5_4_pair_and_its_own_interpolant():
    models = _designs()
    runs = pp.simulate_batch(models, 0.1, q0=[0.05, 0.0, -0.05], output_dt_s=2e-3, rtol=RTOL,
                             method="RK45", damping_ratio=0.02)
    assert runs.vectorised and runs.method == "RK45"
    for b, m in enumerate(models):
        ref = _reference(m, 0.1, q0=[0.05, 0.0, -0.05], output_dt_s=2e-3, damping_ratio=0.02)
        assert _peak_error(runs.q_rad[b], ref.q_rad) <= BOUND


def test_per_design_start_states_forces_and_the_step_samples():
    models = _designs()
    q0 = np.array([[0.1, 0.0, -0.1], [0.0, 0.2, 0.0], [0.05, 0.05, 0.05]])
    F = np.array([[5.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 3.0, -8.0]])
    runs = pp.simulate_batch(models, 0.2, q0=q0, v0=[1.0, 0.0, 0.0], tip_force=F, rtol=RTOL,
                             damping_ratio=0.0)
    # no output grid: a sample at every shared step
    assert runs.t_s.size == runs.steps[0] + 1
    for b, m in enumerate(models):
        ref = _reference(m, 0.2, q0=q0[b], v0=[1.0, 0.0, 0.0], tip_force=F[b],
                         damping_ratio=0.0, output_dt_s=0.2)
        assert _peak_error(runs.q_rad[b, -1], ref.q_rad[-1]) <= BOUND
        assert np.allclose(runs.q_rad[b, 0], q0[b], rtol=0.0, atol=0.0)


def test_a_batch_of_state_feedback_gains_on_one_model():
    model = _designs()[0]
    gains = [pp.StateFeedback(np.array([[0.0, 0.0, 0.0, g, 0.0, 0.0]]), u_ref=[u])
             for g, u in ((0.0, 1.0), (5.0, 0.0), (20.0, -2.0))]
    kw = dict(q0=[0.05, 0.0, 0.0], inputs=("joint_torque[0]",), damping_ratio=0.0,
              output_dt_s=0.01)
    runs = pp.simulate_batch(model, 0.2, u=gains, rtol=RTOL, **kw)
    assert runs.vectorised
    for b, law in enumerate(gains):
        ref = _reference(model, 0.2, u=law, **kw)
        assert _peak_error(runs.q_rad[b], ref.q_rad) <= BOUND


def test_a_tip_force_input_with_a_shared_function_of_time():
    models = _designs()[:2]
    kw = dict(inputs=("tip_force_z",), u=lambda t: [-10.0 * np.sin(40.0 * t)],
              tip_force=lambda t: [0.0, 0.0, -2.0 * t], output_dt_s=0.01, damping_ratio=0.05)
    runs = pp.simulate_batch(models, 0.2, rtol=RTOL, **kw)
    assert runs.vectorised
    for b, m in enumerate(models):
        ref = _reference(m, 0.2, **kw)
        assert _peak_error(runs.q_rad[b], ref.q_rad) <= BOUND


def test_designs_the_closed_form_does_not_carry_are_looped_through_simulate():
    hubs = [pp.build_model(BEAM, [0.2, 0.5, 0.3], [2500.0 * s, 1200.0], hub=pp.Hub(5.0))
            for s in (1.0, 2.0)]
    runs = pp.simulate_batch(hubs, 0.1, q0=[0.0, 0.02, 0.0], output_dt_s=0.01, rtol=RTOL,
                             damping_ratio=0.0)
    assert not runs.vectorised and runs.q_rad.shape == (2, 11, 3)
    for b, m in enumerate(hubs):
        ref = _reference(m, 0.1, q0=[0.0, 0.02, 0.0], output_dt_s=0.01, damping_ratio=0.0)
        assert _peak_error(runs.q_rad[b], ref.q_rad) <= BOUND
        one = runs.design(b)
        assert one.q_rad.shape == (11, 3) and one.steps == runs.steps[b]


def test_a_controller_or_a_pose_input_is_looped_through_simulate():
    models = _designs()[:2]
    damper = pp.Controller(lambda t, q, v: -2.0 * v[:1])
    for kw in (dict(inputs=("joint_torque[0]",), u=damper),
               dict(inputs=("tip_moment_y",), u=[0.5])):
        runs = pp.simulate_batch(models, 0.05, q0=[0.05, 0.0, 0.0], output_dt_s=0.01,
                                 rtol=RTOL, damping_ratio=0.0, **kw)
        assert not runs.vectorised
        for b, m in enumerate(models):
            ref = _reference(m, 0.05, q0=[0.05, 0.0, 0.0], output_dt_s=0.01,
                             damping_ratio=0.0, **kw)
            assert _peak_error(runs.q_rad[b], ref.q_rad) <= BOUND


def test_bad_batches_are_refused_naming_the_argument():
    models = _designs()
    two = pp.build_model(BEAM, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    with pytest.raises(BeamInputError, match=r"models\[1\]: 2 joints .* the batch has 3"):
        pp.simulate_batch([models[0], two], 0.1)
    hub = pp.build_model(BEAM, [0.2, 0.3, 0.3, 0.2], [900.0, 1500.0, 700.0],
                         hub=pp.Hub(5.0))
    with pytest.raises(BeamInputError, match=r"models\[1\]"):
        pp.simulate_batch([models[0], hub], 0.1)
    with pytest.raises(BeamInputError, match="models: the batch is empty"):
        pp.simulate_batch([], 0.1)
    with pytest.raises(InputTypeError, match=r"models\[1\]"):
        pp.simulate_batch([models[0], "beam.json"], 0.1)
    bad_gain = [pp.StateFeedback(np.zeros((1, 6))), pp.StateFeedback(np.zeros((1, 4)))]
    with pytest.raises(BeamInputError, match=r"u\[1\]: StateFeedback gain"):
        pp.simulate_batch(models[0], 0.1, inputs=("joint_torque[0]",), u=bad_gain)
    with pytest.raises(BeamInputError, match=r"models: 3 models for 2 signals"):
        pp.simulate_batch(models, 0.1, inputs=("joint_torque[0]",), u=bad_gain[:1] * 2)
    with pytest.raises(BeamInputError, match=r"q0 has shape \(2, 3\)"):
        pp.simulate_batch(models, 0.1, q0=np.zeros((2, 3)))
    with pytest.raises(BeamInputError, match=r"tip_force has shape \(2,\)"):
        pp.simulate_batch(models, 0.1, tip_force=[0.0, 1.0])
    for rtol in (1e-15, 0.5):
        with pytest.raises(BeamInputError, match=r"rtol = .*: must be in \(1e-14, 0\.1\)"):
            pp.simulate_batch(models, 0.1, rtol=rtol)
    with pytest.raises(BeamInputError, match="inputs = 'tip_force_z': must be a non-empty"):
        pp.simulate_batch([hub, hub], 0.1, inputs="tip_force_z")
    with pytest.raises(BeamInputError, match="output_dt_s: these designs"):
        pp.simulate_batch([hub, hub], 0.1)
    runs = pp.simulate_batch(models[:1], 0.01, rtol=1e-6)
    with pytest.raises(BeamInputError, match="index = 1: the batch has 1 designs"):
        runs.design(1)
