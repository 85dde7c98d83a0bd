"""The clamped truth plant against the uniform cantilever's closed-form statics and modal tip
FRF, and the hub model's coupled-mode damping against the eigenvalues of its state matrix."""


import numpy as np
import pytest
from tolerances import EPS, hermite_basis_cond

from prbdm_pin.errors import BeamInputError
from prbdm_pin.simulation.response import euler_bernoulli_modal_tip, modal_frf
from prbdm_pin.truth.beam import beam_stations
from prbdm_pin.truth.plant import clamped_model, hybrid_model


@pytest.fixture(scope="module")
def all_modes(narrow, truth_of):
    """Every mode of the 200-element beam: the modal sum is the finite-element statics, and
    cubic Hermite elements are exact at the nodes under nodal loads."""
    return truth_of(narrow, model="beam", modes=400, static=False, error_tol_pct=None)


@pytest.fixture(scope="module")
def six_modes(narrow, truth_of):
    return truth_of(narrow, model="beam", modes=6, static=False, error_tol_pct=None)


def _static_gain(plant):
    """y = -C A^-1 B u at rest: the plant's static gain (outputs x inputs)."""
    return -plant.C @ np.linalg.solve(plant.A, plant.B)


def test_all_mode_static_gains_are_the_euler_bernoulli_cantilever(narrow, all_modes):
    xa, xb = 0.2, 0.6  # element nodes of the 200-element mesh
    plant = clamped_model(all_modes, narrow, actuators=((xa, xb),))
    assert plant.input_names == ("tip_force_z", "strain[0]", "base_accel_z")
    assert plant.output_names == ("tip_z", "tip_z_rate")
    L, EI = narrow.length_m, narrow.root_EI_Nm2
    rhoA = narrow.material.rho_kg_m3 * 2 * narrow.half_width_m[0] * narrow.thickness_m
    G = _static_gain(plant)
    # a tip force: L^3 / 3EI; a moment pair M on [xa, xb]: w'' = -M / EI there, so the tip
    # drops by M (xb - xa)(L - (xa + xb) / 2) / EI; rates settle to 0
    # rtol: the Hermite basis comes from inverting each element's Vandermonde matrix (condition
    # c up to 5.8e8 here), so every element matrix is off by up to EPS c = 1.3e-7 relative and
    # the statics with it (compliance is first order in the elements' stiffness); the modal
    # sum of all modes (eigenvectors of a stiffness of condition 3.7e10) adds its own rounding
    # of the same size: 2 EPS c (measured 4e-9 to 6.4e-8 across BLAS kernels)
    c = hermite_basis_cond(beam_stations(narrow))
    # the clamp accelerated along +z: relative to it the strip carries the uniform load
    # -rho A a, so the tip drops by rho A L^4 / (8 EI) per m/s^2
    np.testing.assert_allclose(G[0], [L**3 / (3 * EI), -(xb - xa) * (L - 0.5 * (xa + xb)) / EI,
                                      -rhoA * L**4 / (8 * EI)], rtol=2 * EPS * c)
    # exact by structure: A is n decoupled 2 x 2 blocks [[0, 1], [-w^2, -2 z w]] and B drives
    # accelerations only, so the solve's rate rows are exact zeros; slack 5000 EPS of the tip
    # compliance (the test's 1e-12, kept)
    np.testing.assert_allclose(G[1], 0.0, atol=5000 * EPS * L**3 / EI)


def test_tip_frf_is_the_closed_form_cantilevers(narrow, six_modes):
    zeta = 0.03
    plant = clamped_model(six_modes, narrow, damping_ratio=zeta)
    w = np.linspace(0.0, 1.2 * six_modes.omega_rad_s[-1], 3001)
    eye = np.eye(plant.A.shape[0])
    h = np.array([(plant.C @ np.linalg.solve(1j * wi * eye - plant.A, plant.B))[:, 0]
                  for wi in w])
    # the closed-form modes: beta_k L from cos cosh = -1, tip gains 4 / (mu L)
    ref = modal_frf(euler_bernoulli_modal_tip(narrow, 6), w, zeta)
    # measured 1.2e-6, near the sixth resonance: the 200-element mesh's error in its frequency
    np.testing.assert_allclose(h[:, 0], ref, rtol=2e-6)  # tip z per newton
    np.testing.assert_allclose(h[:, 1], 1j * w * ref, rtol=2e-6)  # its rate


def test_coupled_modal_damping_gives_every_hub_stiffened_mode_the_ratio(narrow, six_modes):
    zeta = 0.04
    h = hybrid_model(six_modes, narrow, 0.05, 0.1, damping_ratio=zeta, damping="modal")
    assert h.damping_form == "modal"
    lam = np.linalg.eigvals(h.A)
    flexible = lam[np.abs(lam) > 1e-6]
    flexible = flexible[flexible.imag > 0]
    flexible = flexible[np.argsort(np.abs(flexible))]
    np.testing.assert_allclose(np.abs(flexible), h.frequencies_rad_s[1:], rtol=1e-9)
    np.testing.assert_allclose(-flexible.real / np.abs(flexible), zeta, rtol=1e-9)
    assert np.sum(np.abs(lam) <= 1e-6) == 2  # the rigid rotation stays undamped
    # an internal damping: no torque about the hub axis, the angular momentum is conserved
    n = h.mass.shape[0]
    p = np.concatenate([np.zeros(n), h.mass[0]])
    np.testing.assert_allclose(p @ h.A, 0.0, atol=1e-9 * np.abs(h.A).max())


def test_clamped_mode_damping_gives_a_light_hubs_modes_other_ratios(narrow, six_modes):
    # why the plant comparison damps the coupled modes: on a light hub the default form's
    # ratios are far from zeta (measured 0.056, 0.050, 0.029 for zeta = 0.02)
    h = hybrid_model(six_modes, narrow, 0.05, 0.1, damping_ratio=0.02)
    assert h.damping_form == "clamped"
    lam = np.linalg.eigvals(h.A)
    flexible = lam[(np.abs(lam) > 1e-6) & (lam.imag > 0)]
    flexible = flexible[np.argsort(np.abs(flexible))]
    assert np.all(-flexible.real[:3] / np.abs(flexible[:3]) > 0.025)


@pytest.mark.parametrize(("call", "match"), [
    (lambda t, b: clamped_model(t, b, damping_ratio=1.0), "damping_ratio"),
    (lambda t, b: clamped_model(t, b, damping_ratio=True), "damping_ratio"),
    (lambda t, b: clamped_model(t, b, actuators=((0.5, 0.2),)), r"actuators\[0\]"),
    (lambda t, b: hybrid_model(t, b, 0.5, 0.1, damping="stiffness"), "damping = 'stiffness'"),
])
def test_bad_input_names_the_field(narrow, six_modes, call, match):
    with pytest.raises(BeamInputError, match=match):
        call(six_modes, narrow)
