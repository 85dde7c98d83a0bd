"""The fit's inner-loop kernels against the product path (Pinocchio) and independent quadrature:
vectorised integrals against scipy.integrate.quad, stacked designs against one-at-a-time
evaluation, batched statics against Pinocchio's equilibrium (the closed-form chain itself against
Pinocchio: tests/chain/test_planar.py)."""

from __future__ import annotations

import numpy as np
import pytest
from paths import BEAMS
from reference import ELASTICA, REF_OMEGA
from scipy.integrate import quad
from tolerances import EPS

from prbdm_pin.chain.layout import sample_lengths
from prbdm_pin.chain.sections import link_sections_unchecked, planar_sections
from prbdm_pin.chain.stiffness import finite_segment_stiffness, inv_width_integral
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.fitting.evaluate import chain_mass_matrices, fast_unit_frequencies
from prbdm_pin.fitting.problem import make_problem, unit_frequencies
from prbdm_pin.fitting.target import FitTarget
from prbdm_pin.member.random_beams import random_beam
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.options.objects import FitOptions


def _beams():
    rng = np.random.default_rng(7)
    return [load_beam(p) for p in sorted(BEAMS.glob("*.json"))] + [
        random_beam(rng) for _ in range(3)
    ]


def test_inv_width_integral_against_quadrature_and_stacks():
    rng = np.random.default_rng(11)
    for beam in _beams():
        a = np.sort(rng.uniform(0.0, beam.length_m, (6, 4)), axis=1)
        a[0, 1] = beam.x_m[1]  # an interval end on a planform vertex
        a = np.sort(a, axis=1)
        lo, hi = a[:, :-1], a[:, 1:]
        got = inv_width_integral(beam, lo, hi)
        for r in range(a.shape[0]):
            row = inv_width_integral(beam, lo[r], hi[r])
            assert np.array_equal(got[r], row)
            for j in range(lo.shape[1]):
                pts = [x for x in beam.x_m if lo[r, j] < x < hi[r, j]]
                # the quadrature's request: 450 EPS (1e-13); QUADPACK's floor is 50 EPS
                ref = quad(lambda x, b=beam: 1.0 / b.half_width_at(x), lo[r, j], hi[r, j],
                           points=pts or None, epsabs=0, epsrel=450 * EPS, limit=200)[0]
                assert row[j] == pytest.approx(ref, rel=1e-11, abs=1e-14)


@pytest.mark.parametrize("stiffness", ["paper", "joint"])
def test_stacked_designs_equal_single_designs_and_the_pinocchio_path(stiffness):
    rng = np.random.default_rng(5)
    for beam in _beams()[:3]:
        target = FitTarget(REF_OMEGA, beam.tip_force_N)
        prob = make_problem(beam, target, 4, FitOptions(frequencies=4, stiffness=stiffness,
                                                       joint_sweep=True, eigen_norm="paper"))
        L = sample_lengths(rng, beam.length_m, 5, 6)
        M, K0 = chain_mass_matrices(prob, L)
        _, W = fast_unit_frequencies(prob, L)
        for i, lengths in enumerate(L):
            # a design's numbers do not depend on the stack it is evaluated in
            Mi, K0i = chain_mass_matrices(prob, lengths)
            assert np.array_equal(M[i], Mi) and np.array_equal(K0[i], K0i)
            assert np.array_equal(W[i], fast_unit_frequencies(prob, lengths)[1])
            s = link_sections_unchecked(beam, lengths)
            mass, off, iyy, am = planar_sections(beam, lengths)
            assert np.array_equal(mass, s.mass_kg) and np.array_equal(am, s.area_moment_m4)
            assert np.array_equal(off, s.com_m[:, 0] - s.start_m)
            assert np.array_equal(iyy, s.inertia_com_kg_m2[:, 1, 1])
            # the product path: Pinocchio model, CRBA, validated springs
            _, K0_ref, W_ref = unit_frequencies(prob, lengths)
            # the kernel's springs are the product path's (exact here); kept: the tests' 1e-14
            assert K0i == pytest.approx(K0_ref, rel=50 * EPS)
            if stiffness == "joint":
                assert K0i == pytest.approx(finite_segment_stiffness(beam, lengths),
                                            rel=50 * EPS)
            # frequencies agree to the eigenproblem's rounding (eps * cond, cond <= 1e5 here)
            assert W[i] == pytest.approx(W_ref, rel=1e-9)


# --- batched statics and losses ------------------------------------------------------------------
def _pin_residual(model, q, F) -> float:
    """||K q - J(q)^T F|| / ||J^T F|| with Pinocchio's frame Jacobian (not the solver's)."""
    JtF = model.tip_jacobian(q).T @ F
    return float(np.linalg.norm(model.stiffness_Nm_per_rad * q - JtF) / np.linalg.norm(JtF))


