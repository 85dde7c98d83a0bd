"""Derivatives of the spatial chain's springs and frequencies against central differences.

Every analytic derivative is compared with a central difference whose error bound
(``central_differences``: truncation from D(h) - D(2h), rounding ``noise / h``) is the
tolerance; ``noise`` is the rounding of one value, from the conditioning of what computes it.
"""

import numpy as np
import pytest
from central_differences import central_difference
from tolerances import EPS, eig_rtol

from prbdm_pin.chain.sections import link_sections
from prbdm_pin.chain.sections_derivatives import roll_yaw_inertia_gradient
from prbdm_pin.chain.spatial_modes import axis_mass_matrix, axis_modes
from prbdm_pin.chain.spatial_modes_derivatives import (
    axis_frequency_design_gradient,
    axis_frequency_gradients,
)
from prbdm_pin.chain.spatial_stiffness import axis_stiffness, spatial_stiffness
from prbdm_pin.chain.spatial_stiffness_derivatives import (
    axis_stiffness_design_gradient,
    axis_stiffness_gradient,
)
from prbdm_pin.member.design import Design
from prbdm_pin.member.geometry import Beam
from prbdm_pin.member.material import Material
from prbdm_pin.member.section import torsion_constant_m4
from prbdm_pin.member.section_derivatives import torsion_constant_gradient
from prbdm_pin.model.prbdm_model import build_model

STEEL = Material(E_Pa=205e9, rho_kg_m3=7850.0, nu=0.28)
# a width step at x = 0.3 (no span end or link end on it) and a taper after it
STEPPED = Beam(x_m=np.array([0.0, 0.3, 0.3, 0.8]), half_width_m=np.array([0.04, 0.04, 0.02, 0.012]),
               thickness_m=0.004, material=STEEL)
H = 1e-5  # relative step: truncation h^2 and rounding EPS / h both near 1e-10
SUM_ROUNDING = 50 * EPS  # a sum of a few dozen positive terms (the Gauss rule's 16 per piece)


def _case(name, reference_panel, tapered):
    if name == "stepped":
        return STEPPED, np.array([0.1, 0.15, 0.2, 0.25, 0.1])
    beam = reference_panel if name == "reference" else tapered
    return beam, np.array([0.15, 0.3, 0.2, 0.2, 0.15]) * beam.length_m


def _lengths(beam, stations):
    return np.diff(np.r_[0.0, stations, beam.length_m])


def _design(beam):
    """Every variable a beam offers; a step's station named once (its first vertex)."""
    n = beam.x_m.size
    xs = [f"x[{i}]" for i in range(1, n - 1) if beam.x_m[i - 1] != beam.x_m[i]]
    return Design(beam, ("thickness", "E", "nu", "rho",
                         *(f"half_width[{i}]" for i in range(n)), *xs))


@pytest.mark.parametrize("b, t", [(0.05, 0.004), (0.004, 0.05), (0.011, 0.01), (0.01, 0.01),
                                  (0.3, 0.001)])
def test_torsion_constant_derivatives(b, t):
    J, J_b, J_t = torsion_constant_gradient(b, t)
    # the same series: a sum of 14 terms and a few products
    assert J == pytest.approx(torsion_constant_m4(b, t), rel=SUM_ROUNDING)
    for k, (d, scale) in enumerate(((J_b, b), (J_t, t))):
        def f(v, k=k):
            return torsion_constant_m4(v[0], t) if k == 0 else torsion_constant_m4(b, v[0])

        fd, bound = central_difference(f, np.array([scale]), H * scale, SUM_ROUNDING * J)
        assert abs(d - fd[0]) <= bound[0]
    # Euler's identity of a degree-4 homogeneous function, to the rounding of its terms
    assert b * J_b + t * J_t == pytest.approx(4.0 * J, rel=SUM_ROUNDING)


@pytest.mark.parametrize("name", ["reference", "tapered", "stepped"])
@pytest.mark.parametrize("axis", ["y", "z", "x"])
def test_spring_station_derivatives(reference_panel, tapered, name, axis):
    beam, lengths = _case(name, reference_panel, tapered)
    K, dK = axis_stiffness_gradient(beam, lengths, axis)
    assert np.array_equal(K, axis_stiffness(beam, lengths, axis))
    stations = np.cumsum(lengths)[:-1]
    fd, bound = central_difference(lambda x: axis_stiffness(beam, _lengths(beam, x), axis),
                                   stations, H * beam.length_m, SUM_ROUNDING * K)
    assert np.all(np.abs(dK - fd) <= bound)


