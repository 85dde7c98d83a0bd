"""Time response: eigenfrequency, energy conservation, damping ratio, statics, cross-integrator."""

import numpy as np
import pytest

import prbdm_pin.simulation as sim
from prbdm_pin.errors import BeamInputError
from prbdm_pin.geometry import load_beam
from prbdm_pin.model import build_model
from prbdm_pin.simulation import (
    StiffnessSchedule,
    gauss_frequency_ratio,
    mechanical_energy,
    simulate,
)
from prbdm_pin.stiffness import finite_segment_stiffness


@pytest.fixture(scope="module")
def model():
    beam = load_beam("examples/beams/reference-random.json")
    lengths = np.array([0.1, 0.2, 0.2, 0.2, 0.15, 0.15])
    return build_model(beam, lengths, finite_segment_stiffness(beam, lengths))


def _zero_crossings(t, z):
    s = np.flatnonzero(np.sign(z[:-1]) != np.sign(z[1:]))
    return t[s] - z[s] * (t[s + 1] - t[s]) / (z[s + 1] - z[s])


def _mode1_start(model, amplitude_rad=1e-4):
    omega, phi = model.modes()
    return omega, amplitude_rad * phi[:, 0] / np.abs(phi[:, 0]).max()


def test_free_vibration_at_eigenfrequency_and_energy_conserved(model):
    omega, q0 = _mode1_start(model)
    period = 2 * np.pi / omega[0]
    # dense output (quintic Hermite between the steps) resolves the zero crossings
    tr = simulate(model, 100 * period, q0=q0, damping_ratio=0.0, output_dt=period / 200)
    assert tr.method == "gauss" and abs(tr.steps - 4000) <= 1
    z = tr.tip_position_m[:, 2]
    tc = _zero_crossings(tr.t_s, z)
    measured = 2 * (tc[-1] - tc[0]) / (len(tc) - 1)
    assert abs(measured / period - 1) < 1e-3
    # Gauss-Legendre's period error at 20 and 40 steps per period: 1 / ratio - 1 = x^4 / 720
    for spp in (20, 40):
        stated = 1 / gauss_frequency_ratio(2 * np.pi / spp) - 1
        assert stated == pytest.approx((2 * np.pi / spp) ** 4 / 720, rel=0.01)
    coarse = simulate(model, 100 * period, q0=q0, damping_ratio=0.0, output_dt=period / 200,
                      steps_per_period=20)
    tc = _zero_crossings(coarse.t_s, coarse.tip_position_m[:, 2])
    measured20 = 2 * (tc[-1] - tc[0]) / (len(tc) - 1)
    stated20 = 1 / gauss_frequency_ratio(2 * np.pi / 20) - 1
    assert measured20 / period - 1 == pytest.approx(stated20, rel=0.05)
    # energy at the steps themselves (no interpolation): symplectic, no drift
    steps = simulate(model, 100 * period, q0=q0, damping_ratio=0.0)
    e = mechanical_energy(model, steps.q_rad, steps.v_rad_s)
    assert np.abs(e / e[0] - 1).max() <= 1e-6


def test_trapezoidal_free_vibration_period_error(model):
    omega, q0 = _mode1_start(model)
    period = 2 * np.pi / omega[0]
    tr = simulate(model, 20 * period, q0=q0, damping_ratio=0.0, method="trapezoidal")
    assert tr.steps >= 2000
    tc = _zero_crossings(tr.t_s, tr.tip_position_m[:, 2])
    measured = 2 * (tc[-1] - tc[0]) / (len(tc) - 1)
    # stated period error of the trapezoidal rule: (omega dt)^2 / 12 = 3.3e-4 at 100 steps/period
    assert measured / period - 1 == pytest.approx((2 * np.pi / 100) ** 2 / 12, rel=0.02)
    e = mechanical_energy(model, tr.q_rad, tr.v_rad_s)
    assert np.abs(e / e[0] - 1).max() <= 1e-6


