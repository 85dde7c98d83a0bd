"""The free-floating bus model in hybrid coordinates against the closed-form frequency equation
of a uniform free beam carrying a rigid body at one end, its limits (a heavy bus clamps the
beam, a light one frees it) and momentum balance."""

from dataclasses import FrozenInstanceError

import numpy as np
import pytest
from scipy.optimize import brentq
from tolerances import EPS

from prbdm_pin.errors import BeamInputError
from prbdm_pin.truth.plant.bus import BUS_OUTPUT_NAMES, bus_model, rigid_modes

BUSES = ((0.5, 2e-3), (0.02, 1e-5), (3.0, 0.4))  # (m_b kg, I_b kg m^2), the narrow strip ~0.1 kg


@pytest.fixture(scope="module")
def all_modes(narrow, truth_of):
    """Every mode of the 200-element beam: the bus model is then the bus + beam FE itself."""
    return truth_of(narrow, model="beam", modes=400, static=False, error_tol_pct=None)


@pytest.fixture(scope="module")
def six_modes(narrow, truth_of):
    return truth_of(narrow, model="beam", modes=6, static=False, error_tol_pct=None)


def _props(beam):
    rhoA = beam.material.rho_kg_m3 * 2 * beam.half_width_m[0] * beam.thickness_m
    return beam.length_m, beam.root_EI_Nm2, rhoA


def _bus_beam_det(beta, beam, m_b, I_b):
    """Frequency determinant of a uniform Euler-Bernoulli beam, free at x = L, whose end x = 0
    carries a rigid body (mass m_b, inertia I_b about its centre of mass at x = 0).

    W = A cos bx + B sin bx + C cosh bx + D sinh bx. Hamilton's principle with the body's
    kinetic energy m_b w(0)'^2 / 2 + I_b w'(0)'^2 / 2 gives the natural conditions
    EI W'''(0) = m_b omega^2 W(0), EI W''(0) = -I_b omega^2 W'(0), and W''(L) = W'''(L) = 0;
    rows divided by EI beta^3 and EI beta^2.
    """
    L, EI, rhoA = _props(beam)
    w2 = beta**4 * EI / rhoA
    c, s, ch, sh = np.cos(beta * L), np.sin(beta * L), np.cosh(beta * L), np.sinh(beta * L)
    mu = m_b * w2 / (EI * beta**3)
    j = I_b * w2 / (EI * beta)
    rows = [[-mu, -1.0, -mu, 1.0],  # W'''(0) / beta^3 - mu W(0)
            [-1.0, j, 1.0, j],  # W''(0) / beta^2 + j W'(0) / beta
            [-c, -s, ch, sh],  # W''(L) / beta^2
            [s, -c, sh, ch]]  # W'''(L) / beta^3
    return np.linalg.det(np.array(rows))


def _bus_beam_frequencies(beam, m_b, I_b, n):
    L, EI, rhoA = _props(beam)
    b = np.linspace(0.05, 15.0, 6000) / L
    d = np.array([_bus_beam_det(x, beam, m_b, I_b) for x in b])
    flips = np.flatnonzero(np.sign(d[:-1]) != np.sign(d[1:]))[:n]
    roots = [brentq(_bus_beam_det, b[i], b[i + 1], args=(beam, m_b, I_b), xtol=1e-14)
             for i in flips]
    return np.array(roots) ** 2 * np.sqrt(EI / rhoA)


@pytest.mark.parametrize(("m_b", "I_b"), BUSES)
def test_all_mode_bus_frequencies_are_the_closed_form_free_beam_with_a_body(
        narrow, all_modes, m_b, I_b):
    ref = _bus_beam_frequencies(narrow, m_b, I_b, 4)
    h = bus_model(all_modes, narrow, m_b, I_b)
    assert np.all(h.frequencies_rad_s[:2] == 0.0)  # the rigid translation and rotation
    # the 200-element FE against the continuum: the hub model's measured 3e-8 (same mesh)
    np.testing.assert_allclose(h.frequencies_rad_s[2:6], ref, rtol=1e-6)


