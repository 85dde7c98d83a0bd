"""The hub model in hybrid coordinates against the closed-form hub-beam frequency equation."""

from dataclasses import FrozenInstanceError

import numpy as np
import pytest
from scipy.optimize import brentq
from tolerances import EPS

from prbdm_pin.errors import BeamInputError
from prbdm_pin.truth import compute_truth
from prbdm_pin.truth.beam import beam_modes
from prbdm_pin.truth.digest import truth_modules
from prbdm_pin.truth.plant import OUTPUT_NAMES, hybrid_model

HUBS = ((0.5, 0.1), (2.0, 0.0), (0.05, 0.3))  # (J_h kg m^2, r m)


@pytest.fixture(scope="module")
def all_modes(narrow, truth_of):
    """Every mode of the 200-element beam: the hybrid model is then the hub + beam FE itself."""
    return truth_of(narrow, model="beam", modes=400, static=False, error_tol_pct=None)


@pytest.fixture(scope="module")
def six_modes(narrow, truth_of):
    return truth_of(narrow, model="beam", modes=6, static=False, error_tol_pct=None)


def _hub_beam_det(beta, beam, J_h, r):
    """Frequency determinant of a uniform Euler-Bernoulli beam clamped at radius r to a hub.

    W = A cos bx + B sin bx + C cosh bx + D sinh bx, unknowns (A, B, C, D, Theta):
    W(0) = r Theta, W'(0) = Theta, W''(L) = W'''(L) = 0, and the hub's balance
    J_h theta'' = EI w''(0) - r EI w'''(0) (the root moment and the root shear's moment about
    the axis) with theta'' = -omega^2 Theta, scaled by EI beta^2.
    """
    L = beam.length_m
    EI = beam.root_EI_Nm2
    rhoA = beam.material.rho_kg_m3 * 2 * beam.half_width_m[0] * beam.thickness_m
    c, s, ch, sh = np.cos(beta * L), np.sin(beta * L), np.cosh(beta * L), np.sinh(beta * L)
    w2 = beta**4 * EI / rhoA
    rows = [[1.0, 0.0, 1.0, 0.0, -r],
            [0.0, beta, 0.0, beta, -1.0],
            [-c, -s, ch, sh, 0.0],
            [s, -c, sh, ch, 0.0],
            [1.0, -r * beta, -1.0, r * beta, -J_h * w2 / (EI * beta**2)]]
    return np.linalg.det(np.array(rows))


def _hub_beam_frequencies(beam, J_h, r, n):
    L = beam.length_m
    EI = beam.root_EI_Nm2
    rhoA = beam.material.rho_kg_m3 * 2 * beam.half_width_m[0] * beam.thickness_m
    b = np.linspace(0.05, 15.0, 6000) / L
    d = np.array([_hub_beam_det(x, beam, J_h, r) for x in b])
    flips = np.flatnonzero(np.sign(d[:-1]) != np.sign(d[1:]))[:n]
    roots = [brentq(_hub_beam_det, b[i], b[i + 1], args=(beam, J_h, r), xtol=1e-14)
             for i in flips]
    return np.array(roots) ** 2 * np.sqrt(EI / rhoA)


@pytest.mark.parametrize(("J_h", "r"), HUBS)
def test_all_mode_hybrid_frequencies_are_the_closed_form_hub_beam(narrow, all_modes, J_h, r):
    ref = _hub_beam_frequencies(narrow, J_h, r, 4)
    h = hybrid_model(all_modes, narrow, J_h, r)
    assert h.frequencies_rad_s[0] == 0.0  # the rigid rotation
    # measured 3e-8 (the 200-element FE); the task asks 1e-4
    np.testing.assert_allclose(h.frequencies_rad_s[1:5], ref, rtol=1e-6)


@pytest.mark.parametrize(("J_h", "r"), HUBS)
def test_truncated_hybrid_converges_from_above(narrow, all_modes, six_modes, J_h, r):
    full = hybrid_model(all_modes, narrow, J_h, r).frequencies_rad_s[1:5]
    six = hybrid_model(six_modes, narrow, J_h, r).frequencies_rad_s[1:5]
    # a Ritz reduction of the full model: from above (to the all-mode solve's rounding, ~1e-8:
    # its K spans omega^2 over ten decades), measured within 9.2e-4
    assert np.all(six >= full * (1 - 1e-7)) and np.all(six / full - 1 < 2e-3)


