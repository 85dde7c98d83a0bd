"""Stress: extreme link lengths, tapers, thicknesses and moduli; conditioning; exact invariances.

References: the 40-digit mpmath solve of the closed-form Lagrangian (test_stress_poses), link
properties of a uniform strip written out by hand, and scaling laws of the continuum.
"""

import numpy as np
import pytest
from lagrangian import (
    MP_RTOL,
    chain_inputs,
    lagrangian_mass_matrix,
    mpmath_omega2,
    reference_omega2,
)

from prbdm_pin.chain import eigen
from prbdm_pin.chain import pin_dynamics as dyn
from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.errors import BeamInputError, SolveError
from prbdm_pin.member.geometry import Beam
from prbdm_pin.member.material import Material
from prbdm_pin.model.prbdm_model import build_model

EPS = np.finfo(float).eps


def strip(t=0.01, E=205e9, rho=7850.0, w=(0.025, 0.025)):
    return Beam(np.array([0.0, 1.0]), np.array(w), t, Material("m", E, rho, 0.3))


def conditioning(model, q=None):
    """cond(M), cond(K) and cond(K^-1/2 M K^-1/2) at pose q."""
    M = model.mass_matrix(q)
    k = model.stiffness_Nm_per_rad
    A = M / np.sqrt(np.outer(k, k))
    return np.linalg.cond(M), k.max() / k.min(), np.linalg.cond(A)


SHORT = {
    "0.02 L at the root": [0.02, 0.98],
    "0.02 L at the tip": [0.98, 0.02],
    "four 0.02 L links, long tip": [0.02, 0.02, 0.02, 0.02, 0.92],
    "long root, four 0.02 L links": [0.92, 0.02, 0.02, 0.02, 0.02],
    "alternating": [0.02, 0.47, 0.02, 0.47, 0.02],
}
TAPERS = {"1000:1 narrowing": (0.5, 0.0005), "1:1000 widening": (0.0005, 0.5)}


def extreme_cases():
    for tname, w in TAPERS.items():
        for lname, lengths in SHORT.items():
            yield f"{tname}, {lname}", strip(w=w), np.array(lengths)


@pytest.mark.parametrize("case", list(extreme_cases()), ids=lambda c: c[0])
def test_extreme_layouts_match_mpmath(case):
    name, beam, lengths = case
    model = build_model(beam, lengths, finite_segment_stiffness(beam, lengths))
    n = model.n_joints
    for q in (np.zeros(n), np.full(n, np.pi / 2), np.array([np.pi, -0.1, 1e-6, -np.pi][:n])):
        cM, cK, cA = conditioning(model, q)
        w2 = model.natural_frequencies(q, squared=True)
        err = np.max(np.abs(w2 / reference_omega2(model, q) - 1))
        msg = f"{name} q={q}: cond M {cM:.3g}, cond K {cK:.3g}, cond A {cA:.3g}, err {err:.2e}"
        print(msg)
        # 1e-9, or the rounding bound of the highest mode where cond A makes 1e-9 unreachable
        # in double precision (measured: up to 0.7 eps cond A)
        assert err <= max(MP_RTOL, 2 * EPS * cA), msg


def uniform_strip_sections(beam, lengths):
    """Link mass, COM offset and COM inertia about y of a uniform strip, written out by hand."""
    w, t, rho = beam.half_width_m[0], beam.thickness_m, beam.material.rho_kg_m3
    m = rho * 2 * w * t * lengths
    return m, lengths / 2, m * (lengths**2 + t**2) / 12


