"""Link lengths: validation, bounds, uniform sampling and projection on the bounded simplex."""

import numpy as np
import pytest
from scipy.optimize import minimize
from tolerances import EPS

from prbdm_pin.chain.layout import (
    joint_positions,
    length_bounds,
    repair_lengths,
    sample_lengths,
    validate_lengths,
)
from prbdm_pin.errors import BeamInputError
from prbdm_pin.member.geometry import Beam

BEAM = Beam([0.0, 2.0], [0.05, 0.05], 0.01)


def test_joint_positions_are_partial_sums():
    np.testing.assert_allclose(joint_positions([0.5, 0.25, 1.25]), [0.5, 0.75])


def test_bounds_follow_eq15():
    lo, hi = length_bounds(2.0, 4)
    np.testing.assert_allclose(lo, 0.04)
    np.testing.assert_allclose(hi, 1.96)
    with pytest.raises(BeamInputError, match="n_links = 1"):
        length_bounds(2.0, 1)


@pytest.mark.parametrize(
    "lengths, pattern",
    [
        ([2.0], r"lengths = \[2\.0\]: needs at least 2"),
        ([[1.0, 1.0]], r"lengths has shape \(1, 2\)"),
        ([1.0, float("nan")], r"lengths\[1\] = nan"),
        ([1.0, float("inf")], r"lengths\[1\] = inf"),
        ([1.0, 1.1], r"lengths sum to 2\.1"),
        ([1.99, 0.01], r"lengths\[0\] = 1\.99"),
        ([0.03, 1.97], r"lengths\[0\] = 0\.03"),
        ("ab", r"lengths = 'ab'"),
        ([1.0, "x"], r"lengths = \[1\.0, 'x'\]"),
    ],
)
def test_validate_lengths_names_field_and_value(lengths, pattern):
    with pytest.raises(BeamInputError, match=pattern):
        validate_lengths(BEAM, lengths)


def test_validate_lengths_accepts_rounding_of_the_sum():
    ok = validate_lengths(BEAM, [2.0 / 3] * 3)
    assert ok.shape == (3,)


def test_samples_are_feasible_reproducible_and_unbiased():
    a = sample_lengths(np.random.default_rng(7), 2.0, 5, 4000)
    b = sample_lengths(np.random.default_rng(7), 2.0, 5, 4000)
    np.testing.assert_array_equal(a, b)
    lo, hi = length_bounds(2.0, 5)
    assert np.all(a >= lo) and np.all(a <= hi)
    # five positive lengths summed: a few roundings (2 EPS measured); kept: the test's 1e-12
    np.testing.assert_allclose(a.sum(axis=1), 2.0, rtol=5000 * EPS)
    # uniform on the simplex {l >= lo, sum = L}: each coordinate has mean L / 5 and
    # variance (free^2) * (n - 1) / (n^2 (n + 1)) for the flat Dirichlet of n = 5 parts
    free = 2.0 - 5 * 0.04
    var = free**2 * 4 / (25 * 6)
    se = np.sqrt(var / a.shape[0])
    np.testing.assert_allclose(a.mean(axis=0), 0.4, atol=5 * se)
    np.testing.assert_allclose(a.var(axis=0), var, rtol=0.1)


def test_repair_is_the_euclidean_projection():
    rng = np.random.default_rng(3)
    X = rng.normal(0.4, 0.6, size=(6, 5))
    Y = repair_lengths(X, 2.0)
    lo, hi = length_bounds(2.0, 5)
    for x, y in zip(X, Y, strict=True):
        # the projection is made exact on its active set: a few roundings (1 EPS measured);
        # kept: the test's 1e-12
        assert y.sum() == pytest.approx(2.0, rel=5000 * EPS)
        assert np.all(y >= lo[0] - 1e-15) and np.all(y <= hi[0] + 1e-15)
        ref = minimize(
            lambda v, x=x: 0.5 * np.sum((v - x) ** 2), np.full(5, 0.4), jac=lambda v, x=x: v - x,
            bounds=list(zip(lo, hi, strict=True)), method="SLSQP",
            constraints=[{"type": "eq", "fun": lambda v: v.sum() - 2.0}],
            options={"ftol": 1e-14, "maxiter": 500},
        )
        np.testing.assert_allclose(y, ref.x, atol=1e-7)


def test_repair_keeps_feasible_points_and_works_on_1d():
    x = np.array([0.3, 0.5, 1.2])
    # a feasible point is its own projection (exact here); kept: the test's 1e-15 m
    np.testing.assert_allclose(repair_lengths(x, 2.0), x, atol=5 * EPS)
    validate_lengths(BEAM, repair_lengths(np.array([5.0, -3.0, 0.0]), 2.0))
