"""Finite-segment springs of the torsion and in-plane axes against direct integration."""

import numpy as np
import pytest
from scipy.integrate import quad
from tolerances import EPS

from prbdm_pin.chain.spatial_stiffness import axis_stiffness, spatial_stiffness
from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.member.geometry import Beam
from prbdm_pin.member.material import Material
from prbdm_pin.member.section import area_moment_z_m4, torsion_constant_m4

STEEL = Material(E_Pa=205e9, rho_kg_m3=7850.0, nu=0.28)


def _span_ends(lengths):
    """The springs' spans: clamp, the inner links' mid-points, tip (m)."""
    edges = np.concatenate([[0.0], np.cumsum(lengths)])
    mids = 0.5 * (edges[:-1] + edges[1:])
    return np.concatenate([[0.0], mids[1:-1], [edges[-1]]])


UNIFORM = Beam(x_m=np.array([0.0, 1.0]), half_width_m=np.array([0.025, 0.025]),
               thickness_m=0.01, material=STEEL)
TAPERED = Beam(x_m=np.array([0.0, 0.6]), half_width_m=np.array([0.05, 0.02]),
               thickness_m=0.005, material=STEEL)
# a width step at x = 0.3 and a taper after it
STEPPED = Beam(x_m=np.array([0.0, 0.3, 0.3, 0.8]), half_width_m=np.array([0.04, 0.04, 0.02, 0.012]),
               thickness_m=0.004, material=STEEL)
LINKS = {UNIFORM: [0.1, 0.25, 0.3, 0.2, 0.15], TAPERED: [0.05, 0.2, 0.2, 0.15],
         STEPPED: [0.1, 0.15, 0.2, 0.25, 0.1]}


def test_uniform_strip_springs_are_section_stiffness_over_span():
    lengths = np.array(LINKS[UNIFORM])
    span = np.diff(_span_ends(lengths))
    b, t = 0.05, 0.01
    kx = axis_stiffness(UNIFORM, lengths, "x")
    kz = axis_stiffness(UNIFORM, lengths, "z")
    # G J / l and E I_z / l: a sum of 16 (x) or a few (z) equal terms per span, each of a few
    # roundings: 50 EPS
    assert kx == pytest.approx(STEEL.G_Pa * torsion_constant_m4(b, t) / span, rel=50 * EPS)
    assert kz == pytest.approx(STEEL.E_Pa * area_moment_z_m4(b, t) / span, rel=50 * EPS)


@pytest.mark.parametrize("beam", [TAPERED, STEPPED], ids=["tapered", "stepped"])
@pytest.mark.parametrize("axis", ["x", "z"])
def test_tapered_and_stepped_springs_match_quadrature(beam, axis):
    lengths = np.array(LINKS[beam])
    c = _span_ends(lengths)
    t = beam.thickness_m

    def section(x):
        b = 2.0 * float(beam.half_width_at(x))
        return torsion_constant_m4(b, t) if axis == "x" else area_moment_z_m4(b, t)

    modulus = STEEL.G_Pa if axis == "x" else STEEL.E_Pa
    got = axis_stiffness(beam, lengths, axis)
    for j in range(lengths.size - 1):
        inside = [float(v) for v in beam.x_m if c[j] < v < c[j + 1]]
        integral, abserr = quad(lambda x: 1.0 / float(section(x)), c[j], c[j + 1],
                                points=inside or None, epsabs=0.0, epsrel=450 * EPS)
        # quad's own error estimate, plus the 16-point Gauss rule's (below 1e-13 relative for
        # end widths within a factor 10, spatial_stiffness's figure) and a few roundings
        tol = abserr / integral + 1e-13 + 50 * EPS
        assert got[j] == pytest.approx(modulus / integral, rel=tol), j


@pytest.mark.parametrize("beam", [UNIFORM, TAPERED, STEPPED], ids=["uniform", "tapered",
                                                                  "stepped"])
def test_y_axis_is_the_planar_chains_springs(beam):
    lengths = np.array(LINKS[beam])
    ref = finite_segment_stiffness(beam, lengths)
    # the same function's numbers: bit for bit
    assert np.array_equal(axis_stiffness(beam, lengths, "y"), ref)
    assert np.array_equal(spatial_stiffness(beam, lengths, "y"), ref)
    per_node = spatial_stiffness(beam, lengths, "xyz").reshape(-1, 3)
    assert np.array_equal(per_node[:, 0], ref)


def test_unknown_axis_refused():
    with pytest.raises(ValueError, match="axis"):
        axis_stiffness(UNIFORM, np.array(LINKS[UNIFORM]), "w")
