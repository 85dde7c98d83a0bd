"""frequencies_batch against each design's own natural_frequencies (Pinocchio's CRBA and the
scaled eigensolve), planar designs at their own poses and hub designs looped; bad batches."""

from __future__ import annotations

import numpy as np
import pytest
from tolerances import eig_rtol

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError


def _rtol(omega: np.ndarray) -> float:
    # two solves of one pencil (eig_rtol: n EPS carried by the spread) whose mass matrices
    # differ by their own roundings, 10 n EPS of the largest entry (the closed form against
    # CRBA, tests/chain/test_planar_batch.py), carried by the same spread: 11 eig_rtol
    return 11 * eig_rtol(omega)


BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.03, 0.02], thickness_m=[0.012, 0.006])


def _designs(n: int, count: int, seed: int, **kw):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        w = rng.uniform(0.5, 1.5, n + 1)
        out.append(pp.build_model(BEAM, w / w.sum(), rng.uniform(500.0, 5000.0, n), **kw))
    return out


@pytest.mark.parametrize("n", [1, 4, 8])
def test_planar_designs_at_their_own_poses_match_their_own_frequencies(n):
    models = _designs(n, 6, seed=n)
    Q = np.random.default_rng(40 + n).uniform(-0.5, 0.5, (6, n))
    w = pp.frequencies_batch(models, Q)
    w2 = pp.frequencies_batch(models, Q, squared=True)
    for b, m in enumerate(models):
        ref = m.natural_frequencies(Q[b])
        assert np.allclose(w[b], ref, rtol=_rtol(ref), atol=0.0)
        assert np.allclose(w2[b], ref ** 2, rtol=2 * _rtol(ref), atol=0.0)  # squared: twice
    shared = pp.frequencies_batch(models)  # the straight pose
    for b, m in enumerate(models):
        ref = m.natural_frequencies()
        assert np.allclose(shared[b], ref, rtol=_rtol(ref), atol=0.0)


def test_hub_designs_are_looped_and_keep_the_rigid_mode():
    models = _designs(3, 2, seed=5, hub=pp.Hub(5.0))
    w = pp.frequencies_batch(models, [0.0, 0.1, 0.0, -0.1])
    assert w.shape == (2, 4)
    for b, m in enumerate(models):
        lin = pp.linearize(m, q_eq=[0.0, 0.1, 0.0, -0.1], damping_ratio=0.0)
        ref = lin.modal().omega_rad_s  # the linear plant's pencil, another solve
        assert np.allclose(w[b, 1:], ref[1:], rtol=_rtol(ref[1:]), atol=0.0)
        assert w[b, 0] == 0.0  # the hub's rigid mode: an exact zero by construction


def test_bad_batches_are_refused_naming_the_argument():
    three, two = _designs(3, 1, seed=1)[0], _designs(2, 1, seed=2)[0]
    with pytest.raises(BeamInputError, match=r"models\[1\]: 2 joints"):
        pp.frequencies_batch([three, two])
    with pytest.raises(BeamInputError, match="the batch is empty"):
        pp.frequencies_batch([])
    with pytest.raises(BeamInputError, match=r"q_rad has shape \(2, 3\)"):
        pp.frequencies_batch([three] * 3, np.zeros((2, 3)))
