"""The closed-form planar chain (prbdm_pin.chain.planar) against Pinocchio on the same chain, in one
place: tip, linear Jacobian, J^T F against the frame Jacobian, the load stiffness against central
differences, M(q) against CRBA, the joints and centres of mass against Pinocchio's placements, and
stacks of designs and poses against one case at a time."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from paths import BEAMS
from tolerances import EPS

from prbdm_pin.chain.layout import sample_lengths
from prbdm_pin.chain.pin_dynamics import mass_matrices
from prbdm_pin.chain.planar import (
    ChainPotential,
    chain_points,
    force_and_load_stiffness,
    generalised_force,
    load_stiffness,
    planar_mass_matrices,
    planar_tip,
    planar_tips,
    tip_jacobians,
    tip_positions,
    tip_terms,
)
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.member.random_beams import random_beam
from prbdm_pin.model.prbdm_model import build_model


def _beams():
    rng = np.random.default_rng(7)
    return [load_beam(p) for p in sorted(BEAMS.glob("*.json"))] + [
        random_beam(rng) for _ in range(3)
    ]


def _designs(rng, n, count=3):
    """Random chains of ``n`` joints: (beam, lengths (n+1,), springs (n,), Pinocchio model)."""
    beam = random_beam(rng)
    for lengths in sample_lengths(rng, beam.length_m, n + 1, count):
        k = 10.0 ** rng.uniform(0.0, 3.0, n)
        yield beam, lengths, k, build_model(beam, lengths, k)


def _force(rng):
    return rng.normal(size=3) * 10.0 ** rng.uniform(0.0, 3.0)


@pytest.mark.parametrize("n", [1, 2, 3, 5, 8])
def test_planar_mass_matrix_equals_pinocchio_crba(n):
    rng = np.random.default_rng(n)
    for beam in _beams():
        for lengths in sample_lengths(rng, beam.length_m, n + 1, 3):
            model = build_model(beam, lengths, np.ones(n))
            s = model.sections
            Q = rng.uniform(-2.0, 2.0, (4, n))
            ref = mass_matrices(model.pin_model, model.new_data(), Q)
            M = planar_mass_matrices(lengths, s.mass_kg, s.com_m[:, 0] - s.start_m,
                                     s.inertia_com_kg_m2[:, 1, 1], Q)
            assert np.max(np.abs(M - ref)) <= 1e-13 * np.max(np.abs(ref))


def test_planar_tip_equals_pinocchio_kinematics():
    rng = np.random.default_rng(3)
    beam = load_beam(BEAMS / "reference-random.json")
    for n in (1, 4, 7):
        for lengths in sample_lengths(rng, beam.length_m, n + 1, 3):
            model = build_model(beam, lengths, np.ones(n))
            q = rng.uniform(-1.5, 1.5, n)
            p, J = planar_tip(lengths, q)
            # two kinematics of up to 7 links: about n roundings of the 1 m chain (1 EPS m
            # measured); kept: the tests' 1e-14 m
            tol = 50 * EPS * beam.length_m
            np.testing.assert_allclose(p, model.tip_position(q), rtol=0, atol=tol)
            np.testing.assert_allclose(J, model.tip_jacobian(q), rtol=0, atol=tol)
            # the one-pass call of the statics path gives the same placement and Jacobian
            pk, Jk = model.tip_kinematics(q)
            np.testing.assert_allclose(pk, p, rtol=0, atol=tol)
            np.testing.assert_allclose(Jk, J, rtol=0, atol=tol)
            assert Jk.shape == (3, n)


@pytest.mark.parametrize("n", [1, 2, 5, 12])
def test_tips_and_jacobians_equal_pinocchio_at_random_poses(n):
    rng = np.random.default_rng(100 + n)
    for _, lengths, _, model in _designs(rng, n):
        Q = rng.uniform(-3.0, 3.0, (6, n))
        P, J = tip_positions(lengths, Q), tip_jacobians(lengths, Q)
        assert P.shape == (6, 3) and J.shape == (6, 3, n)
        scale = lengths.sum()
        # about n <= 12 roundings of the chain's length (2 EPS measured); kept: the tests'
        # 1e-14 of it
        for q, p, j in zip(Q, P, J, strict=True):
            np.testing.assert_allclose(p, model.tip_position(q), rtol=0, atol=50 * EPS * scale)
            np.testing.assert_allclose(j, model.tip_jacobian(q), rtol=0, atol=50 * EPS * scale)


@pytest.mark.parametrize("n", [1, 3, 6])
def test_generalised_force_equals_pinocchio_frame_jacobian(n):
    rng = np.random.default_rng(200 + n)
    for _, lengths, _, model in _designs(rng, n):
        data = model.new_data()
        for _ in range(4):
            q, F = rng.uniform(-3.0, 3.0, n), _force(rng)
            Jp = pin.computeFrameJacobian(model.pin_model, data, q, model.tip_frame_id,
                                          pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)[:3]
            ref = Jp.reshape(3, n).T @ F
            tau = generalised_force(lengths, q, F)
            assert tau.shape == (n,)
            # J^T F: sums of n terms of at most L |F| (0.4 EPS of it measured); kept: the
            # test's 1e-13 of L |F|
            np.testing.assert_allclose(tau, ref, rtol=0,
                                       atol=500 * EPS * lengths.sum() * np.abs(F).max())


@pytest.mark.parametrize("n", [1, 2, 4, 7])
def test_load_stiffness_equals_central_differences_of_pinocchio(n):
    rng = np.random.default_rng(300 + n)
    h = 1e-6
    for _, lengths, _, model in _designs(rng, n):
        for _ in range(3):
            q, F = rng.uniform(-2.0, 2.0, n), _force(rng)
            S = load_stiffness(lengths, q, F)
            assert S.shape == (n, n)
            np.testing.assert_array_equal(S, S.T)
            fd = np.column_stack([
                (model.tip_jacobian(q + h * e).T @ F - model.tip_jacobian(q - h * e).T @ F)
                / (2 * h) for e in np.eye(n)])
            np.testing.assert_allclose(S, fd, rtol=0,
                                       atol=1e-7 * lengths.sum() * np.abs(F).max())
            tau, S2 = force_and_load_stiffness(lengths, q, F)
            np.testing.assert_array_equal(tau, generalised_force(lengths, q, F))
            np.testing.assert_array_equal(S2, S)


@pytest.mark.parametrize("n", [1, 3, 6])
def test_tip_terms_equal_pinocchio_and_central_differences(n):
    # the one-pass terms of the equilibrium's derivatives: tip and Jacobian against Pinocchio,
    # the load stiffness against central differences of Pinocchio's J^T F
    rng = np.random.default_rng(400 + n)
    h = 1e-6
    for _, lengths, _, model in _designs(rng, n):
        q, F = rng.uniform(-2.0, 2.0, n), _force(rng)
        p, J, T, c, s = tip_terms(lengths, q, F)
        scale = lengths.sum()
        # as in test_tips_and_jacobians_equal_pinocchio_at_random_poses (kept: 1e-14 of L)
        np.testing.assert_allclose(p, model.tip_position(q), rtol=0, atol=50 * EPS * scale)
        np.testing.assert_allclose(J, model.tip_jacobian(q), rtol=0, atol=50 * EPS * scale)
        fd = np.column_stack([
            (model.tip_jacobian(q + h * e).T @ F - model.tip_jacobian(q - h * e).T @ F)
            / (2 * h) for e in np.eye(n)])
        np.testing.assert_allclose(T, fd, rtol=0, atol=1e-7 * scale * np.abs(F).max())
        # cos and sin of the same angles (exact here); kept: the test's 1e-15
        np.testing.assert_allclose(c + 1j * s, np.exp(1j * np.cumsum(q)), rtol=0, atol=5 * EPS)


@pytest.mark.parametrize("n", [1, 2, 5])
def test_chain_points_equal_pinocchio_placements(n):
    # joints and centres of mass of the links (x and -z) against Pinocchio's forward kinematics
    rng = np.random.default_rng(500 + n)
    for _, lengths, _, model in _designs(rng, n):
        s = model.sections
        off = s.com_m[:, 0] - s.start_m
        Q = rng.uniform(-2.0, 2.0, (3, n))
        axes, joints, coms = chain_points(lengths[None], off[None], Q)
        assert axes.shape == (3, 2, n + 1) and joints.shape == coms.shape == (1, 3, 2, n)
        data, pm = model.new_data(), model.pin_model
        tol = 1e-14 * lengths.sum()
        for i, q in enumerate(Q):
            pin.forwardKinematics(pm, data, q)
            for j in range(1, n + 1):
                pj = data.oMi[j].translation
                pc = data.oMi[j].act(pm.inertias[j].lever)
                np.testing.assert_allclose(joints[0, i, :, j - 1], [pj[0], -pj[2]], atol=tol)
                np.testing.assert_allclose(coms[0, i, :, j - 1], [pc[0], -pc[2]], atol=tol)


@pytest.mark.parametrize("n", [1, 3, 8])
def test_stacks_equal_one_case_at_a_time(n):
    rng = np.random.default_rng(400 + n)
    B = 5
    L = sample_lengths(rng, 0.2, n + 1, B)
    Q = rng.uniform(-2.0, 2.0, (B, n))
    F = _force(rng)
    tips, J = tip_positions(L, Q), tip_jacobians(L, Q)
    tau, S = generalised_force(L, Q, F), load_stiffness(L, Q, F)
    np.testing.assert_array_equal(planar_tips(L, Q), tips)
    for b in range(B):
        p1, J1 = planar_tip(L[b], Q[b])
        # the stack sums its cosines in another order: a rounding of the 0.2 m chain (0.7
        # EPS of it measured); kept: the test's 1e-15 m
        np.testing.assert_allclose(tips[b], p1, rtol=0, atol=5 * EPS)
        np.testing.assert_array_equal(J[b], J1)
        np.testing.assert_array_equal(tau[b], generalised_force(L[b], Q[b], F))
        np.testing.assert_array_equal(S[b], load_stiffness(L[b], Q[b], F))
    # one chain at many poses: lengths (n+1,) serve every row
    np.testing.assert_array_equal(tip_positions(L[0], Q), tip_positions(np.tile(L[0], (B, 1)), Q))
    # stacked designs of the mass matrix against one design at a time
    mass, off, iyy = rng.uniform(0.01, 0.1, (3, B, n + 1))
    M = planar_mass_matrices(L, mass, off * L, iyy * 1e-4, Q[:3])
    assert M.shape == (B, 3, n, n)
    for b in range(B):
        np.testing.assert_array_equal(
            M[b], planar_mass_matrices(L[b], mass[b], off[b] * L[b], iyy[b] * 1e-4, Q[:3]))


@pytest.mark.parametrize("n", [2, 5])
def test_potential_of_a_stack_equals_its_chains(n):
    rng = np.random.default_rng(500 + n)
    B = 4
    L = sample_lengths(rng, 0.2, n + 1, B)
    K = 10.0 ** rng.uniform(1.0, 3.0, (B, n))
    F = _force(rng)
    Q = rng.uniform(-1.0, 1.0, (B, n))
    stack = ChainPotential(L, K, F)
    rows = np.arange(B)[::-1]
    g, H, scale = stack.derivatives(Q[rows], rows=rows)
    v = stack.value(Q[rows], rows=rows)
    g0, H0, s0 = stack.derivatives(Q[rows], rows=rows, hessian=False)
    assert H0 is None
    np.testing.assert_array_equal(g0, g)
    for i, r in enumerate(rows):
        one = ChainPotential(L[r], K[r], F)
        g1, H1, s1 = one.derivatives(Q[r], 1.0)
        # a stack row against its chain alone: the same terms, summed in another order where
        # at all (<= 0.9 EPS measured); kept: the tests' 1e-14 and 1e-15
        np.testing.assert_allclose(g[i], g1, rtol=50 * EPS, atol=50 * EPS * s1)
        np.testing.assert_array_equal(H[i], H1)
        np.testing.assert_allclose(scale[i], s1, rtol=5 * EPS)
        np.testing.assert_allclose(v[i], one.value(Q[r], 1.0), rtol=50 * EPS)
        # gradient and Hessian are K q - J^T F and diag(K) - d(J^T F)/dq
        np.testing.assert_array_equal(g1, K[r] * Q[r] - generalised_force(L[r], Q[r], F))
        np.testing.assert_array_equal(H1, np.diag(K[r]) - load_stiffness(L[r], Q[r], F))


def test_hessian_is_exact():
    rng = np.random.default_rng(5)
    lengths = np.array([0.1, 0.25, 0.2, 0.3, 0.15])
    k = np.array([900.0, 700.0, 400.0, 150.0])
    F = np.array([-800.0, 0.0, -1500.0])
    pot = ChainPotential(lengths, k, F)
    m = build_model(load_beam(BEAMS / "reference-random.json"), lengths, k)
    for _ in range(3):
        q = rng.uniform(-1.5, 1.5, 4)
        g, H, _ = pot.derivatives(q, 1.0)
        # gradient against Pinocchio's Jacobian, Hessian against central differences
        # atol: k q - J^T F cancels terms of ~1e3 N m, so it is good to ~EPS 1e3 absolute;
        # rtol: kept, the test's 1e-12 (46 EPS measured)
        np.testing.assert_allclose(g, k * q - m.tip_jacobian(q).T @ F, rtol=5000 * EPS,
                                   atol=1e-10)
        h = 1e-6
        Hfd = np.column_stack([
            (pot.derivatives(q + h * e, 1.0)[0] - pot.derivatives(q - h * e, 1.0)[0]) / (2 * h)
            for e in np.eye(4)
        ])
        np.testing.assert_allclose(H, Hfd, rtol=1e-7, atol=1e-6)
        np.testing.assert_array_equal(H, H.T)