@pytest.mark.parametrize("t", [1e-4, 1e-3, 1e-2, 1e-1])
@pytest.mark.parametrize("E", [1e6, 1e9, 1e12])
def test_uniform_strip_thickness_and_modulus_sweep(t, E):
    beam = strip(t=t, E=E)
    lengths = np.array([0.1, 0.3, 0.25, 0.35])
    model = build_model(beam, lengths, finite_segment_stiffness(beam, lengths))
    # K_j = E I / (distance between link centres) for a uniform strip; the end links count
    # from the clamp and to the tip
    centres = np.cumsum(lengths) - lengths / 2
    centres[0], centres[-1] = 0.0, lengths.sum()
    k_ref = E * (2 * 0.025 * t**3 / 12) / np.diff(centres)
    # EI over a distance either side: a few roundings (1.8 EPS measured); kept: the test's 1e-13
    np.testing.assert_allclose(model.stiffness_Nm_per_rad, k_ref, rtol=500 * EPS)
    import mpmath

    with mpmath.workdps(40):
        M = lagrangian_mass_matrix(lengths, *uniform_strip_sections(beam, lengths), np.zeros(3),
                                   lib=mpmath)
        ref = mpmath_omega2(M, k_ref)
    w2 = model.natural_frequencies(squared=True)
    cM, cK, cA = conditioning(model)
    err = np.max(np.abs(w2 / ref - 1))
    assert err <= MP_RTOL, f"t={t} E={E}: cond M {cM:.3g} K {cK:.3g} A {cA:.3g} err {err:.2e}"


def test_frequencies_scale_as_sqrt_E_and_inverse_sqrt_rho():
    lengths = np.array([0.15, 0.3, 0.2, 0.35])
    base = strip(w=(0.3, 0.01))
    ref_model = build_model(base, lengths, finite_segment_stiffness(base, lengths))
    w_ref = ref_model.natural_frequencies(np.full(3, 0.3))
    # scaling K or M by a non-power of two rounds the scaled matrix anew: the solves agree to
    # eig_rtol(w_ref) = 142 EPS (42 measured); M scales exactly up to a rounding (0.9 EPS);
    # kept: the tests' 1e-13
    for E in (1e6, 1e9, 1e12):
        b = strip(w=(0.3, 0.01), E=E)
        m = build_model(b, lengths, finite_segment_stiffness(b, lengths))
        np.testing.assert_allclose(m.natural_frequencies(np.full(3, 0.3)),
                                   w_ref * np.sqrt(E / 205e9), rtol=500 * EPS)
    for rho in (1.0, 1e3, 2e4):
        b = strip(w=(0.3, 0.01), rho=rho)
        m = build_model(b, lengths, finite_segment_stiffness(b, lengths))
        np.testing.assert_allclose(m.mass_matrix(np.full(3, 0.3)),
                                   ref_model.mass_matrix(np.full(3, 0.3)) * rho / 7850.0,
                                   rtol=500 * EPS)
        np.testing.assert_allclose(m.natural_frequencies(np.full(3, 0.3)),
                                   w_ref * np.sqrt(7850.0 / rho), rtol=500 * EPS)


def test_frequencies_scale_as_thickness_up_to_rotary_inertia():
    # M(t) = t (M0 + t^2 M1) with 0 <= t^2 M1 <= (t / l_min)^2 M0 (the thickness term m t^2 / 12
    # beside the link's own m l^2 / 12) and K ∝ t^3: so omega / t lies in
    # [c / sqrt(1 + (t / l_min)^2), c], c = lim omega / t as t -> 0.
    lengths = np.array([0.1, 0.3, 0.25, 0.35])
    l_min = lengths.min()
    per_t = {}
    for t in (1e-5, 1e-4, 1e-3, 1e-2, 1e-1):  # 1e-5 m: the thinnest plausible member
        b = strip(t=t)
        per_t[t] = build_model(b, lengths, finite_segment_stiffness(b, lengths)) \
            .natural_frequencies() / t
    c = per_t[1e-5]
    for t, r in per_t.items():
        ratio = r / c
        assert np.all(ratio <= 1 + 1e-12) and np.all(ratio >= 1 / np.sqrt(1 + (t / l_min) ** 2)
                                                      - 1e-12), (t, ratio)
    # and the thin-plate limit is reached: at 0.1 mm the rotary term is below 1e-6 relative
    np.testing.assert_allclose(per_t[1e-4], c, rtol=1e-6)