def test_dense_output_matches_dop853(model):
    """Samples between the steps (quintic Hermite) against an independent tight integrator."""
    force = 0.01 * model.beam.tip_force_N
    omega = model.natural_frequencies()
    duration = 2 * np.pi / omega[0]
    ref = simulate(model, duration, tip_force=force, method="DOP853", rtol=1e-11,
                   output_dt=duration / 97)
    tr = simulate(model, duration, tip_force=force, output_dt=duration / 97,
                  dt=0.25 / omega[-1])
    assert tr.steps < 97 * 20
    scale = np.abs(ref.q_rad).max()
    np.testing.assert_allclose(tr.q_rad, ref.q_rad, atol=1e-5 * scale)
    np.testing.assert_allclose(tr.v_rad_s, ref.v_rad_s, atol=1e-4 * np.abs(ref.v_rad_s).max())


def test_tip_positions_closed_form_equal_pinocchio(model):
    q = np.array([0.3, -0.2, 0.5, 0.1, -0.4])
    tr = simulate(model, 0.01, q0=q, damping_ratio=0.0, dt=1e-4)
    np.testing.assert_allclose(tr.tip_position_m[0], model.tip_position(q), atol=1e-14)
    np.testing.assert_allclose(tr.tip_position_m[-1], model.tip_position(tr.q_rad[-1]),
                               atol=1e-14)


def test_dop853_free_vibration_frequency(model):
    omega, q0 = _mode1_start(model)
    period = 2 * np.pi / omega[0]
    tr = simulate(model, 10 * period, q0=q0, damping_ratio=0.0, method="DOP853", rtol=1e-10,
                  output_dt=period / 200)
    tc = _zero_crossings(tr.t_s, tr.tip_position_m[:, 2])
    measured = 2 * (tc[-1] - tc[0]) / (len(tc) - 1)
    assert abs(measured / period - 1) < 1e-6
    e = mechanical_energy(model, tr.q_rad, tr.v_rad_s)
    assert np.abs(e / e[0] - 1).max() <= 1e-6


def test_logarithmic_decrement_matches_modal_ratio(model):
    omega, q0 = _mode1_start(model)
    xi = 0.01
    period = 2 * np.pi / omega[0]
    tr = simulate(model, 20 * period, q0=q0, damping_ratio=xi, dt=period / 200)
    z = tr.tip_position_m[:, 2] - model.tip_position()[2]
    # successive maxima of |z| one period apart (parabolic refinement of the sampled peaks)
    i = np.flatnonzero((z[1:-1] > z[:-2]) & (z[1:-1] >= z[2:])) + 1
    a, b, c = z[i - 1], z[i], z[i + 1]
    peaks = b - 0.25 * (a - c) ** 2 / (a - 2 * b + c)
    delta = np.log(peaks[0] / peaks[-1]) / (len(peaks) - 1)
    measured = delta / np.sqrt(4 * np.pi**2 + delta**2)
    assert measured == pytest.approx(xi, rel=2e-3)


def test_step_response_settles_to_static_deflection(model):
    force = model.beam.tip_force_N
    q_static, tip_static = model.static_deflection(force)
    omega = model.natural_frequencies(q_static)
    # damping frozen at the equilibrium: every mode about it decays at exactly its ratio
    tr = simulate(model, 14.0 / (0.2 * omega[0]), tip_force=force, damping_ratio=0.2,
                  damping_pose=q_static)
    deflection = tip_static - model.tip_position()
    np.testing.assert_allclose(tr.tip_position_m[-1], tip_static,
                               atol=1e-4 * np.linalg.norm(deflection))
    np.testing.assert_allclose(tr.q_rad[-1], q_static, atol=1e-4 * np.abs(q_static).max())
    # the undamped-like overshoot of a step: peak deflection near twice the static one
    peak = np.abs(tr.tip_position_m[:, 2] - model.tip_position()[2]).max()
    assert 1.4 * abs(deflection[2]) < peak < 2.0 * abs(deflection[2])


