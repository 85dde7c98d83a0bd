"""The compiled one-chain eigensolver (chain/small_eigen) against independent solutions.

Its eigenvalues against 40-digit mpmath solves and LAPACK, its triangle and guard against
LAPACK's path in eig_scaled, and a model's frequencies through it against the generalised
problem K phi = w^2 M phi solved by scipy (Cholesky of M, another algorithm)."""

from __future__ import annotations

import mpmath
import numpy as np
import pinocchio as pin
import pytest
import scipy.linalg as sla
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.chain import pin_dynamics as dyn
from prbdm_pin.chain.eigen import _SAFE_SCALE, COND_LIMIT, eig_scaled, one_chain
from prbdm_pin.chain.small_eigen import scaled_omega
from prbdm_pin.errors import BeamInputError, SolveError

BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)


def _graded_spd(rng, n):
    # a positive definite matrix graded over 1e-3..1e3 by a diagonal congruence, as a chain's
    # S M S is (its root joints heavy, its tip joints light)
    X = rng.normal(size=(n, n))
    D = np.exp(rng.uniform(-3.5, 3.5, n))
    return D[:, None] * (X @ X.T + 1e-2 * np.eye(n)) * D[None, :]


def _mu(w2, s):
    """Eigenvalues mu of S M S (ascending) from omega^2 (ascending) and s, as eig_scaled scales."""
    return (1.0 / s.max()) ** 2 / w2[::-1]


@pytest.mark.parametrize("n", [1, 2, 3, 5, 8, 16])
def test_eigenvalues_against_mpmath_and_lapack(n):
    rng = np.random.default_rng(100 + n)
    mpmath.mp.dps = 40
    for _ in range(4 if n == 16 else 8):
        A = _graded_spd(rng, n)
        s = np.ones(n)  # S = I: the kernel's mu are A's eigenvalues
        w2 = np.empty(n)
        if not scaled_omega(A, s, np.empty(0), w2, True, False, COND_LIMIT, _SAFE_SCALE):
            continue  # refused by the guard: the LAPACK path's business (tested below)
        mu = _mu(w2, s)
        exact = np.array(sorted(float(x) for x in mpmath.eigsy(mpmath.matrix(A.tolist()),
                                                               eigvals_only=True)))
        lapack = sla.eigvalsh(A)
        # Householder tridiagonalisation and QL are backward stable: every eigenvalue is off
        # by at most p(n) EPS ||A|| with p(n) of order n (Wilkinson); measured up to 7 EPS
        # mu_max over n <= 16, LAPACK's dsyevd alike. Bound 2 n EPS mu_max.
        assert np.max(np.abs(mu - exact)) <= 2 * n * EPS * exact[-1]
        assert np.max(np.abs(lapack - exact)) <= 2 * n * EPS * exact[-1]


@pytest.mark.parametrize("lower", [False, True])
def test_graded_matrices_keep_their_small_eigenvalues_relative(lower):
    # A = D B D with D falling by 10^0.8 a row: a chain's S M S is graded so (heavy root).
    # Householder from the large end keeps every eigenvalue to about n cond(B) EPS relative
    # (not only to EPS mu_max); LAPACK reduces from the last row for the upper triangle and
    # from the first for the lower, and so must the kernel: the other direction loses 1e8
    # EPS on the smallest here, which the fits' central differences see as noise
    rng = np.random.default_rng(5)
    mpmath.mp.dps = 50
    n = 6
    for _ in range(5):
        X = rng.normal(size=(n, n))
        B = X @ X.T + n * np.eye(n)
        D = 10.0 ** (-0.8 * np.arange(n))
        A = D[:, None] * B * D[None, :]
        if not lower:
            A = A[::-1, ::-1].copy()  # large at the bottom right: the upper triangle's way
        w2 = np.empty(n)
        assert scaled_omega(A, np.ones(n), np.empty(0), w2, True, lower, COND_LIMIT,
                            _SAFE_SCALE)
        mu = _mu(w2, np.ones(n))
        exact = np.array(sorted(float(x) for x in mpmath.eigsy(mpmath.matrix(A.tolist()),
                                                               eigvals_only=True)))
        lapack = sla.eigvalsh(A, lower=lower)
        # relative accuracy of a graded matrix: p(n) cond(B) EPS; measured over 40 draws up
        # to 78 n cond(B) EPS here (LAPACK 23 n), the wrong direction 1e8 EPS: bound 200 n
        bound = 200 * n * np.linalg.cond(B) * EPS
        assert np.max(np.abs(mu - exact) / exact) <= bound
        assert np.max(np.abs(lapack - exact) / exact) <= bound