def test_a_heavy_hub_clamps_the_beam(narrow, six_modes):
    h = hybrid_model(six_modes, narrow, 1e9, 0.1)
    assert h.frequencies_rad_s[0] == 0.0
    np.testing.assert_allclose(h.frequencies_rad_s[1:], six_modes.omega_rad_s, rtol=1e-7)  # 8e-10


def test_state_space_poles_are_the_hub_stiffened_frequencies(narrow, six_modes):
    undamped = hybrid_model(six_modes, narrow, 0.5, 0.1, damping_ratio=0.0)
    lam = np.linalg.eigvals(undamped.A)
    np.testing.assert_allclose(np.sort(np.abs(lam.imag))[::2][1:],
                               undamped.frequencies_rad_s[1:], rtol=1e-9)
    damped = hybrid_model(six_modes, narrow, 0.5, 0.1, damping_ratio=0.02)
    lam = np.linalg.eigvals(damped.A)
    flexible = lam[np.abs(lam) > 1e-6]
    assert np.all(flexible.real < 0.0)
    assert np.sum(np.abs(lam) <= 1e-6) == 2  # the rigid rotation: a double pole at 0, undamped


def test_modal_damping_gives_every_hub_stiffened_mode_its_ratio(narrow, six_modes):
    # the poles of A against the undamped frequencies: -zeta w +- i w sqrt(1 - zeta^2) per mode
    zeta = 0.05
    h = hybrid_model(six_modes, narrow, 0.5, 0.1, damping_ratio=zeta, damping="modal")
    lam = np.linalg.eigvals(h.A)
    flexible = lam[lam.imag > 1e-6]
    w = np.sort(np.abs(flexible))
    np.testing.assert_allclose(w, h.frequencies_rad_s[1:], rtol=1e-9)
    np.testing.assert_allclose(np.sort(-flexible.real / np.abs(flexible)), zeta, rtol=1e-9)
    assert np.sum(np.abs(lam) <= 1e-6) == 2  # the rigid rotation stays undamped
    # the clamped form does not give the hub-stiffened first mode zeta (here 1.9 zeta with the
    # hub raising mode 1 by 1.93 times): why "modal" exists
    c = np.linalg.eigvals(hybrid_model(six_modes, narrow, 0.5, 0.1, damping_ratio=zeta).A)
    first = c[c.imag > 1e-6][np.argmin(np.abs(c[c.imag > 1e-6]))]
    assert abs(-first.real / abs(first) / zeta - 1.0) > 0.5


def test_angular_momentum_about_the_hub_axis(narrow, six_modes):
    # H = first row of M times dq/dt; dH/dt = the external torque about +y: the hub torque, and
    # -(r + L) F_z from a tip force; an actuator's moment pair is internal; the axis accelerated
    # along +z: d'Alembert's -rho A a on the uniform strip at arm r + x, torque
    # rho A a int (r + x) dx = m a (r + L / 2)
    J_h, r = 0.5, 0.1
    h = hybrid_model(six_modes, narrow, J_h, r, actuators=((0.2, 0.6), (0.0, 1.0)))
    n = h.mass.shape[0]
    p = np.concatenate([np.zeros(n), h.mass[0]])
    np.testing.assert_allclose(p @ h.A, 0.0, atol=1e-9 * np.abs(h.A).max())
    torque = p @ h.B
    L = narrow.length_m
    m = narrow.material.rho_kg_m3 * 2 * narrow.half_width_m[0] * narrow.thickness_m * L
    np.testing.assert_allclose(torque, [-(r + L), 1.0, 0.0, 0.0, m * (r + L / 2)], atol=1e-9)


def test_names_shapes_and_outputs(narrow, six_modes):
    h = hybrid_model(six_modes, narrow, 0.5, 0.1, actuators=((0.2, 0.6),))
    assert h.input_names == ("tip_force_z", "hub_torque", "strain[0]", "base_accel_z")
    assert h.output_names == OUTPUT_NAMES == ("tip_z", "tip_z_rate", "hub_angle", "hub_rate")
    n = 7
    assert h.A.shape == (2 * n, 2 * n) and h.B.shape == (2 * n, 4) and h.C.shape == (4, 2 * n)
    assert not h.D.any()
    # a rigid rotation theta about +y lowers the tip by (r + L) theta
    x = np.zeros(2 * n)
    x[0] = 1e-3
    np.testing.assert_allclose(h.C @ x, [-(0.1 + narrow.length_m) * 1e-3, 0.0, 1e-3, 0.0])
    with pytest.raises(FrozenInstanceError):
        h.hub_radius_m = 0.0
    assert not h.A.flags.writeable


