"""Station derivatives of the sections and springs under a thickness law, and the fit on a taper.

References: central differences with their error bound (``tests/central_differences.py``) for
every derivative; the 1D beam truth's frequencies (an independent FE of the continuum) for the
joint-spring fit.
"""

from __future__ import annotations

import numpy as np
import pytest
from central_differences import central_difference
from tolerances import EPS

from prbdm_pin.chain.sections import link_sections_unchecked, planar_sections
from prbdm_pin.chain.sections_derivatives import (
    finite_segment_stiffness_gradient,
    planar_sections_gradient,
    roll_yaw_inertia_gradient,
)
from prbdm_pin.chain.stiffness import finite_segment_stiffness_unchecked
from prbdm_pin.fitting import fit
from prbdm_pin.fitting.target import FitTarget
from prbdm_pin.member.geometry import Beam
from prbdm_pin.truth.beam import beam_modal

STATIONS = np.array([0.2, 0.45, 0.8])  # m: joints away from the law's kink at 0.3 m


@pytest.fixture(scope="module")
def beam():
    return Beam([0.0, 0.3, 1.0], [0.05, 0.04, 0.02], [0.01, 0.006, 0.0003])


def _lengths(x):
    return np.diff(np.r_[0.0, x, 1.0])


def _check(analytic, f, scale):
    # each value of f carries ~100 EPS of its scale in rounding (sums over a few Gauss points)
    fd, bound = central_difference(f, STATIONS, 1e-4, 100 * EPS * scale)
    assert np.all(np.abs(analytic - fd) <= bound + 100 * EPS * np.abs(fd)), (analytic, fd)


def test_planar_section_derivatives(beam):
    g = planar_sections_gradient(beam, _lengths(STATIONS))
    for k, d in enumerate((g.d_mass_kg_per_m, g.d_com_offset, g.d_inertia_yy_kg_m,
                           g.d_area_moment_m3)):
        def f(x, k=k):
            return planar_sections(beam, _lengths(x))[k]
        _check(d, f, np.max(np.abs(f(STATIONS))))


def test_roll_yaw_inertia_derivatives(beam):
    _, _, d_xx, d_zz = roll_yaw_inertia_gradient(beam, _lengths(STATIONS))
    for a, d in ((0, d_xx), (2, d_zz)):
        def f(x, a=a):
            return link_sections_unchecked(beam, _lengths(x)).inertia_com_kg_m2[:, a, a]
        _check(d, f, np.max(np.abs(f(STATIONS))))


def test_spring_derivatives(beam):
    _, dK = finite_segment_stiffness_gradient(beam, _lengths(STATIONS))

    def f(x):
        return finite_segment_stiffness_unchecked(beam, _lengths(x))
    _check(dK, f, np.max(np.abs(f(STATIONS))))


def test_joint_spring_fit_reaches_the_truth_on_a_wedge():
    b = Beam([0.0, 0.5], [0.02, 0.02], [0.004, 0.0004], tip_force_N=[0.0, 0.0, -1.0])
    omega = beam_modal(b, 2).omega_rad_s
    r = fit(b, FitTarget(omega, b.tip_force_N), 3, frequencies=2, starts=3, seed=0,
            progress=False, stiffness="joint")
    # 5 free parameters for 2 frequencies: the fit reaches them to the solver's tolerance
    # (measured 9e-14 %); 1e-8 % leaves the least-squares gtol room
    assert np.max(np.abs(r.omega_export_errors_pct)) < 1e-8, r.omega_export_errors_pct
