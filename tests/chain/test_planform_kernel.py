"""The compiled planform integrals of a member of one thickness (chain/planform_kernel.py).

The links' properties and the finite-segment springs, one design and a stack of designs, on a
random taper and on a width step with link ends on its vertices, against adaptive quadrature
of the analytic integrands (scipy's QUADPACK); the compiled interpolation against
``numpy.interp``, whose arithmetic it copies.
"""

import numpy as np
import pytest
from paths import BEAMS
from scipy.integrate import quad
from tolerances import EPS

from prbdm_pin.chain.planform_kernel import _advance, _interp_at
from prbdm_pin.chain.sections import link_sections, planar_sections
from prbdm_pin.chain.stiffness import finite_segment_stiffness_unchecked
from prbdm_pin.files.beam_file import load_beam

# the quadrature's own request: 450 EPS (1e-13); QUADPACK's floor is 50 EPS
QUAD_RTOL = 450 * EPS
# the compiled sums against it: the request, plus as much again for the rounding of a few
# tens of Gauss terms and of the cancellation S2 - A dx^2 in the inertia about the centre of
# mass (the links are no shorter than a twenty-fifth of the member; 24 EPS measured)
RTOL = 2 * QUAD_RTOL


def _integral(f, a, b, beam):
    pts = [x for x in beam.x_m if a < x < b]
    return quad(f, a, b, points=pts or None, epsabs=0, epsrel=QUAD_RTOL, limit=200)[0]


def _link_reference(beam, a, b):
    """Mass (kg), centre (m) and the planar inertia about it around y (kg m^2) of [a, b]."""
    t, rho = beam.thickness_m, beam.material.rho_kg_m3

    def w(x):  # the planform's one-sided value inside [a, b] (quad never samples a vertex)
        return float(beam.half_width_at(x))

    A = _integral(lambda x: 2 * w(x), a, b, beam)
    xc = _integral(lambda x: 2 * w(x) * x, a, b, beam) / A
    sxx = _integral(lambda x: 2 * w(x) * (x - xc) ** 2, a, b, beam)
    m = rho * t * A
    return m, xc, rho * t * sxx + m * t**2 / 12


def _designs(beam, n, count, seed):
    rng = np.random.default_rng(seed)
    L = rng.dirichlet(np.full(n + 1, 4.0), size=count) * 0.8 + 0.2 / (n + 1)
    return L * beam.length_m


@pytest.mark.parametrize("name", ["reference-random", "stepped-narrow"])
def test_a_stack_of_designs_matches_quadrature_link_by_link(name):
    beam = load_beam(BEAMS / f"{name}.json")
    L = _designs(beam, 4, 3, 1)
    if name == "stepped-narrow":  # a link end on the step's two vertices
        L[0] = [0.2, 0.2, 0.2, 0.2, 0.2]
    mass, offset, inertia, _ = planar_sections(beam, L)
    for d in range(L.shape[0]):
        ends = np.cumsum(L[d])
        for i in range(L.shape[1]):
            a, b = ends[i] - L[d, i], ends[i]
            m, xc, Iyy = _link_reference(beam, a, b)
            assert mass[d, i] == pytest.approx(m, rel=RTOL)
            assert offset[d, i] == pytest.approx(xc - a, rel=RTOL)
            assert inertia[d, i] == pytest.approx(Iyy, rel=RTOL)
        # the same design alone (its own compiled call) against the same reference
        s = link_sections(beam, L[d])
        assert s.inertia_com_kg_m2[2, 1, 1] == pytest.approx(
            _link_reference(beam, ends[1], ends[2])[2], rel=RTOL)


@pytest.mark.parametrize("name", ["reference-random", "stepped-narrow", "tapered"])
@pytest.mark.parametrize("n", [1, 2, 5])
def test_the_springs_match_quadrature_of_the_compliance(name, n):
    beam = load_beam(BEAMS / f"{name}.json")
    L = _designs(beam, n, 2, n)
    EI_w = beam.material.E_Pa * 2 * beam.thickness_m**3 / 12  # E I(x) = EI_w w(x)
    for K in (finite_segment_stiffness_unchecked(beam, L),  # a stack
              np.array([finite_segment_stiffness_unchecked(beam, row) for row in L])):
        for d in range(L.shape[0]):
            ends = np.cumsum(L[d])
            c = ends - 0.5 * L[d]
            c[0], c[-1] = 0.0, beam.length_m
            for j in range(n):
                ref = EI_w / _integral(lambda x: 1.0 / float(beam.half_width_at(x)),
                                       c[j], c[j + 1], beam)
                assert K[d, j] == pytest.approx(ref, rel=RTOL)


def test_the_compiled_interpolation_is_numpys_to_the_bit():
    # numpy.interp's arithmetic (slope (x - x_j) + f_j, the vertex's value on a hit, the last
    # of repeated abscissae, clamping outside): the same operations, so equal exactly
    xp = np.array([0.0, 0.13, 0.4, 0.4, 0.71, 1.0])
    fp = np.array([0.02, 0.017, 0.015, 0.01, 0.012, 0.008])
    x = np.sort(np.r_[np.random.default_rng(3).uniform(0.0, 1.0, 200), xp, 1.0])
    j = 0
    got = np.empty(x.size)
    for k, xk in enumerate(x):
        j = _advance(j, xk, xp)
        got[k] = _interp_at(j, xk, xp, fp)
    np.testing.assert_array_equal(got, np.interp(x, xp, fp))
