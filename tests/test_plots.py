"""The fit's figures: drawn without pyplot, and the same bytes in a figure worker as here."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from prbdm_pin.beam_file import load_beam
from prbdm_pin.plots import figure_worker, fit_figures

ROOT = Path(__file__).resolve().parents[1]
BEAM = ROOT / "examples" / "beams" / "tapered.json"


def _result() -> SimpleNamespace:
    # the fields the figures read, of a 3R paper fit over five poses
    poses = np.radians([[3.0, 1.0, 0.5], [8.0, 3.0, 1.0], [14.0, 5.0, 2.0], [20.0, 7.0, 3.0],
                        [26.0, 9.0, 4.0]])
    factors = np.array([9.5, 9.7, 10.0, 10.5, 10.9])
    mean = float(factors.mean())
    return SimpleNamespace(
        lengths_m=np.array([0.24, 0.15, 0.12, 0.09]), joints=3, stiffness="paper",
        objective="eigen", poses_rad=poses, factors=factors, scf_mean=mean,
        export_pose_rad=poses[0], scf_deviation_pct=100.0 * (factors / mean - 1.0))


def test_figures_drawn_in_the_worker_are_the_bytes_drawn_here(tmp_path):
    beam, result = load_beam(BEAM), _result()
    (tmp_path / "here").mkdir()
    (tmp_path / "worker").mkdir()
    here = fit_figures(beam, result, tmp_path / "here")
    with figure_worker() as figures:
        there = figures.submit(fit_figures, beam, result, tmp_path / "worker").result()
    assert [p.name for p in here] == [p.name for p in there] == ["planform.png", "scf.png"]
    for a, b in zip(here, there, strict=True):
        assert a.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert a.read_bytes() == b.read_bytes(), a.name


def test_the_figures_load_no_pyplot(tmp_path):
    code = (
        "import sys\n"
        "from prbdm_pin.beam_file import load_beam\n"
        "from prbdm_pin.plots import plot_planform\n"
        f"plot_planform(load_beam({str(BEAM)!r}), [0.3, 0.2, 0.1], sys.argv[1])\n"
        "assert 'matplotlib.pyplot' not in sys.modules\n"
    )
    p = subprocess.run([sys.executable, "-c", code, str(tmp_path / "p.png")],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr[-2000:]
    assert (tmp_path / "p.png").stat().st_size > 0
