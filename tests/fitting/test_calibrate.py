"""calibrate: E, rho and modal damping of a 5R chain fitted to a ring-down of the scaled 1D beam
truth (its modal model, stepped by the matrix exponential: ``ring_down_truth``), the ring-down
basis against the matrix exponential and its derivatives against central differences, and the
refusals (E with rho from a ring-down, bad data)."""

import numpy as np
import pytest
import scipy.linalg as sla
from central_differences import central_difference
from ring_down_truth import truth_ring_down
from tolerances import EPS

from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.model_source import load_model
from prbdm_pin.fitting.calibrate import calibrate
from prbdm_pin.fitting.calibration_basis import ring_basis
from prbdm_pin.fitting.calibration_data import ring_down
from prbdm_pin.fitting.calibration_problem import Problem
from prbdm_pin.truth.plant import clamped_model

S_E, S_RHO, ZETA = 1.07, 0.96, np.array([0.012, 0.006])
ETA0 = np.array([0.05, 0.01, 0.0, 0.3])  # modal coordinates (sqrt(kg) m) and rates


@pytest.fixture(scope="module")
def chain(strip_fit):
    # a 5R eigen fit: its five frequencies are the truth's (fit.json), so the data's only
    # departure from the chain is the noise (the shapes' gains go into the amplitudes)
    return load_model(strip_fit(5) / "fit" / "fit.json").model


@pytest.fixture(scope="module")
def plant(narrow, truth_of):
    return clamped_model(truth_of(narrow, model="beam", modes=4, static=False,
                                  error_tol_pct=None), narrow, damping_ratio=0.0)


def test_the_chain_has_the_truth_s_frequencies(chain, plant):
    import prbdm_pin as pp

    lin = pp.linearize(chain, damping_ratio=0.0)
    w = np.sqrt(sla.eigh(lin.stiffness_Nm_per_rad, lin.mass_kg_m2, eigvals_only=True))
    # the eigen fit's objective is these errors; measured 1e-14: 1e-9 is far below the
    # calibration's statistical error (1e-5 of E) that the trials below test
    np.testing.assert_allclose(w[:2], plant.frequencies_rad_s[:2], rtol=1e-9)


def test_the_ring_basis_is_the_matrix_exponential_s_response():
    w, z = np.array([50.0, 310.0]), np.array([0.02, 0.005])
    t = np.arange(500) / 250.0
    cq, cv = np.array([[1.0, -0.4], [0.0, 0.0]]), np.array([[0.0, 0.0], [1.0, 2.0]])
    x0 = np.array([0.3, -0.1, 2.0, 5.0])
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.diag(w**2), -np.diag(2 * z * w)]])
    X = np.array([sla.expm(A * ti) @ x0 for ti in t])
    want = np.column_stack([X[:, :2] @ cq[0], X[:, 2:] @ cv[1]])
    # eta = a g + b h: a = eta(0), b = (eta'(0) + sigma eta(0)) / w_d
    sigma, wd = z * w, w * np.sqrt(1 - z**2)
    coef = np.ravel(np.column_stack([x0[:2], (x0[2:] + sigma * x0[:2]) / wd]))
    got = ring_basis(t, w, z, cq, cv) @ coef
    # expm of |A t| up to 1.2e3: its relative error grows with the norm (scaling and squaring,
    # ~ EPS |A t| per entry, Higham 2005); the rate reads omega times the coordinate
    scale = np.abs(want).max(axis=0)
    np.testing.assert_allclose(got, want, rtol=0, atol=4 * EPS * 1.2e3 * scale.max())


