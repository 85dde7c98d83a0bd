"""The model's direct dependence on the design (link sections, finite-segment springs, the
chain's frequencies at fixed lengths and the fit's KKT conditions) against central differences
and against a second algorithm.

Errors are measured per output: the largest |analytic - difference| times the variable's scale
(``Design.scales``), over that output's largest scaled derivative. Differences are fourth-order
central (steps 1e-3 of the scale: truncation about 1e-12, rounding about 1e-13), on a tapered
panel (four vertices), a panel with a width step and the reference random panel. Measured: the
sections and springs within 8e-11, the frequencies within 1.4e-11; the bound 1e-9 leaves the
differences' own error room and nothing else (dropping a width step's jump term fails at 1e-2).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from paths import BEAMS
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.chain.eigen import modes_from_mass
from prbdm_pin.chain.planar import planar_mass_matrices
from prbdm_pin.chain.sections import link_sections
from prbdm_pin.chain.sections_design_derivatives import (
    finite_segment_design_gradient,
    section_design_gradient,
)
from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.errors import BeamInputError
from prbdm_pin.fitting.design_derivatives import kkt_design_jacobian
from prbdm_pin.fitting.joint import JointResiduals
from prbdm_pin.fitting.multistart_derivatives import fit_coordinates, fit_problem_of
from prbdm_pin.fitting.spec import FitSpec
from prbdm_pin.fitting.unique import log_frequency_jacobian, reference_x
from prbdm_pin.model.prbdm_model_derivatives import frequency_design_gradient


def _tapered():
    beam = pp.load_beam(BEAMS / "tapered.json")
    x = np.linspace(0.0, beam.length_m, 4)
    return dataclasses.replace(beam, x_m=x, half_width_m=beam.half_width_at(x))


# (beam, variables, link lengths): no moving vertex within 2 steps of a link end or spring span
# end (the sections are piecewise smooth in the stations: a kink where a vertex crosses one)
CASES = {
    "tapered": (_tapered, ("thickness", "half_width[0]", "half_width[1]", "half_width[2]",
                           "half_width[3]", "x[1]", "x[2]", "E", "rho", "nu"),
                [0.1, 0.25, 0.15, 0.1]),
    "stepped": (lambda: pp.load_beam(BEAMS / "stepped-narrow.json"),
                ("x[1]", "half_width[0]", "half_width[1]", "half_width[2]", "half_width[3]",
                 "thickness", "rho", "E"), [0.15, 0.4, 0.3, 0.15]),
    "reference": (lambda: pp.load_beam(BEAMS / "reference-random.json"),
                  ("thickness", "half_width[0]", "half_width[3]", "half_width[8]", "x[1]", "x[4]",
                   "x[9]", "E", "rho"), [0.2, 0.3, 0.35, 0.15]),
}


def _case(name):
    make, names, lengths = CASES[name]
    d = pp.Design(make(), names)
    return d, np.array(d.values), np.array(lengths)


def _differences(f, d, p, rel=1e-3):
    """Fourth-order central differences of f over the design, one column per variable."""
    cols = []
    for j in range(d.size):
        h = rel * d.scales[j]
        e = np.zeros(d.size)
        e[j] = h

        def at(s, e=e):
            return f(d.beam_at(p + s * e))

        cols.append((-at(2) + 8 * at(1) - 8 * at(-1) + at(-2)) / (12 * h))
    return np.array(cols).T


def _err(A, D, scales):
    As, Ds = A * scales, D * scales
    return np.max(np.abs(As - Ds), axis=1) / np.max(np.abs(Ds), axis=1)


def _sections(beam, lengths):
    s = link_sections(beam, lengths)
    inertia = s.inertia_com_kg_m2
    return np.concatenate([s.mass_kg, s.com_m[:, 0] - s.start_m, inertia[:, 0, 0],
                           inertia[:, 1, 1], inertia[:, 2, 2], s.area_moment_m4,
                           finite_segment_stiffness(beam, lengths)])


def _analytic(beam, d, lengths):
    g = section_design_gradient(beam, d, lengths)
    K, dK = finite_segment_design_gradient(beam, d, lengths)
    values = np.concatenate([g.mass_kg, g.com_offset_m, g.inertia_xx_kg_m2, g.inertia_yy_kg_m2,
                             g.inertia_zz_kg_m2, g.area_moment_m4, K])
    return values, np.vstack([g.d_mass_kg, g.d_com_offset_m, g.d_inertia_xx_kg_m2,
                              g.d_inertia_yy_kg_m2, g.d_inertia_zz_kg_m2, g.d_area_moment_m4, dK])


@pytest.mark.parametrize("name", sorted(CASES))
def test_section_and_spring_design_derivatives_equal_central_differences(name):
    d, p, lengths = _case(name)
    beam = d.beam_at(p)
    values, A = _analytic(beam, d, lengths)
    # exact by construction: the gradient's values are link_sections' and the springs' own;
    # slack 50 EPS (the test's 1e-14)
    np.testing.assert_allclose(values, _sections(beam, lengths), rtol=50 * EPS, atol=0.0)
    D = _differences(lambda b: _sections(b, lengths), d, p)
    assert np.all(_err(A, D, d.scales) < 1e-9), _err(A, D, d.scales)
    # what the design cannot move stays exactly still: nu everywhere, E in the sections
    for name_, col in zip(d.names, A.T, strict=True):
        if name_ == "nu":
            assert not np.any(col)
        if name_ == "E":
            assert not np.any(col[: -lengths.size + 1])


def test_by_hand_uniform_strip():
    # a uniform strip of one link pair: moving the half-width scales the mass per unit width,
    # the thickness scales the area moment as t^3 and the springs as t^3 and E
    beam = pp.load_beam(BEAMS / "uniform-narrow.json")
    d = pp.Design(beam, ("half_width[0]", "half_width[1]", "thickness", "E"))
    lengths = np.array([0.4, 0.6]) * beam.length_m
    g = section_design_gradient(beam, d, lengths)
    K, dK = finite_segment_design_gradient(beam, d, lengths)
    rho, t, w = beam.material.rho_kg_m3, beam.thickness_m, beam.half_width_m[0]
    # each side a few products and a sum of two (1 EPS measured): the tests' bounds kept, 500
    # EPS for the sum of mass derivatives, 5000 EPS for the springs', 50 EPS for the others
    # the whole half-width (both vertices together) adds 2 rho t per metre of link
    np.testing.assert_allclose(g.d_mass_kg[:, 0] + g.d_mass_kg[:, 1], 2 * rho * t * lengths,
                               rtol=500 * EPS)
    np.testing.assert_allclose(g.d_area_moment_m4[:, 2], 3 * g.area_moment_m4 / t,
                               rtol=50 * EPS)
    np.testing.assert_allclose(dK[:, 0] + dK[:, 1], K / w, rtol=5000 * EPS)  # K ∝ w
    np.testing.assert_allclose(dK[:, 2], 3 * K / t, rtol=50 * EPS)
    np.testing.assert_allclose(dK[:, 3], K / beam.material.E_Pa, rtol=50 * EPS)


@pytest.mark.parametrize("lengths", [[0.15, 0.25, 0.3, 0.3], [0.3, 0.2, 0.2, 0.3]])
def test_width_step_on_a_span_end_takes_the_mean_of_the_one_sided_derivatives(lengths):
    # the step (x = 0.4 m) on a link end, then on a spring span end (the links' mid-spans)
    beam = pp.load_beam(BEAMS / "stepped-narrow.json")
    d = pp.Design(beam, ("x[1]", "half_width[1]", "half_width[2]", "thickness"))
    p, lengths = np.array(d.values), np.array(lengths)
    _, A = _analytic(beam, d, lengths)

    def f(b):
        return _sections(b, lengths)

    cols = []
    for j in range(d.size):
        h = 1e-6 * d.scales[j]
        e = np.zeros(d.size)
        e[j] = h
        at = [f(d.beam_at(p + s * e)) for s in (-2, -1, 0, 1, 2)]
        fwd = (-3 * at[2] + 4 * at[3] - at[4]) / (2 * h)
        bwd = (3 * at[2] - 4 * at[1] + at[0]) / (2 * h)
        cols.append(0.5 * (fwd + bwd))
    D = np.array(cols).T
    assert np.all(_err(A, D, d.scales) < 1e-7), _err(A, D, d.scales)
    # the one-sided derivatives differ there (the check is not of a smooth point)
    e = np.zeros(d.size)
    e[0] = 1e-6 * d.scales[0]
    fwd = (f(d.beam_at(p + e)) - f(d.beam_at(p))) / e[0]
    assert np.any(np.abs(fwd - D[:, 0]) > 0.1 * np.abs(D[:, 0]))


def _chain_omega(beam, lengths, k):
    s = link_sections(beam, lengths)
    M = planar_mass_matrices(lengths, s.mass_kg, s.com_m[:, 0] - s.start_m,
                             s.inertia_com_kg_m2[:, 1, 1], np.zeros((1, lengths.size - 1)))
    return modes_from_mass(M, k)[0][0]


@pytest.mark.parametrize("name", sorted(CASES))
def test_frequency_design_gradient_equals_central_differences(name):
    d, p, lengths = _case(name)
    beam = d.beam_at(p)
    k = np.array([3.0, 1.0, 2.0]) * finite_segment_stiffness(beam, lengths)
    # fixed springs, then springs that follow the finite-segment law
    w, dw = frequency_design_gradient(beam, d, lengths, k)
    # the same sections, mass matrices and scaled solve (exact here; two solves of the pencil
    # would agree to eig_rtol, 1e-14 here); kept: the test's 1e-12
    np.testing.assert_allclose(w, _chain_omega(beam, lengths, k), rtol=5000 * EPS)
    D = _differences(lambda b: _chain_omega(b, lengths, k), d, p)
    assert np.all(_err(dw, D, d.scales) < 1e-9), _err(dw, D, d.scales)
    s = np.array([3.0, 1.0, 2.0])
    _, dK0 = finite_segment_design_gradient(beam, d, lengths)
    _, dw = frequency_design_gradient(beam, d, lengths, k, s[:, None] * dK0)
    D = _differences(lambda b: _chain_omega(b, lengths, s * finite_segment_stiffness(
        b, lengths)), d, p)
    assert np.all(_err(dw, D, d.scales) < 1e-9), _err(dw, D, d.scales)


def _kkt_case(name):
    d, p, _ = _case(name)
    beam = d.beam_at(p)
    truth = pp.truth_gradient(beam, ("E",), model="beam", modes=3, static=False)
    target = pp.FitTarget(truth.omega_rad_s[:3], beam.tip_force_N)
    fr = pp.fit(beam, target, 3, stiffness="joint", unique="nearest", progress=False)
    P0 = fit_problem_of(fr, beam, target)
    x = fit_coordinates(fr, P0)
    _, J = log_frequency_jacobian(P0, x)
    lam = -np.linalg.lstsq(J.T, x - reference_x(P0), rcond=None)[0]
    return d, p, fr, target, P0, np.r_[x, lam]


def _kkt_rows_by_joint_jacobian(problem, z):
    """[J^T lambda, ln w] with J = d ln w/dx from the fit's analytic residual Jacobian."""
    n = problem.n_joints
    x, lam = z[: 2 * n], z[2 * n:]
    R = JointResiduals(FitSpec(problem, "eigen", 100))
    r, Jr = R.residuals(x), R.jac(x)  # r = d (w - f): weights d per mode
    w = r / R.d + R.f
    return np.r_[(Jr / (R.d * w)[:, None]).T @ lam, np.log(w)]