def test_geometric_similarity_scales_frequencies_as_one_over_size():
    # scaling x, w and t by s: mass s^3, inertia s^5, EI/h s^3 -> omega ∝ 1/s exactly
    lengths = np.array([0.02, 0.5, 0.3, 0.18])
    base = Beam(np.array([0.0, 0.4, 1.0]), np.array([0.5, 0.1, 0.001]), 0.01)
    w0 = build_model(base, lengths, finite_segment_stiffness(base, lengths)) \
        .natural_frequencies(np.array([0.4, -1.0, 2.0]))
    for s in (1e-2, 1e3):  # to the ends of the plausible sizes, 1e-5 ... 1e3 m
        b = Beam(base.x_m * s, base.half_width_m * s, base.thickness_m * s)
        m = build_model(b, lengths * s, finite_segment_stiffness(b, lengths * s))
        # as above, scaling by s rounds the scaled matrices anew (5 EPS measured); kept: the
        # test's 1e-12
        np.testing.assert_allclose(m.natural_frequencies(np.array([0.4, -1.0, 2.0])), w0 / s,
                                   rtol=5000 * EPS)


def test_ill_conditioned_stiffness_raises_instead_of_returning_a_wrong_top_frequency():
    beam = strip(w=(0.2, 0.05))
    lengths = np.array([0.2, 0.3, 0.25, 0.25])
    # a spring spread of 1e14 with the stiff joint at the light end: the unguarded scaled
    # eigensolve loses the highest frequency (the mpmath solve shows it)
    k = np.array([1e10, 1e10, 1e-4])
    # build_model refuses a spring 1e6 below what the beam can hold: set them on the built chain
    model = build_model(beam, lengths, [1.0, 1.0, 1.0]).with_stiffness(k)
    q = np.array([0.1, -1.0, 0.5])
    ref = reference_omega2(model, q)
    A = model.mass_matrix(q) / np.sqrt(np.outer(k, k))
    mu = np.linalg.eigvalsh(A)
    cond = mu[-1] / mu[0]
    assert cond > eigen.COND_LIMIT
    unguarded = np.sort(1.0 / mu)
    err = np.abs(unguarded / ref - 1)
    assert err.max() > eigen.FREQUENCY_RTOL, f"cond {cond:.3g}: error {err.max():.2e}"
    with pytest.raises(SolveError, match="cannot be trusted"):
        model.natural_frequencies(q)
    with pytest.raises(SolveError, match=r"cannot be trusted \(pose 1\)"):
        model.natural_frequencies_batch(np.array([np.zeros(3), q]), stiffness=np.array(
            [[1.0, 1.0, 1.0], k]))
    with pytest.raises(SolveError, match="cannot be trusted"):
        model.modes(q)
    # a spread that stays under the limit is answered, and accurately
    k_ok = np.array([1e6, 1e6, 1e-1])
    ok = model.with_stiffness(k_ok)
    _, _, cA = conditioning(ok, q)
    assert cA < eigen.COND_LIMIT
    err = np.max(np.abs(ok.natural_frequencies(q, squared=True) / reference_omega2(ok, q) - 1))
    assert err <= 2 * EPS * cA, f"cond A {cA:.3g}: error {err:.2e}"


@pytest.mark.stress
@pytest.mark.slow
def test_extreme_conditioning_sweep_full():
    # every combination of taper, layout, thickness and modulus: either accurate to the rounding
    # bound against mpmath or a SolveError (never a silent wrong answer)
    rng = np.random.default_rng(7)
    for tname, w in TAPERS.items():
        for lname, lengths in SHORT.items():
            for t in (1e-4, 1e-2, 1e-1):
                for E in (1e6, 1e12):
                    beam = strip(t=t, E=E, w=w)
                    lengths = np.asarray(lengths)
                    model = build_model(beam, lengths, finite_segment_stiffness(beam, lengths))
                    q = rng.choice([0.0, 1e-12, 0.1, np.pi / 2, np.pi], model.n_joints)
                    cM, cK, cA = conditioning(model, q)
                    err = np.max(np.abs(model.natural_frequencies(q, squared=True)
                                        / reference_omega2(model, q) - 1))
                    assert err <= max(MP_RTOL, 2 * EPS * cA), \
                        f"{tname} {lname} t={t} E={E}: cond M {cM:.3g} A {cA:.3g} err {err:.2e}"


