"""Statics under hostile loads: an answer that is an equilibrium, or an error naming the load.

A load whose residual overflows used to pass ``inf <= inf`` and return the straight pose."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from tolerances import EPS

from prbdm_pin.chain import statics
from prbdm_pin.chain.statics_guard import max_load_index
from prbdm_pin.errors import BeamInputError, SolveError

L0, L1, K1 = 0.1, 0.4, 2.0  # a 1R chain: clamp offset, link (m), spring (N m/rad)


def one_r_angle(P: float) -> float:
    """Closed form of the 1R chain under a dead load (0, 0, -P): k q = P L1 cos q, 0 < q < pi/2."""
    return brentq(lambda q: K1 * q - P * L1 * math.cos(q), 0.0, math.pi / 2, xtol=1e-15,
                  rtol=4 * np.finfo(float).eps)


@pytest.mark.parametrize("alpha", [0.5, 3.0, 50.0, 1e3, 1e5])
def test_one_link_matches_closed_form_up_to_large_loads(alpha):
    P = alpha * K1 / L1
    q = statics.static_deflection_planar(np.array([L0, L1]), np.array([K1]), [0.0, 0.0, -P])
    assert q[0] == pytest.approx(one_r_angle(P), rel=1e-8, abs=1e-12)
    qb, ok = statics.static_deflection_planar_batch(np.array([L0, L1]), np.array([[K1]]),
                                                [0.0, 0.0, -P])
    assert ok[0] and qb[0, 0] == pytest.approx(one_r_angle(P), rel=1e-8, abs=1e-12)


def joint_torques(lengths, q, F):
    """Moments (N m) of the tip force about each joint (y axis), from the tip geometry alone."""
    phi = np.cumsum(q)
    pts = [np.array([lengths[0], 0.0])]
    for Li, p in zip(lengths[1:], phi, strict=True):
        pts.append(pts[-1] + Li * np.array([math.cos(p), -math.sin(p)]))
    tip = pts[-1]
    # rotating joint j by +dq moves the tip by dq (r_z, -r_x) with r = tip - joint (x, z plane)
    return np.array([F[0] * (tip - j)[1] - F[2] * (tip - j)[0] for j in pts[:-1]])


@pytest.mark.parametrize("alpha", [1.0, 1e2, 1e4])
def test_four_link_equilibrium_balances_the_moments(alpha):
    lengths = np.array([0.05, 0.3, 0.25, 0.2, 0.2])
    k = np.array([4.0, 3.0, 2.0, 1.0])
    F = np.array([0.3, 0.0, -1.0]) * alpha * k.max() / lengths[1:].sum()
    q = statics.static_deflection_planar(lengths, k, F)
    np.testing.assert_allclose(k * q, joint_torques(lengths, q, F), rtol=1e-7,
                               atol=1e-9 * np.abs(k * q).max())
    assert np.abs(q).max() > 1e-3  # a real deflection, not the straight pose


HUGE = [1e7, 1e20, 1e100, 1e155, 1e160, 1e200, 1e300]


@pytest.mark.parametrize("alpha", HUGE)
@pytest.mark.parametrize("direction", [(0.0, -1.0), (0.6, -0.8), (-1.0, 0.0)])
def test_loads_beyond_double_precision_are_refused_naming_the_load(alpha, direction):
    lengths = np.array([0.05, 0.3, 0.25, 0.2])
    k = np.array([3.0, 2.0, 1.0])
    F = np.array([direction[0], 0.0, direction[1]]) * alpha * k.max() / lengths[1:].sum()
    with pytest.raises(SolveError, match=r"tip_force = .*load index"):
        statics.static_deflection_planar(lengths, k, F)
    q, ok = statics.static_deflection_planar_batch(lengths, np.array([k, k * alpha]), F)
    assert not ok[0] and np.isnan(q[0]).all()
    if alpha <= 1e100:
        # springs scaled with the load: load index 1, the equilibrium of F / alpha on k
        assert ok[1]
        # rtol: the solves' tolerance; atol for angles near 0: a few roundings (1 EPS
        # measured), kept: the test's 1e-12 rad
        np.testing.assert_allclose(q[1], statics.static_deflection_planar(lengths, k, F / alpha),
                                   rtol=1e-8, atol=5000 * EPS)
    else:
        assert not ok[1] and np.isnan(q[1]).all()  # k alpha pi overflows the squared norms


def test_overflowing_springs_and_loads_at_a_moderate_index_are_refused():
    # load index 1, but the squared norms overflow double precision
    lengths, k = np.array([L0, L1]), np.array([1e160])
    F = np.array([0.0, 0.0, -1e160 / L1])
    with pytest.raises(SolveError, match="tip_force"):
        statics.static_deflection_planar(lengths, k, F)
    q, ok = statics.static_deflection_planar_batch(lengths, k[None], F)
    assert not ok[0] and np.isnan(q[0, 0])


def test_the_refusal_bound_is_where_the_residual_test_stops_resolving():
    # pi rtol / eps at the default rtol; every load below converges (1R closed form)
    bound = max_load_index(1e-10)
    assert bound == pytest.approx(math.pi * 1e-10 / np.finfo(float).eps)
    P = 0.5 * bound * K1 / L1
    q = statics.static_deflection_planar(np.array([L0, L1]), np.array([K1]), [0.0, 0.0, -P])
    assert q[0] == pytest.approx(one_r_angle(P), rel=1e-8)
    with pytest.raises(SolveError, match="load index"):
        statics.static_deflection_planar(np.array([L0, L1]), np.array([K1]),
                                     [0.0, 0.0, -2.0 * bound * K1 / L1])


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_loads_raise_naming_the_load(bad):
    for F in ([0.0, 0.0, bad], [bad, 0.0, 1.0]):
        with pytest.raises(BeamInputError, match="tip_force"):
            statics.static_deflection_planar(np.array([L0, L1]), np.array([K1]), F)
        with pytest.raises(BeamInputError, match="tip_force"):
            statics.static_deflection_planar_batch(np.array([L0, L1]), np.array([[K1]]), F)


@pytest.mark.parametrize("n, alpha", [(1, 3.0), (3, 10.0), (8, 0.1), (8, 100.0)])
def test_axial_compression_past_buckling_finds_the_buckled_equilibrium(n, alpha):
    # a dead load along -x, exactly axial: the straight pose is a saddle past buckling, where
    # the load stepping used to stall ("no equilibrium") at a few percent of the load
    rng = np.random.default_rng(int(1000 * n + 10 * math.log10(alpha) + 180))
    lengths, k = rng.uniform(0.05, 0.4, n + 1), rng.uniform(0.5, 5.0, n)
    F = np.array([-1.0, 0.0, 1e-16]) * alpha * k.max() / lengths[1:].sum()
    try:
        q = statics.static_deflection_planar(lengths, k, F)
    except SolveError:
        # only a load below the chain's buckling load may keep it straight; none of these is
        pytest.fail("no equilibrium found")
    np.testing.assert_allclose(k * q, joint_torques(lengths, q, F), rtol=1e-7,
                               atol=1e-9 * np.abs(k * q).max())
    assert np.abs(q).max() > 0.05  # buckled, not the straight saddle
    if n == 1:
        # closed form: k q = P L1 sin q, 0 < |q| < pi
        P = -F[0]
        ref = brentq(lambda x: k[0] * x - P * lengths[1] * math.sin(x), 1e-6, math.pi)
        assert abs(q[0]) == pytest.approx(ref, rel=1e-8)


def test_a_chain_without_stiffness_is_refused_naming_the_load():
    # k_max = 0: the load index is infinite (the guard's numpy path, not its float one)
    with pytest.raises(SolveError, match=r"tip_force = .*load index"):
        statics.static_deflection_planar(np.array([L0, L1]), np.array([0.0]), [0.0, 0.0, -1.0])


def test_the_unchecked_solver_goes_on_from_a_warm_start_to_the_moment_balance():
    # a fit's next design: stiffer springs, from the last equilibrium (left unmodified)
    lengths = np.array([0.05, 0.3, 0.25, 0.2, 0.2])
    k = np.array([4.0, 3.0, 2.0, 1.0])
    F = np.array([0.3, 0.0, -1.0]) * 100.0 * k.max() / lengths[1:].sum()
    q_last = statics.static_deflection_planar(lengths, k, F)
    start = q_last.copy()
    q = statics.static_deflection_planar_unchecked(lengths, 1.1 * k, F, q_last)
    np.testing.assert_array_equal(q_last, start)
    np.testing.assert_allclose(1.1 * k * q, joint_torques(lengths, q, F), rtol=1e-7,
                               atol=1e-9 * np.abs(k * q).max())
    assert np.abs(q - q_last).max() > 1e-3  # it moved to the new equilibrium
    with pytest.raises(SolveError, match="load index"):
        statics.static_deflection_planar_unchecked(lengths, 1e-20 * k, F, q_last)
