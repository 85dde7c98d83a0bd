"""Warm starts, the unique='nearest' rule, fit_sweep and the IFT derivative of a fit, on the
tapered panel with the 1D beam truth (fast)."""

from __future__ import annotations

import dataclasses
from functools import lru_cache

import numpy as np
import pytest

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError
from prbdm_pin.fitting.result import EXACT_MATCH_PCT
from prbdm_pin.fitting.sweep import max_relative_step

BEAM = pp.load_beam("examples/beams/tapered.json")
TIP = np.linspace(0.015, 0.03, 8)  # tip half-widths of the sweep, m


def beam_at(w: float) -> pp.Beam:
    return dataclasses.replace(BEAM, half_width_m=np.array([0.05, w]))


@lru_cache(maxsize=64)
def _target(w: float) -> pp.FitTarget:
    b = beam_at(w)
    tr = pp.compute_truth(b, model="beam", modes=3, static=True, error_tol_pct=None)
    return pp.target_from_truth(tr, b.tip_force_N)


def target_at(b: pp.Beam) -> pp.FitTarget:
    return _target(float(b.half_width_m[-1]))


def test_warm_start_reaches_the_cold_optimum_with_fewer_evaluations():
    a, b = TIP[3], TIP[4]
    prev = pp.fit(beam_at(a), _target(a), 3, stiffness="joint", starts=8, progress=False)
    cold = pp.fit(beam_at(b), _target(b), 3, stiffness="joint", starts=8, progress=False)
    warm = pp.fit(beam_at(b), _target(b), 3, stiffness="joint", start=prev, progress=False)
    # both match the 3 truth frequencies exactly (the optimum of an eigen fit: loss 0)
    assert cold.eigen_loss_pct < EXACT_MATCH_PCT and warm.eigen_loss_pct < EXACT_MATCH_PCT
    assert np.allclose(warm.omega_model_rad_s[0], _target(b).omega_truth_rad_s, rtol=1e-8)
    assert warm.nfev < cold.nfev / 4 and warm.starts_run == 1
    # the warm start stays on the start's branch: next to it, not wherever the cold one lands
    assert np.max(np.abs(warm.lengths_m - prev.lengths_m)) < 0.01 * BEAM.length_m
    # the start is recorded (fit.json's options) and reads back
    o = pp.FitOptions.from_dict(warm.options.to_dict())
    assert o.start_lengths_m == warm.options.start_lengths_m
    assert np.allclose(o.start_lengths_m, prev.lengths_m)


def test_sweep_is_continuous_where_cold_fits_jump():
    designs = [beam_at(w) for w in TIP]
    cold = [pp.fit(b, target_at(b), 3, stiffness="joint", starts=16, progress=False)
            for b in designs]
    theta = np.array([np.r_[f.lengths_m, f.stiffness_Nm_per_rad] for f in cold])
    cold_step = np.max(max_relative_step(theta, TIP))
    uniq = pp.fit_sweep(designs, target_at, 3, stiffness="joint", unique="nearest",
                        parameter=TIP, progress=False)
    warm = pp.fit_sweep(designs, target_at, 3, stiffness="joint", starts=8,
                        parameter=TIP, progress=False)
    # every fit matches the truth; the cold fits' parameters jump (measured: 19.7 times the
    # design's relative step), the sweeps' move by a bounded elasticity (measured: 0.71
    # unique, 1.8 warm)
    assert np.all(uniq.loss_pct < EXACT_MATCH_PCT) and np.all(warm.loss_pct < EXACT_MATCH_PCT)
    assert cold_step > 10.0
    assert np.max(uniq.max_relative_step()) < 2.5
    assert np.max(warm.max_relative_step()) < 2.5
    assert warm.warm.tolist() == [False] + [True] * (TIP.size - 1)


def test_ift_derivative_matches_refits():
    p, h = 0.02, 1e-4

    def refit(w):
        return pp.fit(beam_at(w), _target(w), 3, stiffness="joint", unique="nearest",
                      progress=False)

    d = pp.fit_derivative(refit(p), beam_at, p, target_at)
    a, b = refit(p + h), refit(p - h)
    dL = (a.lengths_m - b.lengths_m) / (2 * h)
    dK = (a.stiffness_Nm_per_rad - b.stiffness_Nm_per_rad) / (2 * h)
    # measured: 2e-6 (lengths) and 3e-7 (springs) of the largest entry; 1e-4 is the O(h^2)
    # difference between central steps 4x apart
    assert np.max(np.abs(d.d_lengths_m - dL)) < 1e-4 * np.max(np.abs(dL))
    assert np.max(np.abs(d.d_stiffness_Nm_per_rad - dK)) < 1e-4 * np.max(np.abs(dK))
    assert d.conditions == "kkt"


def test_bad_input_is_refused_by_name():
    w = TIP[0]
    r3 = pp.fit(beam_at(w), _target(w), 3, stiffness="joint", starts=2, progress=False)
    with pytest.raises(BeamInputError, match="3R fit cannot start a 2R"):
        pp.fit(beam_at(w), _target(w), 2, stiffness="joint", start=r3, progress=False)
    with pytest.raises(BeamInputError, match="start lengths: 3 links"):
        pp.fit(beam_at(w), _target(w), 3, stiffness="joint",
               start=(np.full(3, 0.2), np.ones(3)), progress=False)
    with pytest.raises(BeamInputError, match="unique = 'nearest': stiffness"):
        pp.fit(beam_at(w), _target(w), 3, stiffness="paper", unique="nearest", progress=False)
    with pytest.raises(BeamInputError, match="unique = 'fancy'"):
        pp.FitOptions(unique="fancy")
    three = dataclasses.replace(BEAM, x_m=np.array([0.0, 0.3, 0.6]),
                                half_width_m=np.array([0.05, 0.035, 0.02]))
    with pytest.raises(BeamInputError, match=r"designs\[1\]: 3 planform vertices"):
        pp.fit_sweep([BEAM, three], target_at, 3, stiffness="joint", progress=False)
    with pytest.raises(BeamInputError, match="targets: 1 given for 2 designs"):
        pp.fit_sweep([BEAM, beam_at(0.021)], [_target(0.02)], 3, progress=False)
