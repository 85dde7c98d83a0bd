"""What the door checks brought with them: the light-hub warning against the continuum's
pinned-free limit, ``extra_loads`` and ``LoadCase`` in the API against the elastica table, a
fit saved from Python that ``--compare-truth`` accepts, the actuators a URDF records read back,
and the truth cache's stale temporary files removed by the next lookup."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
from paths import ROOT
from reference import BETA_L, ELASTICA
from scipy.optimize import brentq

import prbdm_pin as pp
from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.cli import main
from prbdm_pin.truth.request import TruthRequest

BEAM = pp.load_beam(ROOT / "examples" / "beams" / "uniform-narrow.json")
L = BEAM.length_m


# --------------------------------------------------------------------------------------------
# a light hub

def _hub_beta_l(ratio: float) -> float:
    """First flexible root beta L of a uniform Euler-Bernoulli beam on a free rigid hub at its
    root (r = 0) of inertia ``ratio`` times the beam's own about the axis, rho A L^3 / 3.

    w(0) = 0, w'(0) = theta, -J omega^2 theta = EI w''(0), w''(L) = w'''(L) = 0; with
    w = A cosh + B sinh - A cos + D sin of beta x the conditions are a 3x3 determinant in
    beta L; lambda = J beta^3 / (rho A) = ratio (beta L)^3 / 3."""
    def det(bl):
        lam = ratio * bl**3 / 3.0
        ch, sh, c, s = np.cosh(bl), np.sinh(bl), np.cos(bl), np.sin(bl)
        return np.linalg.det(np.array([[2.0, lam, lam], [ch + c, sh, -s], [sh - s, ch, -c]]))

    grid = np.linspace(0.5, 5.0, 4001)
    vals = [det(b) for b in grid]
    k = next(i for i in range(len(grid) - 1) if np.sign(vals[i]) != np.sign(vals[i + 1]))
    return brentq(det, grid[k], grid[k + 1], xtol=1e-13)


def test_the_continuum_reference_has_the_clamped_and_pinned_limits():
    assert _hub_beta_l(1e9) == pytest.approx(BETA_L[0], rel=1e-6)  # a hub that does not turn
    assert _hub_beta_l(1e-9) == pytest.approx(3.9266023120, rel=1e-6)  # tan = tanh: pinned


def _hub_model(ratio: float):
    n = 6
    lengths = np.r_[0.5, np.ones(n - 1), 0.5] * L / n
    k = finite_segment_stiffness(BEAM, lengths)
    clamped = pp.build_model(BEAM, lengths, k)
    J_beam = BEAM.mass_kg * L**2 / 3.0 + BEAM.mass_kg * BEAM.thickness_m**2 / 12.0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        hub = pp.build_model(BEAM, lengths, k, hub=pp.Hub(ratio * J_beam, 0.0))
    return clamped, hub, [w for w in caught if issubclass(w.category, pp.LightHubWarning)]


@pytest.mark.parametrize("ratio", [30.0, 10.0, 3.0, 0.5, 0.1])
def test_a_light_hub_warns_where_the_continuum_moves_mode_one_by_more_than_25_percent(ratio):
    shift = 100.0 * ((_hub_beta_l(ratio) / BETA_L[0]) ** 2 - 1.0)  # 1.6 ... 210 %
    clamped, hub, caught = _hub_model(ratio)
    assert bool(caught) == (shift > 25.0), (ratio, shift)
    # the chain's own shift follows the continuum's (6R finite-segment chain: within 5 %)
    model_shift = 100.0 * (hub.natural_frequencies()[1] / clamped.natural_frequencies()[0] - 1)
    assert model_shift == pytest.approx(shift, rel=0.05)
    if caught:
        msg = str(caught[0].message)
        assert "hub inertia_kg_m2" in msg and "pinned-free" in msg
        quoted_ratio = float(re.search(r"is ([0-9.e+-]+) times the member", msg).group(1))
        quoted_shift = float(re.search(r"\(\+([0-9.e+-]+) %\)", msg).group(1))
        assert quoted_ratio == pytest.approx(ratio, rel=1e-3)
        assert quoted_shift == pytest.approx(model_shift, rel=1e-2)
        assert Path(caught[0].filename).resolve() == Path(__file__).resolve()


# --------------------------------------------------------------------------------------------
# extra_loads and LoadCase, as the fitting guide documents them

@pytest.fixture(scope="module")
def beam_truth(tmp_path_factory):
    cache = tmp_path_factory.mktemp("cache")
    return pp.compute_truth(BEAM, model="beam", modes=3, cache_dir=cache), cache


def test_extra_loads_as_multiples_get_the_elastica_tips(beam_truth):
    truth, _ = beam_truth
    target = pp.target_from_truth(truth, BEAM.tip_force_N)
    r = pp.fit(BEAM, target, 3, objective="combined", stiffness="joint", starts=2, seed=0,
               progress=False, extra_loads=(2.0, 5.0))
    F = BEAM.tip_force_N
    np.testing.assert_allclose(r.extra_tip_force_N, [2 * F, 5 * F])
    # P L^2 / EI = 1 carries 2 and 5: the elastica table's rows (the 1D truth's gap is ~0)
    for row, alpha2 in zip(r.extra_tip_position_truth_m, (2.0, 5.0), strict=True):
        retreat, deflection = ELASTICA[alpha2]
        assert row == pytest.approx([L * (1 - retreat), 0.0, -deflection * L], abs=2e-5)
    # the deflection loss averages the three load cases' relative tip errors
    tips = [r.tip_position_model_m[0], *r.extra_tip_position_model_m[:, 0]]
    refs = [r.tip_position_truth_m, *r.extra_tip_position_truth_m]
    errs = [np.linalg.norm(p - t) / np.linalg.norm(t) for p, t in zip(tips, refs, strict=True)]
    assert r.deflection_loss_pct == pytest.approx(100 * np.mean(errs), rel=1e-9)


def test_extra_loads_as_load_cases_and_refusals(beam_truth):
    truth, _ = beam_truth
    target = pp.target_from_truth(truth, BEAM.tip_force_N)
    retreat, deflection = ELASTICA[10.0]
    tip = np.array([L * (1 - retreat), 0.0, -deflection * L])
    case = pp.LoadCase(10 * BEAM.tip_force_N, tip, tip - [L, 0.0, 0.0])
    r = pp.fit(BEAM, target, 2, objective="deflection", stiffness="joint", starts=2,
               progress=False, extra_loads=[case])
    np.testing.assert_array_equal(r.extra_tip_position_truth_m, [tip])
    for bad, exc, name in (("2,5", pp.InputTypeError, "extra_loads"),
                           ((0.0,), pp.BeamInputError, "extra_loads[0] = 0"),
                           ((float("nan"),), pp.BeamInputError, "extra_loads[0] = nan"),
                           ((None,), pp.InputTypeError, "extra_loads[0]")):
        with pytest.raises(exc, match=re.escape(name)):
            pp.fit(BEAM, target, 2, objective="deflection", stiffness="joint", starts=1,
                   progress=False, extra_loads=bad)


# --------------------------------------------------------------------------------------------
# save_fit from Python keeps the truth record; --compare-truth accepts the file

def test_a_fit_saved_from_python_carries_its_truth_for_compare_truth(beam_truth, tmp_path,
                                                                     capsys):
    truth, cache = beam_truth
    assert truth.request == TruthRequest(model="beam", modes=3)
    target = pp.target_from_truth(truth, BEAM.tip_force_N)
    r = pp.fit(BEAM, target, 3, stiffness="joint", starts=2, progress=False)
    path = pp.save_fit(r, tmp_path / "fit.json", BEAM)
    assert json.loads(path.read_text())["truth_request"] == {
        "model": "beam", "modes": 3, "mesh_level": None, "selection": "paper",
        "large_deflection": "calibrated-elastica", "error_tol_pct": 0.5}
    assert pp.load_fit(path).truth_request == truth.request
    out = tmp_path / "lin"
    rc = main(["linearize", str(path), "--compare-truth", "--cache-dir", str(cache),
               "--out", str(out), "-q"])
    assert rc == 0, capsys.readouterr().err
    cmp = json.loads((out / "comparison.json").read_text())
    assert cmp["truth"]["model"] == "beam"


# --------------------------------------------------------------------------------------------
# load_urdf keeps the actuators the file records

def test_load_urdf_reads_back_the_recorded_actuators(tmp_path):
    lengths = np.array([0.2, 0.3, 0.3, 0.2])
    model = pp.build_model(BEAM, lengths, finite_segment_stiffness(BEAM, lengths))
    acts = (pp.StrainActuator(0.1, 0.6), pp.StrainActuator(0.25, 0.45,
                                                           joint_weights=(0.1, -0.2, 0.05)))
    path = pp.export_model(model, tmp_path / "m.urdf", "urdf", actuators=acts)
    back = pp.load_urdf(path)
    assert back.actuators == acts
    assert pp.load_urdf(pp.export_model(model, tmp_path / "n.urdf", "urdf")).actuators == ()
    lin = pp.linearize(back, inputs=("strain[0]", "strain[1]"), actuators=back.actuators)
    np.testing.assert_array_equal(lin.input_map.T, [[1.0, 1.0, 0.0], [0.1, -0.2, 0.05]])
    # the model JSON carries them the same way
    assert pp.read_model_json(pp.export_model(model, tmp_path / "m.json", "json",
                                              actuators=acts)).actuators == acts


# --------------------------------------------------------------------------------------------
# the truth cache: a killed writer's temporary files go at the next lookup

def _dead_pid() -> int:
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def test_stale_temporary_entries_are_removed_by_the_next_lookup(beam_truth, tmp_path):
    cache = tmp_path / "truth-cache"
    cache.mkdir()
    hour_ago = time.time() - 2 * 3600
    dead = cache / f".truth-{_dead_pid()}-0123456789ab.tmp"  # its writer is gone
    old = cache / ".truth-0123456789ab.tmp"  # an older version's name, two hours old
    live = cache / f".truth-{os.getppid()}-0123456789ab.tmp"  # a running writer, fresh
    mine_old = cache / f".truth-{os.getpid()}-00000000ffff.tmp"  # running, but two hours old
    other = cache / ".other.tmp"  # not the cache's
    for p in (dead, old, live, mine_old, other):
        p.write_bytes(b"partial")
    os.utime(old, (hour_ago, hour_ago))
    os.utime(mine_old, (hour_ago, hour_ago))
    os.utime(other, (hour_ago, hour_ago))
    pp.compute_truth(BEAM, model="beam", modes=2, static=False, cache_dir=cache)
    left = sorted(p.name for p in cache.iterdir())
    assert live.name in left and other.name in left
    assert dead.name not in left and old.name not in left and mine_old.name not in left
    # and the entry written has no temporary file beside it
    assert [n for n in left if n.endswith(".npz")] and len(left) == 3
