"""Stress: the 4R eigen fit on 20 seeded random beams reaches <= 0.1 % loss, or says why not.

Joint parametrisation, eigen objective on the straight pose, 4 frequencies, against the default
plate truth (``compute_truth``: Kirchhoff plate, paper mode selection; about 100 s for the 20
beams). A beam that misses the target must carry the reason in its result's ``warnings``: the
missed match and the truth modes a chain cannot represent. Measured: 19 of 20 match their four
frequencies to <= 1e-8 %; seed 1019 (necks of 35-56 mm half-width) selects a chordwise and a mixed
mode 1.34 apart in frequency (360.9 and 484.3 rad/s), which no 4R chain reaches (best 5.2 %,
every start; its first three frequencies match exactly).
"""

from __future__ import annotations

import numpy as np
import pytest

from prbdm_pin.fitting import fit
from prbdm_pin.fitting.target import target_from_truth
from prbdm_pin.member.random_beams import random_beam
from prbdm_pin.truth import compute_truth

pytestmark = [pytest.mark.slow, pytest.mark.stress]

SEEDS = tuple(range(1000, 1020))
TARGET_PCT = 0.1


def test_4r_eigen_fit_on_20_random_beams():
    missed = []
    for seed in SEEDS:
        beam = random_beam(np.random.default_rng(seed))
        # the fits are under test, not the truth: take the default-level truth as it is, even
        # where its error estimate would refuse it (one of these panels' first mode moves by
        # 0.4 % to the next level; tests/truth/test_truth_judge.py checks the refusal)
        truth = compute_truth(beam, modes=4, static=False, error_tol_pct=None)
        r = fit(beam, target_from_truth(truth, beam.tip_force_N), 4, frequencies=4,
                objective="eigen", stiffness="joint", eigen_norm="paper", starts=32, seed=0,
                progress=False,
                loss_tol_pct=1e-4)
        # independent of the fit's own loss: recompute the frequency errors from the result
        w = r.omega_model_rad_s[0]
        loss = 100.0 * np.linalg.norm(w - truth.omega_rad_s[:4]) \
            / np.linalg.norm(truth.omega_rad_s[:4])
        assert loss == pytest.approx(r.eigen_loss_pct, rel=1e-6, abs=1e-9)
        assert np.all(np.isfinite(w)) and np.all(np.diff(w) > 0)
        if loss <= TARGET_PCT:
            continue
        # never a silent bad model: the result says it missed, and why
        assert r.warnings and "not matched" in r.warnings[0], (seed, r.warnings)
        assert any("not beam-like" in note for note in r.warnings[1:]), (seed, r.warnings)
        missed.append((seed, loss))
    # the measured misses (see the module docstring); a new miss fails here with its numbers
    assert [s for s, _ in missed] == [1019], missed
