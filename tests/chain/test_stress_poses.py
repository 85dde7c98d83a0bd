"""Stress: the mass matrix and frequencies over extreme poses, n = 1 ... 40.

References are independent of Pinocchio: the mass matrix of the planar chain from its closed-form
Lagrangian (numpy for every n, mpmath at 40 digits for n <= 4) and the generalised eigenproblem
solved in mpmath through its own Cholesky factor.
"""


import numpy as np
import pytest
from lagrangian import (
    MP_RTOL,
    chain_inputs,
    lagrangian_mass_matrix,
    reference_omega2,
)
from paths import BEAMS
from tolerances import EPS

from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.model.prbdm_model import build_model

RANDOM = load_beam(BEAMS / "reference-random.json")
ANGLES = (0.0, 1e-12, 1e-6, 0.1, np.pi / 2, np.pi)


def pose_set(n, rng, count):
    """Uniform poses at each angle, alternating signs, and random picks from the angle set."""
    poses = [np.full(n, a) for a in ANGLES]
    poses += [np.array([a * (-1) ** j for j in range(n)]) for a in ANGLES[1:]]
    for _ in range(count):
        poses.append(rng.choice(ANGLES, n) * rng.choice([-1.0, 1.0], n))
    return poses


def model_with(n, beam=RANDOM):
    lengths = np.full(n + 1, beam.length_m / (n + 1))
    lengths[-1] = beam.length_m - lengths[:-1].sum()
    return build_model(beam, lengths, finite_segment_stiffness(beam, lengths))


def check_pose(model, q):
    """SPD mass matrix (Cholesky), numpy Lagrangian agreement, finite ascending frequencies."""
    M = model.mass_matrix(q)
    np.testing.assert_array_equal(M, M.T)
    np.linalg.cholesky(M)  # raises LinAlgError if not positive definite
    ref = lagrangian_mass_matrix(model.lengths_m, *chain_inputs(model), q)
    # CRBA against the numpy Lagrangian: sums of up to n = 40 terms of M's size, about n EPS
    # of max |M| (3 EPS measured); kept: the test's 1e-13 of it
    np.testing.assert_allclose(M, ref, rtol=0, atol=500 * EPS * np.abs(ref).max())
    w = model.natural_frequencies(q)
    assert np.all(np.isfinite(w)) and np.all(w > 0), (q, w)
    assert np.all(np.diff(w) >= 0), (q, w)
    return w


def check_against_mpmath(model, q, rounding_bound=False):
    """omega^2 within 1e-9 of mpmath; with ``rounding_bound``, within max(1e-9, 2 eps cond A),
    the double-precision limit of the highest mode when cond A = cond(K^-1/2 M K^-1/2) is large
    (measured: up to 0.7 eps cond A)."""
    w2 = model.natural_frequencies(q, squared=True)
    ref = reference_omega2(model, q)
    err = np.max(np.abs(w2 / ref - 1))
    tol = MP_RTOL
    cond = ref[-1] / ref[0]
    if rounding_bound:
        tol = max(MP_RTOL, 2 * np.finfo(float).eps * cond)
    assert err <= tol, (f"n={model.n_joints} q={q}: max relative omega^2 error {err:.2e}, "
                        f"cond A {cond:.3g}")
    return err


@pytest.mark.parametrize("n", [1, 2, 4])
def test_mpmath_agreement_cheap(n):
    model = model_with(n)
    rng = np.random.default_rng(n)
    for q in pose_set(n, rng, 3)[::2]:
        check_pose(model, q)
        check_against_mpmath(model, q)


@pytest.mark.parametrize("n", [10, 40])
def test_large_chain_cheap(n):
    model = model_with(n)
    rng = np.random.default_rng(100 + n)
    for q in pose_set(n, rng, 2)[::3]:
        check_pose(model, q)


def test_tiny_angles_are_continuous_with_the_straight_pose():
    # 1e-12 rad must give the straight pose's frequencies to ~1e-12 (no branch in the code)
    model = model_with(4)
    w0 = model.natural_frequencies(np.zeros(4))
    for eps in (1e-12, -1e-12):
        np.testing.assert_allclose(model.natural_frequencies(np.full(4, eps)), w0, rtol=1e-11)


@pytest.mark.stress
@pytest.mark.slow
@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_mpmath_agreement_full(n):
    rng = np.random.default_rng(10 + n)
    worst = 0.0
    for beam_lengths in (None, "short-root", "short-tip"):
        if beam_lengths is None:
            model = model_with(n)
        else:
            lengths = np.full(n + 1, 0.02)
            lengths[0 if beam_lengths == "short-tip" else -1] = 1.0 - 0.02 * n
            model = build_model(RANDOM, lengths, finite_segment_stiffness(RANDOM, lengths))
        for q in pose_set(n, rng, 10):
            check_pose(model, q)
            err = check_against_mpmath(model, q, rounding_bound=beam_lengths is not None)
            if beam_lengths is None:
                worst = max(worst, err)
    assert worst <= MP_RTOL


@pytest.mark.stress
@pytest.mark.slow
@pytest.mark.parametrize("n", [1, 2, 3, 5, 8, 13, 20, 30, 40])
def test_every_pose_family_full(n):
    model = model_with(n)
    rng = np.random.default_rng(200 + n)
    for q in pose_set(n, rng, 20):
        check_pose(model, q)
    # the batch path (a different LAPACK driver) agrees with the single-pose path within the
    # rounding bound of the highest mode, eps * cond = eps * (omega_max / omega_min)^2
    Q = np.array(pose_set(n, rng, 5))
    single = np.array([model.natural_frequencies(q) for q in Q])
    bound = 4 * np.finfo(float).eps * np.max((single[:, -1] / single[:, 0]) ** 2)
    np.testing.assert_allclose(model.natural_frequencies_batch(Q), single, rtol=bound)
