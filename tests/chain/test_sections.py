"""Link sections against closed forms, an independent quadrature and conservation properties."""


import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from paths import BEAMS
from scipy.integrate import quad
from tolerances import EPS

from prbdm_pin.chain.sections import link_sections
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.member.geometry import Beam


def test_uniform_links_match_closed_forms():
    beam = load_beam(BEAMS / "uniform-narrow.json")
    t, b = beam.thickness_m, 2 * beam.half_width_m[0]
    rho = beam.material.rho_kg_m3
    lengths = np.array([0.3, 0.45, 0.25])
    s = link_sections(beam, lengths)
    starts = np.array([0.0, 0.3, 0.75])
    # closed forms of a uniform strip against its section integrals: a few roundings each
    # (<= 5 EPS measured); kept: the tests' 1e-14, 1e-12, and 1e-16 m as EPS / 2; the zero
    # products of inertia within one rounding of the largest moment (>= the test's 1e-18)
    for i, ell in enumerate(lengths):
        m = rho * t * b * ell
        assert s.mass_kg[i] == pytest.approx(m, rel=50 * EPS)
        np.testing.assert_allclose(s.com_m[i], [starts[i] + ell / 2, 0, 0], rtol=50 * EPS,
                                   atol=EPS / 2)
        expected = np.diag([m * (b**2 + t**2) / 12, m * (ell**2 + t**2) / 12,
                            m * (ell**2 + b**2) / 12])
        np.testing.assert_allclose(s.inertia_com_kg_m2[i], expected, rtol=5000 * EPS,
                                   atol=EPS * np.abs(expected).max())
        assert s.area_moment_m4[i] == pytest.approx(b * t**3 / 12, rel=50 * EPS)
    # exact here (cumulative sums of the lengths); kept: the tests' 1e-15 m
    np.testing.assert_allclose(s.start_m, starts, atol=5 * EPS)
    np.testing.assert_allclose(s.end_m, starts + lengths, atol=5 * EPS)


def _quad_reference(beam, a, b):
    """Mass, COM and inertia of [a, b] by adaptive quadrature of the analytic integrands."""
    t, rho = beam.thickness_m, beam.material.rho_kg_m3
    w = beam.half_width_at
    pts = [x for x in beam.x_m if a < x < b]

    def integral(f):
        # the quadrature's request: 450 EPS (1e-13); QUADPACK's floor is 50 EPS
        return quad(f, a, b, points=pts or None, epsabs=0, epsrel=450 * EPS, limit=200)[0]

    A = integral(lambda x: 2 * w(x))
    xc = integral(lambda x: 2 * w(x) * x) / A
    sxx = integral(lambda x: 2 * w(x) * (x - xc) ** 2)
    syy = integral(lambda x: 2 * w(x) ** 3 / 3)
    m = rho * t * A
    inertia = np.diag([rho * t * syy + m * t**2 / 12, rho * t * sxx + m * t**2 / 12,
                       rho * t * (sxx + syy)])
    imean = integral(lambda x: 2 * w(x) * t**3 / 12) / (b - a)
    return m, xc, inertia, imean


def test_tapered_links_match_quadrature():
    beam = load_beam(BEAMS / "reference-random.json")
    lengths = np.array([0.04, 0.2, 0.31, 0.13, 0.32])
    s = link_sections(beam, lengths)
    ends = np.cumsum(lengths)
    for i in range(lengths.size):
        m, xc, inertia, imean = _quad_reference(beam, ends[i] - lengths[i], ends[i])
        assert s.mass_kg[i] == pytest.approx(m, rel=1e-11)
        assert s.com_m[i, 0] == pytest.approx(xc, rel=1e-11)
        np.testing.assert_allclose(s.inertia_com_kg_m2[i], inertia, rtol=1e-9, atol=0)
        assert s.area_moment_m4[i] == pytest.approx(imean, rel=1e-11)


def test_masses_sum_to_beam_mass():
    beam = load_beam(BEAMS / "reference-random.json")
    s = link_sections(beam, [0.1, 0.25, 0.2, 0.3, 0.15])
    # five section integrals summed against the planform's: a few roundings (1.7 EPS
    # measured); kept: the test's 1e-14
    assert s.mass_kg.sum() == pytest.approx(beam.mass_kg, rel=50 * EPS)


