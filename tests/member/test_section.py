"""The rectangle's section constants against published values and limits."""

import numpy as np
import pytest
from tolerances import EPS

from prbdm_pin.member.section import (
    area_moment_y_m4,
    area_moment_z_m4,
    polar_area_moment_m4,
    torsion_constant_m4,
    torsion_constant_thin_m4,
)

# Timoshenko & Goodier, Theory of Elasticity, Sec. 109: J = beta a b^3 (a >= b), three digits
TIMOSHENKO_BETA = [(1.0, 0.141), (1.5, 0.196), (2.0, 0.229), (3.0, 0.263), (4.0, 0.281),
                   (5.0, 0.291), (10.0, 0.312)]


@pytest.mark.parametrize("ratio, beta", TIMOSHENKO_BETA)
def test_torsion_constant_matches_the_timoshenko_goodier_table(ratio, beta):
    b = 0.004
    a = ratio * b
    # the table's three digits: half a unit of the last one
    assert torsion_constant_m4(a, b) / (a * b**3) == pytest.approx(beta, abs=5e-4)
    # either side may be the longer one
    assert torsion_constant_m4(b, a) == torsion_constant_m4(a, b)


def test_torsion_constant_tends_to_a_third_and_the_thin_strip_correction():
    b = 1.0
    # the table's last row, a / b -> infinity: beta = 1/3, approached as 1/3 (1 - 0.630 b / a)
    a = 1e6
    assert torsion_constant_m4(a, b) / (a * b**3) == pytest.approx(1.0 / 3.0, rel=1e-6)
    for a in (10.0, 20.0, 100.0, 1000.0):
        thin = a * b**3 / 3.0 * (1.0 - 0.630 * b / a)
        # the constant 0.630 to three digits (192 lambda(5) / pi^5 = 0.63025): 5e-4 b / a; the
        # series' other terms, 2 exp(-pi a / b) / (a / b) at most, are 5e-15 at a / b = 10
        assert torsion_constant_m4(a, b) == pytest.approx(thin, rel=5e-4 * b / a)


def test_roark_closed_form_close_to_the_exact_series():
    b = 1.0
    a = np.logspace(np.log10(1.5), 4, 400)
    err = torsion_constant_thin_m4(a, b) / torsion_constant_m4(a, b) - 1.0
    # Roark's finite-width correction: 0.2 % on strips (a >= 1.5 b; measured 0.087 % at most)
    assert np.all(np.abs(err) < 2e-3)
    a = np.linspace(1.0, 1.5, 201)
    err = torsion_constant_thin_m4(a, b) / torsion_constant_m4(a, b) - 1.0
    # near the square it is worse: 0.49 % at a = 1.15 b (measured), 0.18 % at the square
    assert np.all(np.abs(err) < 5e-3)


def test_area_moments_of_the_rectangle():
    b, t = 0.05, 0.01
    # b t^3 / 12 and t b^3 / 12 written out: one or two roundings apart
    assert area_moment_y_m4(b, t) == pytest.approx(4.1666666666666667e-9, rel=4 * EPS)
    assert area_moment_z_m4(b, t) == pytest.approx(1.0416666666666667e-7, rel=4 * EPS)
    # I_p = b t (b^2 + t^2) / 12
    assert polar_area_moment_m4(b, t) == pytest.approx(b * t * (b**2 + t**2) / 12, rel=8 * EPS)
    # the polar moment overstates a thin strip's torsion constant by about (b / t)^2 / 4
    assert polar_area_moment_m4(0.1, 0.001) / torsion_constant_m4(0.1, 0.001) > 2000
