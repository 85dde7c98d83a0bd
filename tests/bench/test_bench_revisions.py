"""scripts/bench_revisions.py: its error measure against a closed form, and a run against a git
revision checked out into a temporary worktree that is gone afterwards, its simulation rows'
errors against scipy's DOP853 at rtol 1e-11 within the exponential integrator's known
accuracy."""

from __future__ import annotations

import importlib.util
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
from paths import ROOT
from tolerances import EPS


def _module():
    spec = importlib.util.spec_from_file_location(
        "bench_revisions", ROOT / "scripts" / "bench_revisions.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_tip_error_is_the_largest_deviation_over_the_peak_excursion():
    t = np.linspace(0.0, 1.0, 101)
    # a tip swinging about its start (0, 0, -1) with a 0.2 m amplitude: peak excursion 0.4 m
    ref = np.c_[np.zeros_like(t), np.zeros_like(t), -1.0 + 0.2 * (1.0 - np.cos(2 * np.pi * t))]
    tip = ref.copy()
    tip[37] += [3e-4, 0.0, 4e-4]  # 5e-4 m off at one sample (a 3-4-5 triangle)
    tip[80] += [0.0, 1e-4, 0.0]
    # tip - ref cancels |ref| <= 1 m down to the 5e-4 m offset: a rounding of 1 m (EPS m) over
    # 5e-4 m, four of them (the offset's add, the difference, the norm, the division)
    assert _module().tip_error(tip, ref) == pytest.approx(5e-4 / 0.4, rel=4 * EPS / 5e-4)


def _worktrees() -> str:
    return subprocess.run(["git", "-C", str(ROOT), "worktree", "list"], capture_output=True,
                          text=True, check=True).stdout


@pytest.mark.slow
def test_a_revision_is_measured_in_a_temporary_worktree_then_removed(tmp_path):
    out = tmp_path / "table.md"
    before = _worktrees()
    folders = set(Path(tempfile.gettempdir()).glob("bench_rev_*"))
    subprocess.run([sys.executable, str(ROOT / "scripts" / "bench_revisions.py"), "--base",
                    "HEAD", "--only", "3R release, exponential", "--repeats", "1", "--out",
                    str(out)], check=True, cwd=ROOT, capture_output=True, text=True)
    assert _worktrees() == before  # the temporary worktree is removed, and its folder
    assert set(Path(tempfile.gettempdir()).glob("bench_rev_*")) <= folders
    head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True, check=True).stdout.strip()
    text = out.read_text()
    assert f"Base `{head}`" in text
    row = re.search(r"\| simulate 3R release, exponential \| exponential \| ([\d.e+-]+) \| "
                    r"exponential \| ([\d.e+-]+) \|", text)
    assert row is not None, text
    # the exponential integrator at its default step control on a release from 0.1 rad with
    # 2 % modal damping: 0.03-0.08 % of the peak on the 3R and 5R chains (benchmarks page)
    for err in map(float, row.groups()):
        assert 0.0 < err < 1e-3