def test_trapezoidal_agrees_with_dop853_under_a_large_step_load(model):
    force = model.beam.tip_force_N
    omega = model.natural_frequencies()
    duration = 3 * 2 * np.pi / omega[0]
    ref = simulate(model, duration, tip_force=force, method="DOP853", rtol=1e-10,
                   output_dt=duration / 300)
    peak = np.abs(ref.tip_displacement_m).max()
    # resolve the highest mode too: the comparison covers the whole response
    for method in ("gauss", "trapezoidal"):
        tr = simulate(model, duration, tip_force=force, output_dt=duration / 300,
                      dt=0.2 / omega[-1], method=method)
        assert np.abs(tr.tip_position_m - ref.tip_position_m).max() < 2e-3 * peak
    # the default steps keep the tip within 1 % of the peak
    for method in ("gauss", "trapezoidal"):
        coarse = simulate(model, duration, tip_force=force, output_dt=duration / 300,
                          method=method)
        err = np.abs(coarse.tip_position_m - ref.tip_position_m).max() / peak
        print(f"{method}: default step, max tip error {err:.2e} of the peak")
        assert err < 1e-2


@pytest.mark.slow
def test_radau_with_analytic_jacobian(model):
    force = model.beam.tip_force_N
    omega = model.natural_frequencies()
    duration = 2 * np.pi / omega[0]
    ref = simulate(model, duration, tip_force=force, method="DOP853", rtol=1e-10,
                   output_dt=duration / 50)
    tr = simulate(model, duration, tip_force=force, method="Radau", rtol=1e-8,
                  output_dt=duration / 50)
    peak = np.abs(ref.tip_displacement_m).max()
    assert np.abs(tr.tip_position_m - ref.tip_position_m).max() < 1e-4 * peak
    assert tr.steps > 0


def test_callable_force_and_sampling(model):
    omega = model.natural_frequencies()
    w = 0.5 * omega[0]
    tr = simulate(model, 0.2, tip_force=lambda t: np.array([0.0, 0.0, -10.0 * np.sin(w * t)]),
                  output_dt=0.01)
    np.testing.assert_allclose(tr.t_s, np.arange(21) * 0.01, atol=1e-12)
    assert tr.q_rad.shape == (21, 5) and tr.tip_position_m.shape == (21, 3)
    assert not tr.t_s.flags.writeable


def test_only_needed_work(model, monkeypatch):
    def forbidden(*args, **kwargs):
        raise AssertionError("not needed")

    monkeypatch.setattr(sim.pin, "computeFrameJacobian", forbidden)
    monkeypatch.setattr(sim, "damping_matrix", forbidden)
    tr = simulate(model, 0.01, q0=np.full(5, 1e-3), damping_ratio=0.0)
    assert tr.steps > 0


def test_stiffness_schedule_interpolates():
    s = StiffnessSchedule(np.array([0.05, 0.15]), np.array([[100.0, 200.0], [300.0, 400.0]]))
    np.testing.assert_allclose(s.at(np.array([0.1, -0.1])), [200.0, 300.0])
    np.testing.assert_allclose(s.at(np.zeros(2)), [100.0, 200.0])
    np.testing.assert_allclose(s.at(np.ones(2)), [300.0, 400.0])


def test_schedule_constant_in_pose_matches_scaled_model(model):
    """A schedule that is one stiffness at every pose is that stiffness's model."""
    k2 = 2.0 * model.stiffness_Nm_per_rad
    sched = StiffnessSchedule(np.array([0.0, 1.0]), np.vstack([k2, k2]))
    q0 = np.full(5, 1e-3)
    a = simulate(model, 0.05, q0=q0, stiffness_schedule=sched, dt=1e-4)
    b = simulate(model.with_stiffness(k2), 0.05, q0=q0, dt=1e-4)
    np.testing.assert_allclose(a.q_rad, b.q_rad, atol=1e-12)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"duration_s": -1.0}, "duration"),
        ({"duration_s": 1.0, "tip_force": [1.0, 2.0]}, "tip_force"),
        ({"duration_s": 1.0, "q0": [0.0]}, "q0"),
        ({"duration_s": 1.0, "damping": "rayleigh"}, "damping"),
        ({"duration_s": 1.0, "method": "euler"}, "method"),
        ({"duration_s": 1.0, "dt": 0.0}, "dt"),
        ({"duration_s": 1.0, "steps_per_period": 0.5}, "steps_per_period"),
        ({"duration_s": 1.0, "damping_ratio": -0.1}, "damping_ratio"),
    ],
)
def test_bad_input(model, kwargs, match):
    with pytest.raises(BeamInputError, match=match):
        simulate(model, **kwargs)
