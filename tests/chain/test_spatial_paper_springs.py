"""The paper-style closed form (Eq. 14) on every axis: the links' mean section constants against
adaptive quadrature, and the y axis against the planar chain's Eq. 14."""

import numpy as np
import pytest
from scipy.integrate import quad
from tolerances import EPS

from prbdm_pin.chain.sections import link_sections
from prbdm_pin.chain.spatial_stiffness import link_mean_section_m4, paper_axis_unit_stiffness
from prbdm_pin.chain.stiffness import paper_unit_stiffness
from prbdm_pin.member.section import torsion_constant_thin_m4


@pytest.mark.parametrize("axis", ["y", "z", "x"])
def test_the_mean_section_is_the_quadrature_of_the_section_law(tapered, axis):
    lengths = np.array([0.15, 0.35, 0.3, 0.2]) * tapered.length_m
    t = tapered.thickness_m
    law = {"y": lambda b: b * t**3 / 12, "z": lambda b: t * b**3 / 12,
           "x": lambda b: float(torsion_constant_thin_m4(b, t))}[axis]
    ends = np.cumsum(lengths)
    starts = ends - lengths
    ref = []
    for a, b in zip(starts, ends, strict=True):
        val, err = quad(lambda x: law(2 * float(tapered.half_width_at(x))), a, b,
                        points=tapered.x_m[(tapered.x_m > a) & (tapered.x_m < b)],
                        epsabs=0, epsrel=450 * EPS)
        ref.append(val / (b - a))
    # quad's own relative request (1e-13) beside the 16-point rule's rounding
    assert np.allclose(link_mean_section_m4(tapered, lengths, axis), ref, rtol=1e-11, atol=0)


def test_the_y_axis_is_the_planar_equation_14(reference_panel):
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * reference_panel.length_m
    sec = link_sections(reference_panel, lengths)
    planar = paper_unit_stiffness(reference_panel.material.E_Pa, sec.area_moment_m4,
                                  sec.mass_kg)
    # the same mean I_y two ways (exact planform integrals; a Gauss rule exact for cubics):
    # a few roundings of a sum over the vertex intervals, halved by the square root
    got = paper_axis_unit_stiffness(reference_panel, lengths, sec.mass_kg, "y")
    assert np.allclose(got, planar, rtol=50 * EPS, atol=0)


def test_torsion_and_in_plane_scale_as_their_moduli_and_sections(narrow):
    # a uniform strip: every link's mean section is the section itself, so K_j^2 m_(j+1)
    # is the modulus times the section constant, exactly
    lengths = np.array([0.25, 0.25, 0.25, 0.25]) * narrow.length_m
    sec = link_sections(narrow, lengths)
    b, t = 2 * narrow.half_width_m[0], narrow.thickness_m
    for axis, expect in (("z", narrow.material.E_Pa * t * b**3 / 12),
                         ("x", narrow.material.G_Pa * float(torsion_constant_thin_m4(b, t)))):
        k = paper_axis_unit_stiffness(narrow, lengths, sec.mass_kg, axis)
        # a product and a square root of rounded sums: a few EPS
        assert np.allclose(k**2 * sec.mass_kg[1:], expect, rtol=50 * EPS, atol=0)
