"""The geodesic Levenberg-Marquardt solver against problems with known solutions."""

import numpy as np
import pytest
from tolerances import EPS

from prbdm_pin.fitting.geodesic_lm import lm_advance, lm_start


def _solve(fun, jac, x0, lb, ub, max_nfev=2000, tol=1e-12):
    state = lm_start(fun, jac, np.asarray(x0, float), np.asarray(lb, float),
                     np.asarray(ub, float))
    return lm_advance(state, fun, jac, np.asarray(lb, float), np.asarray(ub, float), max_nfev,
                      tol=tol)


def rosenbrock(x):
    return np.array([10.0 * (x[1] - x[0] ** 2), 1.0 - x[0]])


def rosenbrock_jac(x):
    return np.array([[-20.0 * x[0], 10.0], [-1.0, 0.0]])


def test_rosenbrock_valley_to_its_minimum():
    """The curved valley the acceleration is for: (1, 1) from the classic start."""
    s = _solve(rosenbrock, rosenbrock_jac, [-1.2, 1.0], [-5, -5], [5, 5])
    assert s.status > 0
    np.testing.assert_allclose(s.x, [1.0, 1.0], atol=1e-8)
    assert s.nfev < 200


def test_linear_least_squares_matches_lstsq():
    """A non-zero residual: the minimiser of |A x - b| is numpy's lstsq solution."""
    rng = np.random.default_rng(3)
    A, b = rng.normal(size=(7, 4)), rng.normal(size=7)
    s = _solve(lambda x: A @ x - b, lambda x: A, np.zeros(4), np.full(4, -1e3), np.full(4, 1e3))
    np.testing.assert_allclose(s.x, np.linalg.lstsq(A, b, rcond=None)[0], rtol=1e-9)


def test_optimum_on_the_bounds():
    """min (x0 - 2)^2 + (x1 + 1)^2 + (x0 - x1)^2 / 10 with x0 <= 1 and x1 >= 0: the box corner
    (1, 0) (the unconstrained minimiser lies outside on both coordinates; at the corner the
    gradient points out of the box on both)."""
    def fun(x):
        return np.array([x[0] - 2.0, x[1] + 1.0, (x[0] - x[1]) / np.sqrt(10.0)])

    def jac(x):
        return np.array([[1.0, 0.0], [0.0, 1.0], [1.0, -1.0]]) / np.array([[1], [1],
                                                                            [np.sqrt(10.0)]])

    s = _solve(fun, jac, [0.2, 0.7], [-3.0, 0.0], [1.0, 3.0])
    # exact by construction: both variables end held on their bounds, which the step's clip
    # returns as the bounds themselves; slack 5000 EPS (the test's 1e-12)
    np.testing.assert_allclose(s.x, [1.0, 0.0], atol=5000 * EPS)


def test_one_active_bound_solves_the_rest():
    """x0 held at its bound 1, x1 then minimises (x1 + 1)^2 + (1 - x1)^2 / 10: x1 = -9/11."""
    def fun(x):
        return np.array([x[0] - 2.0, x[1] + 1.0, (x[0] - x[1]) / np.sqrt(10.0)])

    def jac(x):
        return np.array([[1.0, 0.0], [0.0, 1.0], [1 / np.sqrt(10.0), -1 / np.sqrt(10.0)]])

    s = _solve(fun, jac, [0.0, 0.0], [-3.0, -3.0], [1.0, 3.0])
    np.testing.assert_allclose(s.x, [1.0, -9.0 / 11.0], atol=1e-10)


def test_resuming_is_the_same_solve():
    """A solve advanced in slices of the cap ends where one call ends (the state is whole)."""
    lb, ub = np.array([-5.0, -5.0]), np.array([5.0, 5.0])
    one = _solve(rosenbrock, rosenbrock_jac, [-1.2, 1.0], lb, ub, max_nfev=61)
    s = lm_start(rosenbrock, rosenbrock_jac, np.array([-1.2, 1.0]), lb, ub)
    for cap in range(11, 62, 10):
        s = lm_advance(s, rosenbrock, rosenbrock_jac, lb, ub, cap, tol=1e-12)
    assert np.array_equal(s.x, one.x) and s.nfev == one.nfev


def squares(x):
    """r = x^2 term by term: zero residual at 0, where the Jacobian 2 diag(x) is singular, so
    the solve converges only linearly (each step shrinks x by a fixed factor, whatever the
    rounding) and needs 91 residual evaluations to the gradient tolerance from (1, -2): a count
    set by the problem, not by the last bits of a BLAS kernel (Rosenbrock's varies from 27 to
    43 between kernels)."""
    return x**2


@pytest.mark.parametrize("cap", [1, 2, 5, 40])
def test_the_cap_counts_residual_evaluations(cap):
    lb, ub = np.array([-5.0, -5.0]), np.array([5.0, 5.0])
    args = (squares, lambda x: np.diag(2.0 * x), [1.0, -2.0], lb, ub)
    whole = _solve(*args)
    assert whole.status > 0 and whole.nfev > cap  # the uncapped solve goes past every cap
    s = _solve(*args, max_nfev=cap)
    assert 1 <= s.nfev <= max(cap, 1) and s.status == 0 and s.message.startswith("evaluation")


def test_a_start_that_cannot_be_evaluated_stops_at_once():
    """Residuals the model cannot give (a constant, zero Jacobian) stop the solve: status -1."""
    s = _solve(lambda x: np.full(3, 1e3), lambda x: np.zeros((3, 2)), [0.1, 0.2], [-1, -1],
               [1, 1])
    assert s.status == -1 and s.nfev == 1


def test_a_corner_optimum_stops_on_the_projected_gradient():
    """Both variables held on their bounds by the gradient: converged at once, no steps."""
    def fun(x):
        return np.array([x[0] - 2.0, x[1] + 1.0])

    s = _solve(fun, lambda x: np.eye(2), [1.0, 0.0], [-3.0, 0.0], [1.0, 3.0])
    assert s.status == 2 and s.nfev == 1
    np.testing.assert_allclose(s.x, [1.0, 0.0])
