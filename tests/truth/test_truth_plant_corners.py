"""The plate truth's modal gains at the tip corners: their symmetry across the width, the first
torsion modes against the 1D Saint-Venant strip in closed form, the corner plant; the 1D beam
truth, which has no width, refused."""

import numpy as np
import pytest
from tolerances import EPS

from prbdm_pin.errors import BeamInputError
from prbdm_pin.truth import compute_truth
from prbdm_pin.truth.plant import clamped_from_gains, clamped_model, truth_modal_gains


@pytest.fixture(scope="module")
def plate_truth(narrow):
    return compute_truth(narrow, modes=5, static=False, error_tol_pct=None)


@pytest.fixture(scope="module")
def kept(plate_truth):
    """The bending and torsion modes among the computed ones (what a twist test needs)."""
    return [i for i, lab in enumerate(plate_truth.labels) if lab in ("bending", "torsion")][:10]


@pytest.fixture(scope="module")
def gains(narrow, plate_truth, kept):
    return truth_modal_gains(plate_truth, narrow, (), mode_index=kept)


def test_corner_gains_are_symmetric_for_bending_and_antisymmetric_for_torsion(
        plate_truth, kept, gains):
    labels = [plate_truth.labels[i] for i in kept]
    left, right = gains.corner_per_sqrt_kg
    scale = np.abs(gains.corner_per_sqrt_kg).max()
    bend = np.array([lab == "bending" for lab in labels])
    assert bend.sum() >= 5 and (~bend).sum() >= 2
    # the strip's mesh is symmetric about its axis: the two corners are mirror nodes, so what
    # differs is the eigensolver's rounding of a mode (~EPS times the spectrum's spread, 1e6)
    tol = 1e-8 * scale
    assert np.abs(left[bend] - right[bend]).max() <= tol
    assert np.abs(left[~bend] + right[~bend]).max() <= tol
    # a torsion mode leaves the axis still: its tip z gain is a rounding too
    assert np.abs(gains.tip_z_per_sqrt_kg[~bend]).max() <= tol
    # a slender strip's bending modes: the corners move with the tip centre (the anticlastic
    # curvature across the width grows with the mode: 0.6 % at the 8th bending mode, measured)
    np.testing.assert_allclose(left[bend], gains.tip_z_per_sqrt_kg[bend], rtol=1e-2)


def test_torsion_corner_gains_match_the_saint_venant_strip(narrow, plate_truth, kept, gains):
    labels = [plate_truth.labels[i] for i in kept]
    tors = [j for j, lab in enumerate(labels) if lab == "torsion"][:2]
    m, t, L = narrow.material, narrow.thickness_m, narrow.length_m
    w = float(narrow.half_width_m[-1])
    # 1D: theta_k(x) = A sin((2k - 1) pi x / 2L), mass-normalised with the Kirchhoff plate's
    # inertia of w = y theta (rho t (2w)^3 / 12 per length: no rotary inertia of the
    # thickness), so A^2 rho t (2w)^3 L / 24 = 1; the corner's z is w theta(L) = w A
    corner_1d = w * np.sqrt(24.0 / (m.rho_kg_m3 * t * (2 * w) ** 3 * L))
    GJ = m.E_Pa / (2 * (1 + m.nu)) * (2 * w) * t**3 / 3
    omega_1d = np.array([1, 3]) * np.pi / (2 * L) * np.sqrt(GJ / (m.rho_kg_m3 * t * (2 * w) ** 3
                                                                   / 12))
    # the plate-vs-1D gap of this strip (t / 2w = 0.2, clamped root restraining the warping):
    # measured +1.2 % and +1.4 % in frequency, +0.6 % and +0.9 % in the corner gain
    np.testing.assert_allclose(gains.omega_rad_s[tors], omega_1d, rtol=3e-2)
    np.testing.assert_allclose(np.abs(gains.corner_per_sqrt_kg[0, tors]), corner_1d, rtol=2e-2)


def test_the_corner_plant_carries_the_corner_gains(narrow, plate_truth, kept, gains):
    plant = clamped_model(plate_truth, narrow, (), 0.02, corners=True, mode_index=kept)
    assert plant.input_names == ("tip_force_z", "corner_force_z_left", "corner_force_z_right",
                                 "base_accel_z")
    assert plant.output_names == ("tip_z", "tip_z_rate", "corner_z_left", "corner_z_right")
    n = gains.omega_rad_s.size
    # the same numbers placed in B and C: exact
    np.testing.assert_array_equal(plant.B[n:, 1:3], gains.corner_per_sqrt_kg.T)
    np.testing.assert_array_equal(plant.C[2:, :n], gains.corner_per_sqrt_kg)
    # static differential corner response (left minus right) per newton at the left corner:
    # the modal sum of the torsion modes only (bending modes move both corners alike)
    dc = -plant.C[2:] @ np.linalg.solve(plant.A, plant.B[:, 1])
    c = gains.corner_per_sqrt_kg
    modal = np.sum((c[0] - c[1]) * c[0] / gains.omega_rad_s**2)
    # a solve of diag-like A: rounding ~EPS times the spread of omega^2 (~1e5)
    np.testing.assert_allclose(dc[0] - dc[1], modal, rtol=1e6 * EPS)


def test_the_1d_beam_truth_has_no_corners(narrow):
    beam_truth = compute_truth(narrow, model="beam", modes=3, static=False, error_tol_pct=None)
    g = truth_modal_gains(beam_truth, narrow)
    assert g.corner_per_sqrt_kg is None
    with pytest.raises(BeamInputError, match="corners: the 1D beam truth has no width"):
        clamped_model(beam_truth, narrow, corners=True)
    with pytest.raises(BeamInputError, match="corners: the beam truth has no width"):
        clamped_from_gains(g, corners=True)
    with pytest.raises(BeamInputError, match="mode_index = "):
        truth_modal_gains(beam_truth, narrow, mode_index=[0, 99])