@pytest.mark.parametrize("name", sorted(CASES))
def test_kkt_design_jacobian_equals_differences_of_the_analytic_x_jacobian(name):
    # another algorithm: the analytic x-Jacobian of the fit (chain_gradient through
    # joint_jacobian) differenced in the design, against the analytic design derivative
    # differenced in x. Measured: constraint rows 3e-12, stationarity rows up to 2.5e-7 (the
    # reference panel's last spring factor: the step in x of H_MIXED against its rounding)
    d, p, fr, target, P0, z = _kkt_case(name)
    G = kkt_design_jacobian(P0, d, z)
    D = _differences(lambda b: _kkt_rows_by_joint_jacobian(fit_problem_of(fr, b, target), z),
                     d, p)
    err = _err(G, D, d.scales)
    assert np.all(err[6:] < 1e-9), err
    assert np.all(err[:6] < 1e-6), err


def test_bad_input_is_named():
    d, p, lengths = _case("stepped")
    other = pp.Design(_tapered(), ("thickness",))
    with pytest.raises(BeamInputError, match="vertex structure"):
        section_design_gradient(d.beam_at(p), other, lengths)
    with pytest.raises(BeamInputError, match="lengths"):
        finite_segment_design_gradient(d.beam_at(p), d, [0.5, 0.6])
    with pytest.raises(BeamInputError, match="d_stiffness"):
        frequency_design_gradient(d.beam_at(p), d, lengths, [1.0, 2.0, 3.0], np.zeros((3, 2)))
    with pytest.raises(BeamInputError, match="design"):
        section_design_gradient(d.beam_at(p), "thickness", lengths)