@pytest.mark.parametrize("lower", [False, True])
def test_reads_the_triangle_lapack_reads(lower):
    # an unsymmetric M: the two triangles give two different symmetric matrices, and the
    # kernel must solve the one eig_scaled's LAPACK call reads
    rng = np.random.default_rng(7)
    n = 5
    M = _graded_spd(rng, n)
    M[np.tril_indices(n, -1)] *= 1.0 + 0.1 * rng.uniform(size=n * (n - 1) // 2)
    s = rng.uniform(0.2, 1.0, n)
    w = one_chain(M, s, lower=lower)
    sym = np.tril(M) + np.tril(M, -1).T if lower else np.triu(M) + np.triu(M, 1).T
    ref = np.sqrt(sla.eigh(np.diag(1.0 / s**2), sym, eigvals_only=True))
    # the spread of the frequencies bounds the relative error of the lowest: n EPS
    # (w_max / w_min)^2, 1e-10 here; a wrong triangle is off by about 10 %
    tol = n * EPS * (ref[-1] / ref[0]) ** 2
    np.testing.assert_allclose(w, ref, rtol=tol)


@pytest.mark.parametrize("n", [1, 2, 4, 7, 12])
def test_model_frequencies_equal_the_generalised_problem(n):
    rng = np.random.default_rng(n)
    lengths = rng.uniform(0.5, 1.5, n + 1)
    lengths *= 1.0 / lengths.sum()
    k = 10.0 ** rng.uniform(2.0, 4.0, n)
    model = pp.build_model(BEAM, lengths, k)
    for q in (None, rng.uniform(-0.5, 0.5, n)):
        M = pin.crba(model.pin_model, model.pin_model.createData(),
                     np.zeros(n) if q is None else q)
        ref = np.sqrt(sla.eigh(np.diag(k), M, eigvals_only=True))  # Cholesky of M
        w = model.natural_frequencies(q)
        w2 = model.natural_frequencies(q, squared=True)
        # the reference's lowest w is good to n EPS (w_max / w_min)^2 / 2 (the unscaled
        # solve; tolerances.eig_rtol), the kernel's highest to about EPS cond(S M S)
        tol = n * EPS * (ref[-1] / ref[0]) ** 2
        np.testing.assert_allclose(w, ref, rtol=tol)
        np.testing.assert_allclose(w2, ref**2, rtol=2 * tol)
        np.testing.assert_allclose(dyn.natural_frequencies(model.pin_model, model.new_data(),
                                                           k, q), ref, rtol=tol)


def test_refused_spectra_take_the_lapack_path_and_its_errors():
    rng = np.random.default_rng(3)
    n = 4
    M = _graded_spd(rng, n)
    s = np.ones(n)
    # not positive definite: the kernel refuses, the LAPACK path names the cause
    bad = M - 2.0 * np.linalg.eigvalsh(M)[0] * np.eye(n)
    assert one_chain(bad, s) is None
    with pytest.raises(SolveError, match="not positive definite"):
        eig_scaled(bad, s)
    # beyond the conditioning limit
    D = np.diag([1.0, 1.0, 1.0, 1e-10])  # cond 1e10 > COND_LIMIT = 4.5e9
    assert one_chain(D, s) is None
    with pytest.raises(SolveError, match="cannot be trusted"):
        eig_scaled(D, s)
    # a tridiagonal outside the kernel's range: LAPACK answers, the closed form of a
    # diagonal pencil w^2 = 1 / m_i (to a few roundings: 4 EPS)
    tiny = np.diag([2e-150, 1e-150, 4e-150])
    assert one_chain(tiny, np.ones(3)) is None
    np.testing.assert_allclose(eig_scaled(tiny, np.ones(3)),
                               np.sqrt(1.0 / np.array([4e-150, 2e-150, 1e-150])), rtol=4 * EPS)
    # not float64, or a shape the numpy path refuses: not for the kernel
    assert one_chain(np.eye(3, dtype=np.float32), np.ones(3)) is None
    assert one_chain(np.eye(3), np.ones(4)) is None
    with pytest.raises(ValueError):
        eig_scaled(np.eye(3), np.ones(4))


def test_a_non_finite_pose_is_named():
    model = pp.build_model(BEAM, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    for q in ([np.nan, 0.0], [0.0, np.inf]):
        with pytest.raises(BeamInputError, match="q = .*must be finite"):
            model.natural_frequencies(np.array(q))
    with pytest.raises(BeamInputError, match=r"q has shape \(3,\)"):
        model.natural_frequencies(np.zeros(3))