@pytest.mark.stress
@pytest.mark.slow
def test_random_stiffness_spreads_are_accurate_or_refused():
    beam = strip(w=(0.3, 0.02))
    rng = np.random.default_rng(11)
    answered = refused = 0
    for _ in range(150):
        n = int(rng.integers(2, 5))
        lengths = rng.dirichlet(np.ones(n + 1)) * 0.85 + 0.15 / (n + 1)
        lengths[-1] = 1.0 - lengths[:-1].sum()
        k = 10 ** rng.uniform(-4, 10, n)
        # spreads beyond what build_model takes (1e6 past the beam's springs): set on the chain
        model = build_model(beam, lengths, np.ones(n)).with_stiffness(k)
        q = rng.choice([0.0, 1e-6, 0.1, np.pi / 2, np.pi, -np.pi / 2], n)
        try:
            w2 = model.natural_frequencies(q, squared=True)
        except SolveError as exc:
            assert "cannot be trusted" in str(exc)
            refused += 1
            continue
        answered += 1
        err = np.max(np.abs(w2 / reference_omega2(model, q) - 1))
        assert err <= eigen.FREQUENCY_RTOL, f"k={k} q={q}: error {err:.2e}"
    assert answered > 50 and refused > 5, (answered, refused)


def test_mass_matrix_reference_is_consistent_for_uniform_strip():
    # the hand-written strip sections agree with the package's exact section integrals
    beam = strip(t=0.05, w=(0.1, 0.1))
    lengths = np.array([0.3, 0.3, 0.4])
    model = build_model(beam, lengths, [1.0, 1.0])
    # closed forms against section integrals: a few roundings (2.8 EPS measured); kept: the
    # test's 1e-13
    for got, ref in zip(chain_inputs(model), uniform_strip_sections(beam, lengths), strict=True):
        np.testing.assert_allclose(got, ref, rtol=500 * EPS)


def test_stiffness_at_the_ends_of_double_precision():
    beam = strip(w=(0.2, 0.05))
    lengths = np.array([0.3, 0.45, 0.25])
    base = build_model(beam, lengths, [1.0, 1.0])
    w1 = base.natural_frequencies()
    # springs of 1e-307 ... 1e300 N m/rad are answered exactly (omega ∝ sqrt(K))
    for c in (1e-307, 1e-150, 1e150, 1e300):
        # equal springs scale s = K^(-1/2) uniformly, so the scaled solve is unchanged and only
        # the final scaling rounds (0.7 EPS measured); kept: the test's 1e-14
        np.testing.assert_allclose(base.with_stiffness([c, c]).natural_frequencies(),
                                   w1 * np.sqrt(c), rtol=50 * EPS)
    # omega^2 beyond the largest double: a SolveError, not inf
    with pytest.raises(SolveError, match="overflows double precision"):
        base.with_stiffness([1e308, 1e308]).natural_frequencies()
    with pytest.raises(SolveError, match="overflows double precision"):
        base.with_stiffness([1e308, 1e308]).modes()
    # subnormal springs carry too few digits: rejected at the boundary, naming the field
    with pytest.raises(BeamInputError, match=r"stiffness\[1\] = 1e-320"):
        build_model(beam, lengths, [1.0, 1e-320])
    with pytest.raises(BeamInputError, match="stiffness"):
        dyn.natural_frequencies(base.pin_model, base.new_data(), np.array([1.0, 1e-320]))
    # a scaled eigenvalue lost below zero by rounding is a conditioning failure, not an
    # indefinite mass matrix (M stays positive definite: Cholesky succeeds)
    np.linalg.cholesky(base.mass_matrix())
    with pytest.raises(SolveError, match="cannot be trusted"):
        base.with_stiffness([1.0, 1.26e14]).natural_frequencies()
