"""The compiled planar statics (prbdm_pin.chain.planar_statics_kernel, .planar_statics_fast).

Compared with Pinocchio (the static residual K q - J^T F with its frame Jacobian at the
answer), with the numpy descent of prbdm_pin.chain.statics, and the compiled load stiffness
with central differences of J^T F.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from central_differences import central_difference
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.chain.planar import generalised_force
from prbdm_pin.chain.planar_statics_fast import static_deflection_straight
from prbdm_pin.chain.planar_statics_kernel import load_stiffness_into, planar_newton
from prbdm_pin.chain.statics import static_deflection_planar
from prbdm_pin.errors import SolveError

BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
RTOL = 1e-10  # the statics' own convergence request (static_deflection_planar's default)
LOADS = [(0.0, 0.0, -300.0), (200.0, 0.0, -900.0), (-150.0, 0.0, 400.0), (0.0, 0.0, -3000.0)]


def _chain(n: int, seed: int):
    rng = np.random.default_rng(seed)
    lengths = np.r_[0.5, rng.uniform(0.5, 1.5, n)]
    lengths *= 1.0 / lengths.sum()
    return lengths, rng.uniform(300.0, 1500.0, n)


@pytest.mark.parametrize("n", [1, 3, 5, 8])
@pytest.mark.parametrize("load", LOADS)
def test_the_compiled_equilibrium_balances_pinocchios_torques(n, load):
    lengths, k = _chain(n, n)
    F = np.array(load)
    q = static_deflection_straight(lengths, k, F)
    model = pp.build_model(BEAM, lengths, k)
    data = model.pin_model.createData()
    J = pin.computeFrameJacobian(model.pin_model, data, q, model.tip_frame_id,
                                 pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)[:3].reshape(3, n)
    r = k * q - J.T @ F
    scale = max(np.linalg.norm(k * q), np.linalg.norm(J.T @ F))
    # the descent's own test, with its lever arms against Pinocchio's: a few roundings more
    assert np.linalg.norm(r) <= RTOL * scale + 10 * n * EPS * scale
    ref = static_deflection_planar(lengths, k, F)
    # two converged descents (other summation orders): both within EPS cond(H) of the root
    H = np.diag(k) - _load_stiffness(lengths, q, F)
    tol = 10 * n * EPS * np.linalg.cond(H) * max(np.abs(ref).max(), 1.0) + RTOL
    np.testing.assert_allclose(q, ref, rtol=0.0, atol=tol)


def _load_stiffness(lengths, q, F):
    n = q.size
    T = np.empty((n, n))
    load_stiffness_into(lengths, q, float(F[0]), float(F[2]), *(np.empty(n) for _ in range(4)),
                        T)
    return T


@pytest.mark.parametrize("load", LOADS[1:3])
def test_the_compiled_load_stiffness_is_the_derivative_of_the_load_torques(load):
    lengths, _ = _chain(4, 7)
    F = np.array(load)
    q = np.array([0.1, -0.2, 0.15, 0.3])
    # J^T F is a sum of n terms of size |F| L: its rounding is about n EPS |F| L
    noise = 4 * 4 * EPS * np.abs(F).max() * lengths.sum()
    d, bound = central_difference(lambda x: generalised_force(lengths, x, F), q,
                                  np.full(4, 1e-4), noise)
    T = _load_stiffness(lengths, q, F)
    assert np.all(np.abs(T - d) <= bound)


def test_a_descent_the_numpy_path_would_leave_is_left_to_it():
    # a column past its buckling load, straight: a stationary point that is not a minimum
    lengths, k = _chain(3, 1)
    # (an axial load four times the stiffest spring's buckling load k / L)
    F = np.array([-4.0 * k.max() / lengths.sum(), 0.0, 0.0])
    assert not planar_newton(lengths, k, float(F[0]), float(F[2]), RTOL, 60, 0.5, np.zeros(3))
    q_fast = static_deflection_straight(lengths, k, F)
    q_ref = static_deflection_planar(lengths, k, F)
    H = np.diag(k) - _load_stiffness(lengths, q_ref, F)
    tol = 10 * 3 * EPS * np.linalg.cond(H) * max(np.abs(q_ref).max(), 1.0) + RTOL
    np.testing.assert_allclose(q_fast, q_ref, rtol=0.0, atol=tol)


def test_straight_without_in_plane_load_and_an_unresolvable_load_refused():
    lengths, k = _chain(3, 2)
    np.testing.assert_array_equal(static_deflection_straight(lengths, k,
                                                             np.array([0.0, 5.0, 0.0])),
                                  np.zeros(3))  # no in-plane load: exactly straight
    with pytest.raises(SolveError, match="tip_force"):
        static_deflection_straight(lengths, k, np.array([0.0, 0.0, -1e300]))
