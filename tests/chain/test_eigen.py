"""The scaled eigensolve of one pose (the fits' inner loop) against independent solutions.

One pose goes to LAPACK directly and its spectrum is guarded in Python floats; a stack goes
through numpy's batched solver. Both must give the generalised problem's frequencies and refuse
the same spectra."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as sla
from tolerances import EPS

from prbdm_pin.chain.eigen import COND_LIMIT, check_spectrum, modes_from_mass
from prbdm_pin.errors import SolveError
from prbdm_pin.fitting.evaluate import chain_frequencies


def _spd(rng, n):
    X = rng.normal(size=(n, n))
    return X @ X.T + n * np.eye(n)


@pytest.mark.parametrize("n", [1, 2, 4, 7])
def test_one_pose_equals_the_generalised_problem(n):
    rng = np.random.default_rng(n)
    for _ in range(20):
        M = _spd(rng, n) * 10.0 ** rng.uniform(-4.0, 1.0)
        K = 10.0 ** rng.uniform(2.0, 4.0, n)
        ref = np.sqrt(sla.eigh(np.diag(K), M, eigvals_only=True))  # Cholesky of M: another way
        w = chain_frequencies(M[None], K)
        assert w.shape == (1, n)
        # the reference's lowest w is good to eig_rtol(ref), <= 1.1e-13 over these draws (67 EPS
        # measured); M-orthonormality to about n EPS (w_max / w_min)^2 (<= 1e3 EPS; 134
        # measured), P^T K P to n EPS w_max^2: kept, the tests' 1e-12 (of w_max^2 for the
        # last)
        np.testing.assert_allclose(w[0], ref, rtol=5000 * EPS)
        # a stack goes through the batched solver: the doubled mass lowers omega by sqrt(2)
        W = chain_frequencies(np.stack([M, 2.0 * M]), K)
        np.testing.assert_allclose(W[1], ref / math.sqrt(2.0), rtol=5000 * EPS)
        omega, Phi = modes_from_mass(M[None], K)
        P = Phi[0]
        np.testing.assert_allclose(omega[0], ref, rtol=5000 * EPS)
        np.testing.assert_allclose(P.T @ M @ P, np.eye(n), rtol=0, atol=5000 * EPS)
        np.testing.assert_allclose(P.T @ np.diag(K) @ P, np.diag(ref**2), rtol=0,
                                   atol=5000 * EPS * ref.max() ** 2)


def test_diagonal_chain_in_closed_form_across_the_range_of_double():
    # omega_i^2 = k_i / m_i for a diagonal mass matrix, from springs of 1e-150 to 1e150 N m/rad:
    # the overflow checks are skipped only where they cannot fail
    m = np.array([2.0, 0.5, 1.0])
    for scale in (1e-150, 1.0, 1e150):
        K = scale * np.array([3.0, 1.0, 2.0])
        # a diagonal pencil: a few roundings on either side (2 EPS measured); kept: the
        # test's 1e-14
        np.testing.assert_allclose(chain_frequencies(np.diag(m)[None], K)[0],
                                   np.sort(np.sqrt(K / m)), rtol=50 * EPS)
        omega, _ = modes_from_mass(np.diag(m)[None], K)
        np.testing.assert_allclose(omega[0], np.sort(np.sqrt(K / m)), rtol=50 * EPS)
    with pytest.raises(SolveError, match="overflows"):
        chain_frequencies(1e-300 * np.diag(m)[None], 1e300 * np.array([3.0, 1.0, 2.0]))


GOOD = np.array([0.2, 0.5, 1.0])
BAD = {
    "negative": [-1e-3, 0.5, 1.0],
    "zero": [0.0, 0.5, 1.0],
    "nan inside": [1e-3, math.nan, 1.0],
    "infinite": [1e-3, 0.5, math.inf],
    "ill-conditioned": [1.0 / (2.0 * COND_LIMIT), 0.5, 1.0],
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_the_guard_refuses_one_pose_as_it_refuses_a_stack(name):
    bad = np.array(BAD[name])
    for mu in (bad, bad[None], np.stack([GOOD, bad]), np.stack([bad, GOOD])):
        with pytest.raises(SolveError):
            check_spectrum(mu)


def test_the_guard_answers_within_its_limit():
    ok = np.array([2.0 / COND_LIMIT, 0.5, 1.0])  # cond = COND_LIMIT / 2
    for mu in (ok, ok[None], np.stack([GOOD, ok])):
        check_spectrum(mu)