def test_bad_lengths_raise_naming_the_field():
    beam = load_beam(BEAMS / "uniform-narrow.json")
    with pytest.raises(BeamInputError, match=r"lengths\[2\] = 0\.01"):
        link_sections(beam, [0.5, 0.49, 0.01])
    with pytest.raises(BeamInputError, match="sum"):
        link_sections(beam, [0.5, 0.6])


@st.composite
def beams_and_lengths(draw):
    k = draw(st.integers(2, 8))
    gaps = draw(st.lists(st.floats(0.05, 1.0), min_size=k - 1, max_size=k - 1))
    x = np.concatenate([[0.0], np.cumsum(gaps)])
    x = x / x[-1] * draw(st.floats(0.2, 3.0))
    w = draw(st.lists(st.floats(0.005, 0.5), min_size=k, max_size=k))
    t = draw(st.floats(0.001, 0.05))
    beam = Beam(x, np.array(w), t)
    n1 = draw(st.integers(2, 9))
    frac = np.array(draw(st.lists(st.floats(0.1, 1.0), min_size=n1, max_size=n1)))
    lengths = frac / frac.sum() * beam.length_m
    lengths[-1] = beam.length_m - lengths[:-1].sum()
    return beam, lengths


def _whole_beam(beam):
    """Area, first and second moment in x and the y^2 moment of the planform, in closed form."""
    x0, x1 = beam.x_m[:-1], beam.x_m[1:]
    w0, w1 = beam.half_width_m[:-1], beam.half_width_m[1:]
    h = x1 - x0
    # trapezoid pieces: w linear from w0 to w1; exact polynomial moments
    A = np.sum(h * (w0 + w1))
    Sx = np.sum(h * (w0 * (2 * x0 + x1) + w1 * (x0 + 2 * x1)) / 3)
    return A, Sx


@settings(max_examples=60, deadline=None)
@given(beams_and_lengths())
def test_property_mass_first_moment_and_inertia(case):
    beam, lengths = case
    s = link_sections(beam, lengths, min_fraction=0.0)
    rho_t = beam.material.rho_kg_m3 * beam.thickness_m
    A, Sx = _whole_beam(beam)
    # sums of n positive section integrals against closed forms: about n EPS (<= 1.8 EPS
    # measured); kept: the tests' 1e-12
    assert s.mass_kg.sum() == pytest.approx(rho_t * A, rel=5000 * EPS)
    assert (s.mass_kg * s.com_m[:, 0]).sum() == pytest.approx(rho_t * Sx, rel=5000 * EPS)
    assert np.all(s.com_m[:, 0] >= s.start_m) and np.all(s.com_m[:, 0] <= s.end_m)
    for i in range(lengths.size):
        eig = np.linalg.eigvalsh(s.inertia_com_kg_m2[i])
        assert eig.min() > 0
        I = np.diag(s.inertia_com_kg_m2[i])
        # triangle inequality of a rigid body's principal moments
        assert I[0] + I[1] >= I[2] * (1 - 1e-12)
    # the total inertia about the global COM does not depend on where the beam is cut
    def total_inertia(sec):
        c = (sec.mass_kg[:, None] * sec.com_m).sum(0) / sec.mass_kg.sum()
        tot = np.zeros((3, 3))
        for m, r, Ic in zip(sec.mass_kg, sec.com_m - c, sec.inertia_com_kg_m2, strict=True):
            tot += Ic + m * (r @ r * np.eye(3) - np.outer(r, r))
        return tot
    half = link_sections(beam, [beam.length_m / 2, beam.length_m / 2])
    # parallel-axis sums that cancel to the zero products of inertia: a few EPS of the largest
    # entry absolute (1.5 EPS measured); the mean moments' sum as above; kept: the tests' 1e-12
    np.testing.assert_allclose(total_inertia(s), total_inertia(half), rtol=1e-10,
                               atol=5000 * EPS * np.abs(total_inertia(half)).max())
    # mean bending moments integrate back to t^3/12 times the planform area
    itot = (s.area_moment_m4 * (s.end_m - s.start_m)).sum()
    assert itot == pytest.approx(A * beam.thickness_m**3 / 12, rel=5000 * EPS)
