"""The finite-segment chain converges to Euler-Bernoulli cantilever frequencies."""


import numpy as np
import pytest
from paths import BEAMS
from reference import BETA_L as REF_BETA_L

from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.model.prbdm_model import build_model

BEAM = load_beam(BEAMS /
                 "uniform-narrow.json")
# roots of 1 + cos(bL) cosh(bL) = 0
BETA_L = REF_BETA_L[:3]


def euler_bernoulli():
    EI = BEAM.root_EI_Nm2
    mu = BEAM.mass_kg / BEAM.length_m
    return BETA_L**2 * np.sqrt(EI / (mu * BEAM.length_m**4))


def chain_errors(n):
    """Equal segments h = L/n, springs EI/h at the segment centres: links [h/2, h, ..., h/2]."""
    L = BEAM.length_m
    h = L / n
    lengths = np.concatenate([[h / 2], np.full(n - 1, h), [h / 2]])
    m = build_model(BEAM, lengths, np.full(n, BEAM.root_EI_Nm2 / h), min_fraction=0.0)
    k = min(3, n)
    return np.abs(m.natural_frequencies()[:k] / euler_bernoulli()[:k] - 1)


def test_converges_to_euler_bernoulli():
    errs = {n: chain_errors(n) for n in (2, 4, 8, 16)}
    assert np.all(errs[16] < 0.006), errs[16]
    for a, b in ((4, 8), (8, 16)):
        assert np.all(errs[b] < errs[a] / 3)  # second order in h: about 4x per halving
    assert errs[4][0] < errs[2][0]


@pytest.mark.slow
def test_converges_further_at_64_segments():
    assert np.all(chain_errors(64) < 0.0005)