def test_the_basis_derivatives_are_central_differences():
    t = np.arange(300) / 250.0
    w, z = np.array([50.0, 310.0]), np.array([0.02, 0.005])
    cq, cv = np.array([[1.0, -0.4]]), np.array([[0.3, 0.1]])
    _, dBw, dBz = ring_basis(t, w, z, cq, cv, derivatives=True)
    for k in range(2):
        for which, d in (("w", dBw), ("z", dBz)):
            def f(x, k=k, which=which):
                ww, zz = w.copy(), z.copy()
                (ww if which == "w" else zz)[k] = x[0]
                return ring_basis(t, ww, zz, cq, cv)[:, :, 2 * k:2 * k + 2]
            x = np.array([(w if which == "w" else z)[k]])
            h = 1e-4 * x  # truncation ~ (t omega h)^2: below the bound's own estimate
            # values reach omega |cv| ~ 100, and the phase w_d t (up to 372 rad) is rounded
            # to EPS of itself: each value carries ~ EPS 372 100 (x4 for the sums)
            noise = 4 * EPS * 100.0 * w.max() * t.max()
            D, bound = central_difference(f, x, h, noise)
            np.testing.assert_array_less(np.abs(d[:, :, 2 * k:2 * k + 2] - D[..., 0]),
                                         bound[..., 0] + noise)


def test_the_parameter_jacobian_is_central_differences(chain):
    from prbdm_pin.fitting.calibrate import _chain_modes

    t = np.arange(400) / 250.0
    w0, cq, cv = _chain_modes(chain, ("tip_z", "tip_z_rate"))
    y = np.ones(t.size * 2)
    names = ("E", "rho", "damping[0]", "damping[1]")
    prob = Problem(names, t, y, np.array([1.0, 0.01]), w0[:2], cq[:, :2], cv[:, :2],
                   np.full(2, 0.02), (1,))
    x = np.array([1.1, 0.9, 0.015, 0.007])
    B, c, dy = prob.model_jacobian(x)
    # each value's rounding: EPS of the phase omega t (module test above) times its size
    noise = 4 * EPS * np.abs(B @ c).max() * prob.omega0.max() * 1.1 * t.max()
    D, bound = central_difference(lambda v: prob.basis(v) @ c, x, 1e-4 * x, noise)
    np.testing.assert_array_less(np.abs(dy - D), bound + noise)


def _data(plant, seed, T=2.0, noise=0.02):
    t = np.arange(int(T * 250)) / 250.0  # 250 Hz
    y = truth_ring_down(plant, S_E, S_RHO, ZETA, t, ETA0)
    rng = np.random.default_rng(seed)
    return ring_down(t, y + noise * np.abs(y).max() * rng.standard_normal(y.shape), ["tip_z_m"])


def test_recovered_parameters_lie_within_two_standard_errors(chain, plant, narrow):
    # a ring-down sees E/rho: with rho held the fitted E is E0 s_E / s_rho (ring_down_truth)
    want = np.r_[narrow.material.E_Pa * S_E / S_RHO, ZETA]
    hits = np.zeros(3, dtype=int)
    for seed in range(50):
        r = calibrate(chain, _data(plant, seed), ["E", "damping[0]", "damping[1]"])
        hits += np.abs(r.values - want) <= 2.0 * r.std_errors
    # 2 sigma holds 95.4 % of Gaussian errors: at least 90 % of 50 (the target)
    assert np.all(hits >= 45), hits


def test_rho_alone_is_fitted_as_rho0_s_rho_over_s_e(chain, plant, narrow):
    r = calibrate(chain, _data(plant, 7), "rho,damping[0]", n_modes=2)
    want = narrow.material.rho_kg_m3 * S_RHO / S_E
    # one seed: a 3-sigma miss has probability 0.3 %
    assert abs(r.values[0] - want) <= 3.0 * r.std_errors[0], (r.values[0], want)
    assert r.model.beam.material.rho_kg_m3 == r.values[0]
    assert r.residual_rms["tip_z"] > 0


def test_e_with_rho_from_a_ring_down_is_refused_naming_both(chain, plant):
    with pytest.raises(BeamInputError, match=r"E, rho not determined.*E/rho only"):
        calibrate(chain, _data(plant, 0), ["E", "rho", "damping[0]"])


@pytest.mark.parametrize("edit, needle", [
    (lambda t, y: (t, np.where(np.arange(t.size) == 5, np.nan, y.T).T), r"tip_z_m: not finite "
                                                                         r"at row 5"),
    (lambda t, y: (np.r_[t[:3], t[1:]][:t.size], y), r"t_s: not increasing at row 3"),
    (lambda t, y: (t[:5], y[:5]), r"t_s: 5 samples; need at least 8"),
])
def test_bad_data_is_refused_naming_the_field(edit, needle):
    t = np.arange(20) / 100.0
    y = np.cos(50 * t)[:, None]
    with pytest.raises(BeamInputError, match=needle):
        ring_down(*edit(t, y), ["tip_z_m"])


