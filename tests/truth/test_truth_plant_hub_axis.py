"""The truth plant on a hub about x or z: the strip's inertia about the axis against closed forms
(uniform strip) and a fine trapezoid rule (tapered planform), and the uncoupled rotation."""

import numpy as np
import pytest
from tolerances import EPS

from prbdm_pin.errors import BeamInputError
from prbdm_pin.truth.plant import truth_modal_gains
from prbdm_pin.truth.plant.hub_axis import axis_inertia_kg_m2, decoupled_hub_from_gains


@pytest.fixture(scope="module")
def six_modes(narrow, truth_of):
    return truth_of(narrow, model="beam", modes=6, static=False, error_tol_pct=None)


def test_uniform_strip_inertia_is_the_closed_form(narrow):
    L, w, t = narrow.length_m, narrow.half_width_m[0], narrow.thickness_m
    m = narrow.mass_kg
    r = 0.07
    # a rectangle of sides L x 2w at distance r: m ((r + L)^3 - r^3) / (3 L) + m (2w)^2 / 12;
    # about its own axis: m ((2w)^2 + t^2) / 12; Gauss quadrature is exact on these
    # polynomials: rounding only (a sum of a few terms)
    np.testing.assert_allclose(axis_inertia_kg_m2(narrow, r, "z"),
                               m * ((r + L) ** 3 - r**3) / (3 * L) + m * (2 * w) ** 2 / 12,
                               rtol=64 * EPS)
    np.testing.assert_allclose(axis_inertia_kg_m2(narrow, r, "x"),
                               m * ((2 * w) ** 2 + t**2) / 12, rtol=64 * EPS)


def test_tapered_inertia_against_a_fine_trapezoid_rule(tapered):
    x = np.linspace(0.0, tapered.length_m, 200001)
    w = tapered.half_width_at(x)
    t, rho, r = tapered.thickness_m, tapered.material.rho_kg_m3, 0.1
    ref_z = rho * t * np.trapezoid((r + x) ** 2 * 2 * w + 2 * w**3 / 3, x)
    ref_x = rho * t * np.trapezoid(2 * w**3 / 3 + 2 * w * t**2 / 12, x)
    # the trapezoid rule's error, h^2 / 12 max|f''| L relative to f, about 1e-11 at h = L/2e5
    np.testing.assert_allclose(axis_inertia_kg_m2(tapered, r, "z"), ref_z, rtol=1e-9)
    np.testing.assert_allclose(axis_inertia_kg_m2(tapered, r, "x"), ref_x, rtol=1e-9)


@pytest.mark.parametrize("axis", ["x", "z"])
def test_the_rotation_is_uncoupled_from_the_bending(narrow, six_modes, axis):
    gains = truth_modal_gains(six_modes, narrow)
    J_h, r = 0.3, 0.05
    h = decoupled_hub_from_gains(gains, narrow, J_h, r, axis, damping_ratio=0.02)
    J = J_h + axis_inertia_kg_m2(narrow, r, axis)
    # hub torque -> hub angle is the rigid 1 / (J s^2); the tip does not see it; the bending
    # modes keep their clamped frequencies
    s = 1j * 37.0
    eye = np.eye(h.A.shape[0])
    G = h.C @ np.linalg.solve(s * eye - h.A, h.B)
    i_tau, o_hub, o_tip = h.input_names.index("hub_torque"), 2, 0
    np.testing.assert_allclose(G[o_hub, i_tau], 1.0 / (J * s**2), rtol=1e-10)
    assert G[o_tip, i_tau] == 0.0 and G[o_hub, h.input_names.index("tip_force_z")] == 0.0
    np.testing.assert_allclose(h.frequencies_rad_s[1:], six_modes.omega_rad_s, rtol=0)


def test_bad_axis(narrow):
    with pytest.raises(BeamInputError, match="axis"):
        axis_inertia_kg_m2(narrow, 0.0, "y")
