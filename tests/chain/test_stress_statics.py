"""Stress: statics over load index 1e-6 ... 20 and directions from axial compression to transverse.

The reference is an independent elastica solve written here with scipy's solve_bvp: with the
tangent angle theta(s) (rotation about +y, tip to -z for theta > 0) and a dead tip force
F = P (-cos beta, 0, -sin beta) (beta = 0 axial compression, beta = 90 deg transverse down),
stationarity of 1/2 ∫ EI theta'^2 ds - F . p_tip gives EI theta'' = -P sin(theta + beta),
theta(0) = 0, theta'(L) = 0, and p' = (cos theta, 0, -sin theta).
"""

import numpy as np
import pytest
from scipy.integrate import solve_bvp

from prbdm_pin.errors import SolveError
from prbdm_pin.member.geometry import Beam
from prbdm_pin.model.prbdm_model import build_model

BEAM = Beam(np.array([0.0, 1.0]), np.array([0.025, 0.025]), 0.01)
EI, L = BEAM.root_EI_Nm2, BEAM.length_m
ALPHA_CR = np.pi**2 / 4  # Euler load of the clamped-free column, P L^2 / EI


def chain(n):
    h = L / n
    lengths = np.concatenate([[h / 2], np.full(n - 1, h), [h / 2]])
    return build_model(BEAM, lengths, np.full(n, EI / h), min_fraction=0.0)


def force(alpha, beta):
    return alpha * EI / L**2 * np.array([-np.cos(beta), 0.0, -np.sin(beta)])


def elastica_tip(alpha, beta, guess_theta=None):
    """Tip (x, z) / L of the elastica from solve_bvp, continued in load from the linear guess."""
    s = np.linspace(0.0, 1.0, 201)

    def rhs(s, y):
        th, k = y[0], y[1]
        return np.vstack([k, -a * np.sin(th + beta), np.cos(th), -np.sin(th)])

    def bc(y0, y1):
        return np.array([y0[0], y1[1], y0[2], y0[3]])

    y = np.zeros((4, s.size))
    y[2] = s
    steps = np.linspace(0.0, alpha, max(2, int(np.ceil(alpha / 0.5)) + 1))[1:]
    if guess_theta is not None:  # start on a chosen branch at the full load
        steps = [alpha]
    for a in steps:
        if np.allclose(y[0], 0.0):
            # linear cantilever shape as a start: theta = a sin(beta) (s - s^2 / 2)
            y[0] = a * np.sin(beta) * (s - s**2 / 2) if guess_theta is None else guess_theta(s)
            y[1] = np.gradient(y[0], s)
        sol = solve_bvp(rhs, bc, s, y, tol=1e-7, max_nodes=20000)
        assert sol.success, sol.message
        s, y = sol.x, sol.y
    return y[2, -1], y[3, -1]


def check_equilibrium(model, q, F):
    JtF = model.tip_jacobian(q).T @ F
    r = np.linalg.norm(model.stiffness_Nm_per_rad * q - JtF)
    assert r <= 1e-8 * max(np.linalg.norm(JtF), np.linalg.norm(model.stiffness_Nm_per_rad * q))


@pytest.mark.parametrize("alpha,beta_deg", [(1.0, 90.0), (5.0, 45.0)])
def test_64_joint_chain_matches_independent_elastica_cheap(alpha, beta_deg):
    model = chain(64)
    beta = np.radians(beta_deg)
    q, p = model.static_deflection(force(alpha, beta))
    x, z = elastica_tip(alpha, beta)
    assert np.hypot(p[0] / L - x, p[2] / L - z) < 1e-3, (p, x, z)


def test_small_load_increments_give_small_tip_changes_cheap():
    model = chain(16)
    alphas = np.linspace(0.5, 3.0, 26)
    tips = np.array([model.static_deflection(force(a, np.radians(30.0)))[1] for a in alphas])
    steps = np.linalg.norm(np.diff(tips, axis=0), axis=1) / L
    assert_continuous(steps, np.diff(alphas))


def assert_continuous(steps, da, slope=1.0):
    """No jump: |d tip| / d alpha <= ``slope`` L, and no step an isolated outlier (> 2.5x both
    neighbours): a switch of branch moves the tip by a finite amount in one small step."""
    rate = steps / da
    assert np.all(rate <= slope), rate
    inner = rate[1:-1]
    assert not np.any((inner > 2.5 * rate[:-2]) & (inner > 2.5 * rate[2:]) & (inner > 1e-3)), rate


