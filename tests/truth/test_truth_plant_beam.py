"""Modal gains of the 1D beam truth against the analytic clamped-free Euler-Bernoulli beam."""


import numpy as np
import pytest
from paths import BEAMS
from reference import BETA_L

from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.truth import compute_truth
from prbdm_pin.truth.plant import truth_modal_gains

# stations inside elements (200 elements of 5 mm), the whole span, and a patch to near the tip
ACTUATORS = ((0.1234, 0.4567), (0.0, 1.0), (0.3, 0.95))


@pytest.fixture(scope="module")
def all_modes(narrow, truth_of):
    """Every mode of the 200-element beam (400 DOFs): the modal sums are the FE statics."""
    truth = truth_of(narrow, model="beam", modes=400, static=False, error_tol_pct=None)
    assert truth.omega_rad_s.size == 400
    return truth_modal_gains(truth, narrow, ACTUATORS)


def _section(beam):
    EI = beam.root_EI_Nm2
    rhoA = beam.material.rho_kg_m3 * 2 * beam.half_width_m[0] * beam.thickness_m
    return EI, rhoA


def _analytic_slope(k: int, x: np.ndarray, L: float, rhoA: float) -> np.ndarray:
    """d phi_k / dx of the mass-normalised clamped-free mode k (Blevins), positive tip."""
    bl = BETA_L[k]
    be = bl / L
    s = (np.cosh(bl) + np.cos(bl)) / (np.sinh(bl) + np.sin(bl))
    tip = np.cosh(bl) - np.cos(bl) - s * (np.sinh(bl) - np.sin(bl))
    # int_0^L (cosh - cos - s (sinh - sin))^2 dx = L: the shape over sqrt(rho A L) has unit mass
    d = be * (np.sinh(be * x) + np.sin(be * x) - s * (np.cosh(be * x) - np.cos(be * x)))
    return np.sign(tip) * d / np.sqrt(rhoA * L)


def test_strain_gains_match_analytic_mode_slopes(narrow, truth_of):
    truth = truth_of(narrow, model="beam", modes=6, static=False, error_tol_pct=None)
    g = truth_modal_gains(truth, narrow, ACTUATORS)
    _, rhoA = _section(narrow)
    L = narrow.length_m
    # section rotation about +y is -dphi/dx: the gain of a moment pair is -(phi'(x_b) - phi'(x_a))
    ref = np.array([[-(_analytic_slope(k, xb, L, rhoA) - _analytic_slope(k, xa, L, rhoA))
                     for k in range(6)] for xa, xb in ACTUATORS])
    # measured 1.3e-5 (200 Hermite elements)
    np.testing.assert_allclose(g.strain_per_sqrt_kg_m, ref, rtol=5e-5)


def test_tip_gains_are_the_analytic_tip_deflections(narrow, truth_of):
    truth = truth_of(narrow, model="beam", modes=6, static=False, error_tol_pct=None)
    g = truth_modal_gains(truth, narrow, ())
    _, rhoA = _section(narrow)
    # every mass-normalised clamped-free mode has |phi(L)| = 2 / sqrt(rho A L)
    ref = 2.0 / np.sqrt(rhoA * narrow.length_m)
    np.testing.assert_allclose(g.tip_z_per_sqrt_kg, ref, rtol=1e-6)  # measured 1e-8
    np.testing.assert_array_equal(g.tip_force_per_sqrt_kg, g.tip_z_per_sqrt_kg)
    assert g.actuators_m.shape == (0, 2) and g.strain_per_sqrt_kg_m.shape == (0, 6)


def test_modal_static_tip_force_is_the_cantilever_compliance(narrow, all_modes):
    EI, _ = _section(narrow)
    L = narrow.length_m
    ref = L**3 / (3 * EI)
    assert all_modes.static_tip_z_m(1.0, np.zeros(3)) == pytest.approx(ref, rel=1e-7)  # 4e-9
    w, c = all_modes.omega_rad_s, all_modes.tip_z_per_sqrt_kg
    ten = np.sum(c[:10] * all_modes.tip_force_per_sqrt_kg[:10] / w[:10] ** 2)
    assert ten == pytest.approx(ref, rel=1e-4)  # 4.1e-5: the tail falls as N^-3


@pytest.mark.parametrize("i", range(len(ACTUATORS)))
def test_modal_static_moment_pair_is_the_closed_form(narrow, all_modes, i):
    # curvature w'' = -M / EI on [x_a, x_b], zero elsewhere, clamped root:
    # w(L) = int_0^L (L - x) w''(x) dx = -M (x_b - x_a) (L - (x_a + x_b) / 2) / EI
    EI, _ = _section(narrow)
    L = narrow.length_m
    xa, xb = ACTUATORS[i]
    ref = -(xb - xa) * (L - 0.5 * (xa + xb)) / EI
    moments = np.zeros(len(ACTUATORS))
    moments[i] = 1.0
    assert all_modes.static_tip_z_m(0.0, moments) == pytest.approx(ref, rel=1e-7)  # <= 6e-9
    w, c, s = all_modes.omega_rad_s, all_modes.tip_z_per_sqrt_kg, all_modes.strain_per_sqrt_kg_m[i]
    errs = [abs(np.sum(c[:n] * s[:n] / w[:n] ** 2) / ref - 1.0) for n in (10, 40, 160)]
    assert errs[2] < errs[0] and errs[2] < 1e-5, errs  # measured: 1.3e-3, 8e-5, 1.3e-6 at worst
    assert errs[1] < 2e-4, errs


def test_positive_moment_bends_the_tip_like_a_positive_joint_torque(narrow, all_modes):
    # a positive PRBDM joint torque (about +y) moves the tip to -z (planar: dz_tip/dq < 0)
    for i in range(len(ACTUATORS)):
        assert all_modes.static_tip_z_m(0.0, np.eye(len(ACTUATORS))[i]) < 0.0
    assert all_modes.static_tip_z_m(1.0, np.zeros(3)) > 0.0


@pytest.mark.parametrize(("actuators", "match"), [
    (((0.2, 1.2),), r"actuators\[0\].*within the span"),
    (((0.0, 0.5), (-0.1, 0.5)), r"actuators\[1\].*within the span"),
    (((0.5, 0.5),), r"actuators\[0\].*x_a < x_b"),
    (((0.6, 0.4),), r"actuators\[0\].*x_a < x_b"),
    (((0.1, np.nan),), r"actuators\[0\].*finite"),
    ((0.1, 0.2, 0.3), r"actuators = .*pairs"),
])
def test_bad_actuators_are_refused_by_name(narrow, actuators, match):
    truth = compute_truth(narrow, model="beam", modes=3, static=False, error_tol_pct=None)
    with pytest.raises(BeamInputError, match=match):
        truth_modal_gains(truth, narrow, actuators)


def test_a_truth_of_another_beam_is_refused(narrow):
    truth = compute_truth(narrow, model="beam", modes=3, static=False, error_tol_pct=None)
    other = load_beam(BEAMS / "tapered.json")
    with pytest.raises(BeamInputError, match="another beam"):
        truth_modal_gains(truth, other)