@pytest.mark.parametrize("n", [1, 2, 4, 8])
def test_batched_statics_satisfy_pinocchio_equilibrium(n):
    from prbdm_pin.chain.planar import planar_tips
    from prbdm_pin.chain.statics import static_deflection_planar_batch

    rng = np.random.default_rng(n)
    beam = load_beam(BEAMS / "reference-random.json")
    L = sample_lengths(rng, beam.length_m, n + 1, 40)
    K = 10.0 ** rng.uniform(2.5, 4.5, (40, n))
    # transverse, oblique and axially compressive loads: a compressed straight chain is not a
    # minimum beyond buckling, so those rows leave the vectorised Newton for the scalar solver
    for F in ([0.0, 0.0, -2500.0], [-3e3, 0.0, -800.0], [-4e4, 0.0, -1e-3]):
        F = np.array(F)
        q, ok = static_deflection_planar_batch(L, K, F)
        assert ok.all()
        tips = planar_tips(L, q)
        for i in range(0, 40, 7):
            model = build_model(beam, L[i], K[i])
            assert _pin_residual(model, q[i], F) < 1e-9
            # two kinematics of the 1 m chain: a few roundings (2 EPS m measured); kept: the
            # test's 1e-14 m
            np.testing.assert_allclose(tips[i], model.tip_position(q[i]),
                                       atol=50 * EPS * beam.length_m)
            # a minimum: the Hessian of the potential, by differences of Pinocchio's J^T F
            h = 1e-6
            H = np.diag(K[i]) - np.array([
                (model.tip_jacobian(q[i] + h * e).T @ F - model.tip_jacobian(q[i] - h * e).T @ F)
                / (2 * h) for e in np.eye(n)])
            assert np.linalg.eigvalsh(0.5 * (H + H.T)).min() > 0


def test_batched_statics_match_the_elastica_table():
    from prbdm_pin.chain.planar import planar_tips
    from prbdm_pin.chain.statics import static_deflection_planar_batch

    # inextensible elastica under a dead tip load (Mattiasson 1981, Table 1): P L^2/EI,
    # retreat (L - x)/L, deflection -z/L; 32 equal segments, springs EI/h, half links at the ends
    beam = load_beam(BEAMS / "uniform-narrow.json")
    EI, L, n = beam.root_EI_Nm2, beam.length_m, 32
    table = [(a, *ELASTICA[a]) for a in (1.0, 2.0, 10.0)]
    h = L / n
    lengths = np.r_[h / 2, np.full(n - 1, h), h / 2]
    for alpha, retreat, deflection in table:
        F = np.array([0.0, 0.0, -alpha * EI / L**2])
        q, ok = static_deflection_planar_batch(lengths, np.full((3, n), EI / h), F)
        p = planar_tips(lengths, q)
        assert ok.all() and np.ptp(p, axis=0).max() == 0.0
        assert abs((L - p[0, 0]) / L - retreat) < 1e-3
        assert abs(-p[0, 2] / L - deflection) < 1e-3


@pytest.mark.parametrize("stiffness", ["paper", "joint"])
def test_batch_losses_equal_the_pinocchio_path(stiffness):
    from prbdm_pin.fitting.evaluate import batch_losses, evaluate
    from prbdm_pin.fitting.objectives import best_scale

    rng = np.random.default_rng(11)
    beam = load_beam(BEAMS / "reference-random.json")
    L = beam.length_m
    tip = np.array([0.98 * L, 0.0, -0.14 * L])
    target = FitTarget(REF_OMEGA, beam.tip_force_N, tip, tip - [L, 0.0, 0.0])
    for n in (2, 4):
        prob = make_problem(beam, target, n, FitOptions(frequencies=n, stiffness=stiffness,
                                                       eps_rad=0.05, eigen_norm="paper"))
        lengths = sample_lengths(rng, L, n + 1, 12)
        if stiffness == "paper":
            _, _, W = unit_frequencies(prob, np.full(n + 1, L / (n + 1)))
            k_ref = np.mean(best_scale(W, prob.target.omega_truth_rad_s))
            factors = k_ref * 10.0 ** rng.uniform(-0.5, 0.5, (12, prob.n_factors))
        else:
            factors = 10.0 ** rng.uniform(-0.5, 0.5, (12, n))
        got = batch_losses(prob, lengths, factors)
        for i in range(12):
            ev = evaluate(prob, lengths[i], factors[i])  # Pinocchio model, scalar statics
            np.testing.assert_allclose(got.eigen_errors[i], ev.eigen_errors, rtol=1e-9)
            np.testing.assert_allclose(got.position_errors[i], ev.position_errors, rtol=1e-8)
            np.testing.assert_allclose(got.displacement_errors[i], ev.displacement_errors,
                                       rtol=1e-8)