@pytest.mark.stress
@pytest.mark.slow
@pytest.mark.parametrize("beta_deg", [0.0, 1.0, 10.0, 30.0, 60.0, 90.0, 120.0, 180.0])
def test_load_path_converges_and_is_continuous_full(beta_deg):
    """alpha from 1e-6 to 20: converge (with the equilibrium verified) or raise SolveError."""
    model = chain(32)
    beta = np.radians(beta_deg)
    alphas = np.concatenate([np.logspace(-6, -1, 6), np.linspace(0.2, 20.0, 100)])
    tips, ok = [], []
    for a in alphas:
        F = force(a, beta)
        try:
            q, p = model.static_deflection(F)
        except SolveError:
            ok.append(False)
            tips.append(np.full(3, np.nan))
            continue
        check_equilibrium(model, q, F)
        ok.append(True)
        tips.append(p)
    tips = np.array(tips)
    assert all(ok), f"beta={beta_deg}: SolveError at alpha {alphas[~np.array(ok)]}"
    # the chain's own buckling load (its straight-pose Hessian K - P T loses definiteness)
    steps = np.linalg.norm(np.diff(tips, axis=0), axis=1) / L
    da = np.diff(alphas)
    if beta_deg in (0.0, 180.0):
        disp = np.linalg.norm(tips - [L, 0, 0], axis=1) / L
        if beta_deg == 180.0:  # tension: the straight pose is the stable minimum throughout
            assert np.all(disp < 1e-12)  # sin(pi) leaves a 1e-16 transverse load
        else:
            # straight up to the bifurcation, then the buckled branch grows continuously
            straight = disp < 1e-12
            a_last = alphas[straight].max()
            a_first = alphas[~straight].min()
            assert a_last < ALPHA_CR * 1.01 and a_first > ALPHA_CR * 0.99, (a_last, a_first)
            # the problem is symmetric in z -> -z and each solve picks a side at the saddle:
            # continuity holds for the mirror-invariant tip (x, |z|) beyond the first buckled step
            post = np.flatnonzero(~straight)
            mirror = np.column_stack([tips[post, 0], np.abs(tips[post, 2])])
            steps = np.linalg.norm(np.diff(mirror, axis=0), axis=1) / L
            assert_continuous(steps[1:], da[post[1:-1]])
        return
    # near-axial loads amplify the imperfection around alpha_cr: allow a steeper slope there
    assert_continuous(steps[6:], da[6:], slope=1.0 / max(np.sin(beta), 0.1))


@pytest.mark.stress
@pytest.mark.slow
@pytest.mark.parametrize("beta_deg", [5.0, 30.0, 60.0, 90.0, 135.0])
@pytest.mark.parametrize("alpha", [1e-3, 1.0, 5.0, 20.0])
def test_64_joint_chain_matches_independent_elastica_full(alpha, beta_deg):
    model = chain(64)
    beta = np.radians(beta_deg)
    q, p = model.static_deflection(force(alpha, beta))
    check_equilibrium(model, q, force(alpha, beta))
    x, z = elastica_tip(alpha, beta)
    assert np.hypot(p[0] / L - x, p[2] / L - z) < 1e-3, (p, x, z)


@pytest.mark.stress
@pytest.mark.slow
def test_postbuckled_column_matches_elastica():
    # beyond the Euler load the chain leaves the straight saddle; compare |z| with the buckled
    # elastica branch (solve_bvp started from the first buckling mode)
    model = chain(64)
    for alpha in (3.0, 6.0, 12.0):
        q, p = model.static_deflection(force(alpha, 0.0))
        amp = q.sum()  # only picks the branch: solve_bvp converges to its own solution
        x, z = elastica_tip(alpha, 0.0, guess_theta=lambda s, a=amp: a * np.sin(np.pi * s / 2))
        assert abs(p[0] / L - x) < 1e-3 and abs(p[2] / L - z) < 1e-3, (alpha, p, x, z)


@pytest.mark.stress
@pytest.mark.slow
@pytest.mark.parametrize("w", [(0.5, 0.0005), (0.0005, 0.5)], ids=["narrowing", "widening"])
def test_tapered_1000_to_1_load_sweep_converges_or_raises(w):
    from prbdm_pin.chain.stiffness import finite_segment_stiffness

    beam = Beam(np.array([0.0, 1.0]), np.array(w), 0.01)
    n = 32
    h = 1.0 / n
    lengths = np.concatenate([[h / 2], np.full(n - 1, h), [h / 2]])
    model = build_model(beam, lengths, finite_segment_stiffness(beam, lengths, min_fraction=0.0),
                        min_fraction=0.0)
    EI_root = beam.root_EI_Nm2
    for beta_deg in (10.0, 90.0):
        b = np.radians(beta_deg)
        tips = []
        alphas = np.concatenate([np.logspace(-6, -1, 6), np.linspace(0.2, 20.0, 34)])
        for a in alphas:
            F = a * EI_root * np.array([-np.cos(b), 0.0, -np.sin(b)])
            try:
                q, p = model.static_deflection(F)
            except SolveError as exc:
                assert "no equilibrium" in str(exc)
                tips.append(np.full(3, np.nan))
                continue
            check_equilibrium(model, q, F)
            tips.append(p)
        tips = np.array(tips)
        assert np.all(np.isfinite(tips)), (w, beta_deg)
        # the tip's distance from the clamp never exceeds the length (inextensible chain)
        assert np.all(np.linalg.norm(tips, axis=1) <= 1.0 + 1e-12)
