"""linearize's first-order form and damping through their direct LAPACK and spring paths.

``first_order`` solves M X = [K, C_d, B_q] by one Cholesky solve (LAPACK ``posv``): checked
against numpy's LU solve and against the state equation it must satisfy; a mass matrix that is
not positive definite is refused. The modal damping of a plain chain (the model's springs, no
matrix checks) must give every mode its ratio: Phi^T C Phi = diag(2 xi w) with the modes of
scipy's generalised solve."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.errors import SolveError
from prbdm_pin.plant.linearize import first_order

BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)


def _spd(rng, n):
    X = rng.normal(size=(n, n))
    return X @ X.T + n * np.eye(n)


@pytest.mark.parametrize("n", [1, 3, 6])
def test_first_order_against_an_lu_solve(n):
    rng = np.random.default_rng(n)
    M, K, Cd = _spd(rng, n), _spd(rng, n), _spd(rng, n)
    Bq = rng.normal(size=(n, 2))
    A, B, X = first_order(M, K, Cd, Bq)
    ref = np.linalg.solve(M, np.hstack([K, Cd, Bq]))  # LU with pivoting: another algorithm
    # both are backward stable: they agree to about cond(M) EPS of the largest entry
    tol = 10 * n * np.linalg.cond(M) * EPS * np.abs(ref).max()
    np.testing.assert_allclose(X, ref, rtol=0, atol=tol)
    # the state equation: M v' = -K q - C_d v + B_q u, q' = v, exactly by construction
    np.testing.assert_array_equal(A[:n, n:], np.eye(n))
    np.testing.assert_array_equal(A[:n, :n], np.zeros((n, n)))
    np.testing.assert_array_equal(A[n:, :n], -X[:, :n])
    np.testing.assert_array_equal(B[n:], X[:, 2 * n:])
    np.testing.assert_array_equal(B[:n], np.zeros((n, 2)))


def test_first_order_refuses_a_mass_matrix_not_positive_definite():
    M = np.diag([1.0, -1.0, 2.0])
    I3 = np.eye(3)
    with pytest.raises(SolveError, match="not positive definite"):
        first_order(M, I3, I3, np.ones((3, 1)))


@pytest.mark.parametrize("xi", [0.02, [0.01, 0.05, 0.1]])
def test_modal_damping_of_a_plain_chain_gives_each_mode_its_ratio(xi):
    model = pp.build_model(BEAM, [0.2, 0.3, 0.3, 0.2], [2500.0, 1200.0, 700.0])
    q = np.array([0.05, -0.1, 0.2])
    lin = pp.linearize(model, q_eq=q, damping_ratio=xi)
    M, K = model.mass_matrix(q), lin.stiffness_Nm_per_rad
    w2, Phi = sla.eigh(K, M)  # Phi^T M Phi = I, by scipy's generalised solver
    w = np.sqrt(w2)
    modal = Phi.T @ lin.damping_Nms_per_rad @ Phi
    want = np.diag(2.0 * np.broadcast_to(xi, w.shape) * w)
    # modes of two solvers: off by about EPS (w_max / w_min)^2 relative (tolerances.eig_rtol)
    # times the largest modal damping
    tol = 3 * 10 * EPS * (w[-1] / w[0]) ** 2 * want.max()
    np.testing.assert_allclose(modal, want, rtol=0, atol=tol)