def test_the_limits_clamp_and_free_the_beam(narrow, all_modes, six_modes):
    heavy = bus_model(six_modes, narrow, 1e9, 1e9)
    # a bus 1e10 times the beam: the clamped frequencies to the mass ratio (1e-10, measured
    # below 1e-9 with the solve's rounding)
    np.testing.assert_allclose(heavy.frequencies_rad_s[2:], six_modes.omega_rad_s, rtol=1e-7)
    L, EI, rhoA = _props(narrow)
    light = bus_model(all_modes, narrow, 1e-9, 1e-12).frequencies_rad_s[2:5]
    # the free-free beam: beta L = 4.7300408, 7.8532046, 10.9956078 (the roots of
    # cos x cosh x = 1); the bus's residual mass is 1e-8 of the beam's
    free = np.array([4.7300408, 7.8532046, 10.9956078]) ** 2 / L**2 * np.sqrt(EI / rhoA)
    np.testing.assert_allclose(light, free, rtol=1e-6)


def test_momentum_balance(narrow, six_modes):
    # linear momentum along z = first row of M times dq/dt; angular momentum about the bus's
    # centre of mass = second row: their rates are the external force and torque alone
    h = bus_model(six_modes, narrow, 0.5, 2e-3, root_m=0.05, actuators=((0.2, 0.6),))
    n = h.mass.shape[0]
    for row, external in ((0, [1.0, 1.0, 0.0, 0.0]),
                          (1, [-(0.05 + narrow.length_m), 0.0, 1.0, 0.0])):
        p = np.concatenate([np.zeros(n), h.mass[row]])
        # exact structure up to the solve's rounding against M's largest entries
        np.testing.assert_allclose(p @ h.A, 0.0, atol=1e-9 * np.abs(h.A).max())
        np.testing.assert_allclose(p @ h.B, external, atol=1e-9)


def test_modal_damping_gives_every_flexible_mode_its_ratio(narrow, six_modes):
    zeta = 0.05
    h = bus_model(six_modes, narrow, 0.5, 2e-3, damping_ratio=zeta)
    lam = np.linalg.eigvals(h.A)
    flexible = lam[lam.imag > 1e-6]
    np.testing.assert_allclose(np.sort(np.abs(flexible)), h.frequencies_rad_s[2:], rtol=1e-9)
    np.testing.assert_allclose(-flexible.real / np.abs(flexible), zeta, rtol=1e-9)
    assert np.sum(np.abs(lam) <= 1e-6) == 4  # two rigid motions: double poles at 0, undamped


def test_rigid_modes_are_mass_orthonormal_and_solve_the_pencil():
    rng = np.random.default_rng(3)
    X = rng.standard_normal((6, 6))
    M = X @ X.T + 6 * np.eye(6)
    w2 = np.array([4.0, 9.0, 30.0, 50.0])
    omega, Phi = rigid_modes(M, w2)
    K = np.diag(np.concatenate([[0.0, 0.0], w2]))
    # a 6 x 6 pencil of norm ~20 and condition ~10: a few hundred roundings of 1
    np.testing.assert_allclose(Phi.T @ M @ Phi, np.eye(6), atol=1000 * EPS)
    np.testing.assert_allclose(K @ Phi, M @ Phi * omega**2, atol=1e-10)
    # another algorithm: the generalised symmetric eigensolver on the whole pencil
    ref = np.sqrt(np.clip(np.linalg.eigvalsh(np.linalg.solve(np.linalg.cholesky(M),
                                                             np.linalg.solve(
                                                                 np.linalg.cholesky(M), K).T)),
                          0.0, None))
    np.testing.assert_allclose(omega[2:], np.sort(ref)[2:], rtol=1e-10)


def test_names_and_bad_input(narrow, six_modes):
    h = bus_model(six_modes, narrow, 0.5, 2e-3, actuators=((0.2, 0.6),))
    assert h.input_names == ("tip_force_z", "bus_force_z", "bus_torque_y", "strain[0]")
    assert h.output_names == BUS_OUTPUT_NAMES
    with pytest.raises(FrozenInstanceError):
        h.bus_mass_kg = 1.0
    for kwargs, field in (({"bus_mass_kg": 0.0}, "bus_mass_kg"),
                          ({"bus_inertia_kg_m2": -1.0}, "bus_inertia_kg_m2"),
                          ({"bus_mass_kg": "heavy"}, "bus_mass_kg"),
                          ({"root_m": float("nan")}, "root_m")):
        args = {"bus_mass_kg": 0.5, "bus_inertia_kg_m2": 2e-3, "root_m": 0.0} | kwargs
        with pytest.raises(BeamInputError, match=field):
            bus_model(six_modes, narrow, **args)