def test_plate_hybrid_matches_the_beam_hybrid_on_a_narrow_strip(narrow, six_modes):
    plate = compute_truth(narrow, modes=5, static=False, error_tol_pct=None)
    hp = hybrid_model(plate, narrow, 0.5, 0.1)
    hb = hybrid_model(six_modes, narrow, 0.5, 0.1)
    assert hp.beam_inertia_kg_m2 == pytest.approx(hb.beam_inertia_kg_m2, rel=1e-10)
    # the strip's plate/beam gap: measured 0.24-0.43 %
    np.testing.assert_allclose(hp.frequencies_rad_s[1:], hb.frequencies_rad_s[1:6], rtol=1e-2)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"hub_inertia_kg_m2": -1.0}, "hub_inertia_kg_m2"),
    ({"hub_inertia_kg_m2": np.nan}, "hub_inertia_kg_m2"),
    ({"hub_radius_m": -0.1}, "hub_radius_m"),
    ({"damping_ratio": 1.0}, "damping_ratio"),
    ({"damping_ratio": -0.01}, "damping_ratio"),
    ({"damping": "eq5c"}, "damping"),
    ({"actuators": ((0.5, 1.5),)}, r"actuators\[0\]"),
    ({"actuators": ((0.5, 0.2),)}, r"actuators\[0\]"),
])
def test_bad_hub_inputs_are_refused_by_name(narrow, six_modes, kwargs, match):
    args = {"hub_inertia_kg_m2": 0.5, "hub_radius_m": 0.1, **kwargs}
    with pytest.raises(BeamInputError, match=match):
        hybrid_model(six_modes, narrow, **args)


def test_the_plant_modules_stay_out_of_the_truth_digest():
    # they only read a truth: adding or editing them must not move any truth's cache key
    assert not any("plant" in p.parts for p in truth_modules())


def _linear_field_error(beam):
    """Largest error (m) with which the beam truth's Hermite basis gives back the field x at its
    quadrature points. The field is exact in the Hermite space, but scikit-fem builds the basis
    by inverting each element's Vandermonde matrix in global coordinates (condition up to 5.8e8
    at 200 elements), so it gives x back at those points only to ~6e-11, not to EPS."""
    mesh, basis, *_ = beam_modes(beam, 1)
    u, ux = basis.nodal_dofs
    r1 = np.zeros(basis.N)
    r1[u], r1[ux] = mesh.p[0], 1.0
    return float(np.abs(basis.interpolate(r1) - basis.global_coordinates()[0]).max())


@pytest.mark.parametrize("r", [0.0, 0.1, 0.3])
def test_beam_inertia_about_the_hub_axis_is_the_closed_form(narrow, six_modes, r):
    rhoA = narrow.material.rho_kg_m3 * 2 * narrow.half_width_m[0] * narrow.thickness_m
    L = narrow.length_m
    ref = rhoA * ((r + L) ** 3 - r**3) / 3.0  # int_0^L rho A (r + x)^2 dx
    h = hybrid_model(six_modes, narrow, 1e9, r)
    # the truth integrates rho A (r + x)^2 with its mass matrix over the fields 1 and x, the
    # latter off by up to d (above): to first order the integral moves by at most
    # 2 d int rho A (r + x) dx (1.8e-10 relative at r = 0; 1e-12 to 1.8e-12 measured)
    d = _linear_field_error(narrow)
    rel = 2.0 * d * rhoA * (r * L + 0.5 * L**2) / ref + 8 * EPS
    assert h.beam_inertia_kg_m2 == pytest.approx(ref, rel=rel)
    # J_h + J_beam: one rounding of the sum and one of the reference's (EPS), J_beam's error
    # (1e-9 of the sum here), within the 5 EPS the test allowed (1e-15)
    J = 1e9 + ref
    assert h.mass[0, 0] == pytest.approx(J, rel=5 * EPS + rel * ref / J)