def test_too_few_samples_for_the_unknowns_and_bad_names_are_refused(chain):
    t = np.arange(8) / 100.0
    data = ring_down(t, np.cos(50 * t), ["tip_z"])
    with pytest.raises(BeamInputError, match=r"t_s: 8 samples x 1 channel\(s\) for 9 unknowns"):
        calibrate(chain, data, ["E", "damping[0]", "damping[1]"], n_modes=3)
    with pytest.raises(BeamInputError, match=r"parameters\[1\] = 'nu'"):
        calibrate(chain, data, ["E", "nu"])
    with pytest.raises(BeamInputError, match=r"n_modes = 0: must be an integer >= 1"):
        calibrate(chain, data, ["E"], n_modes=0)
    with pytest.raises(BeamInputError, match=r"damping\[5\] is mode 6's; the model has 5"):
        calibrate(chain, data, ["damping[5]"])


def test_a_sensor_offset_is_recovered_with_e(chain, plant, narrow):
    clean = _data(plant, 11)
    off = 0.1 * np.abs(clean.y).max()  # a zero of the sensor 10 % of the peak off
    data = ring_down(clean.t_s, clean.y + off, ["tip_z_m"])
    r = calibrate(chain, data, ["E", "offset[tip_z_m]", "damping[0]"], n_modes=2)
    want = [narrow.material.E_Pa * S_E / S_RHO, off, ZETA[0]]
    # one seed: a 3-sigma miss has probability 0.3 % per parameter
    np.testing.assert_array_less(np.abs(r.values - want), 3 * r.std_errors)
    with pytest.raises(BeamInputError, match=r"parameters\[1\] = 'offset\[tip_x\]': no channel"):
        calibrate(chain, data, ["E", "offset[tip_x]"])


def test_the_rayleigh_jacobian_is_central_differences(chain):
    from prbdm_pin.fitting.calibrate import _chain_modes

    t = np.arange(400) / 250.0
    w0, cq, cv = _chain_modes(chain, ("tip_z",))
    prob = Problem(("E", "rayleigh_alpha", "rayleigh_beta"), t, np.ones(t.size),
                   np.array([1.0]), w0[:2], cq[:, :2], cv[:, :2], np.full(2, 0.02))
    x = np.array([1.1, 0.8, 3e-5])
    B, c, dy = prob.model_jacobian(x)
    # rounding as the parameter test above (the phase omega t)
    noise = 4 * EPS * np.abs(B @ c).max() * prob.omega0.max() * 1.1 * t.max()
    D, bound = central_difference(lambda v: prob.basis(v) @ c, x, 1e-4 * x, noise)
    np.testing.assert_array_less(np.abs(dy - D), bound + noise)


def test_rayleigh_damping_is_recovered(chain, plant, narrow):
    alpha, beta = 0.9, 3.0e-5  # 1/s, s
    w = plant.frequencies_rad_s[:2] * np.sqrt(S_E / S_RHO)
    zeta = alpha / (2 * w) + beta * w / 2  # C = alpha M + beta K on the truth's modes
    t = np.arange(500) / 250.0
    y = truth_ring_down(plant, S_E, S_RHO, zeta, t, ETA0)
    y = y + 0.02 * np.abs(y).max() * np.random.default_rng(5).standard_normal(y.shape)
    r = calibrate(chain, ring_down(t, y, ["tip_z"]), "E,rayleigh_alpha,rayleigh_beta")
    want = [narrow.material.E_Pa * S_E / S_RHO, alpha, beta]
    # one seed: a 3-sigma miss has probability 0.3 % per parameter
    np.testing.assert_array_less(np.abs(r.values - want), 3 * r.std_errors)
    with pytest.raises(BeamInputError, match="two damping forms"):
        calibrate(chain, ring_down(t, y, ["tip_z"]), "E,rayleigh_alpha,damping[0]")