@pytest.mark.parametrize("name", ["reference", "tapered", "stepped"])
@pytest.mark.parametrize("axis", ["y", "z", "x"])
def test_spring_design_derivatives(reference_panel, tapered, name, axis):
    beam, lengths = _case(name, reference_panel, tapered)
    design = _design(beam)
    K, dK = axis_stiffness_design_gradient(beam, design, lengths, axis)
    fd, bound = central_difference(
        lambda p: axis_stiffness(design.beam_at(p), lengths, axis), design.values,
        H * design.scales, SUM_ROUNDING * K)
    assert np.all(np.abs(dK - fd) <= bound)
    assert np.any(dK != 0.0, axis=0)[design.names.index("half_width[1]")]


@pytest.mark.parametrize("name", ["reference", "stepped"])
def test_roll_and_yaw_inertia_station_derivatives(reference_panel, tapered, name):
    beam, lengths = _case(name, reference_panel, tapered)
    Ixx, Izz, dIxx, dIzz = roll_yaw_inertia_gradient(beam, lengths)
    stations = np.cumsum(lengths)[:-1]
    for a, (I, dI) in enumerate(((Ixx, dIxx), (None, None), (Izz, dIzz))):
        if I is None:
            continue

        def f(x, a=a):
            return link_sections(beam, _lengths(beam, x)).inertia_com_kg_m2[:, a, a]

        # a link's inertia: two-point Gauss sums over its pieces, less the centre of mass'
        # share (one cancellation of the link's own size)
        fd, bound = central_difference(f, stations, H * beam.length_m, SUM_ROUNDING * I)
        assert np.all(np.abs(dI - fd) <= bound)


def test_the_axis_blocks_are_pinocchios(reference_panel):
    beam = reference_panel
    lengths = np.array([0.15, 0.3, 0.2, 0.2, 0.15]) * beam.length_m
    model = build_model(beam, lengths, spatial_stiffness(beam, lengths, "xyz"), axes="xyz")
    M = model.mass_matrix()
    for axis in "yzx":
        block = M[np.ix_(model.axis_index(axis), model.axis_index(axis))]
        # CRBA's sums and the closed form's over the same link terms, in other orders: the
        # entries' rounding relative to the largest (a few roundings per link)
        assert np.abs(axis_mass_matrix(beam, lengths, axis) - block).max() <= \
            4 * M.shape[0] * EPS * np.abs(block).max()


def _frequency_noise(beam, lengths, axis, omega):
    """Rounding of the block's omega^2: the eigensolver's (spread) and M's entries' (a sum of
    n link terms each) through 1 / lambda_min(M)."""
    M = axis_mass_matrix(beam, lengths, axis)
    cond = np.abs(M).max() / np.linalg.eigvalsh(M).min()
    return omega**2 * (2 * eig_rtol(omega) + M.shape[0] * EPS * cond)


@pytest.mark.parametrize("name", ["reference", "stepped"])
@pytest.mark.parametrize("axis", ["y", "z", "x"])
def test_frequency_station_and_spring_derivatives(reference_panel, tapered, name, axis):
    beam, lengths = _case(name, reference_panel, tapered)
    k = axis_stiffness(beam, lengths, axis) * np.exp(np.linspace(-0.3, 0.3, lengths.size - 1))
    lam, d_station, d_k = axis_frequency_gradients(beam, lengths, k, axis)
    noise = _frequency_noise(beam, lengths, axis, np.sqrt(lam))
    stations = np.cumsum(lengths)[:-1]
    fd, bound = central_difference(
        lambda x: axis_modes(beam, _lengths(beam, x), k, axis)[0] ** 2, stations,
        H * beam.length_m, noise)
    assert np.all(np.abs(d_station - fd) <= bound)
    fd, bound = central_difference(lambda v: axis_modes(beam, lengths, v, axis)[0] ** 2, k,
                                   H * k, noise)
    assert np.all(np.abs(d_k - fd) <= bound)


@pytest.mark.parametrize("name", ["reference", "stepped"])
@pytest.mark.parametrize("axis", ["y", "z", "x"])
def test_frequency_design_derivatives(reference_panel, tapered, name, axis):
    beam, lengths = _case(name, reference_panel, tapered)
    design = _design(beam)
    K, dK = axis_stiffness_design_gradient(beam, design, lengths, axis)
    omega, d_omega = axis_frequency_design_gradient(beam, design, lengths, K, axis, dK)
    # omega's rounding: half of omega^2's relative (and the springs' sums)
    noise = 0.5 * _frequency_noise(beam, lengths, axis, omega) / omega + SUM_ROUNDING * omega

    def f(p):
        b = design.beam_at(p)
        return axis_modes(b, lengths, axis_stiffness(b, lengths, axis), axis)[0]

    fd, bound = central_difference(f, design.values, H * design.scales, noise)
    assert np.all(np.abs(d_omega - fd) <= bound)
