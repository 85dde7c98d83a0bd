"""A small batch study: a folder of beams, each with its truth and fit, over a process pool.
=========================================================================================

``prbdm_pin.run_batch`` runs one truth and one fit per beam in worker processes (one BLAS
thread each), appends every finished beam to ``results.jsonl`` and writes ``results.csv``; rerun
the same call and it resumes. Each beam's fit seed is drawn from the batch seed and the beam's
index, so no result depends on the worker count. Here the beams are copies of the shipped beam
files (``BatchSpec(n_beams=N)`` draws random panels instead, as the paper's study).

Full mode: five shipped beams, plate truth, 4R eigen fits with 16 starts, two workers.
Quick mode (``--quick``): two beams, 1D beam truth, 3R eigen fits with 4 starts, one worker.

Run it with::

    python examples/batch_study.py [--quick] [--out results/examples/batch_study]
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np

import prbdm_pin as pp
from prbdm_pin.batch import LocalPool, read_records
from prbdm_pin.commands.script_cli import run_example
from prbdm_pin.io.paths import check_out_dir
from prbdm_pin.views.plots import new_figure, save_png

# sphinx-gallery runs the script without __file__, from the examples folder
ROOT = Path(globals().get("__file__", "batch_study.py")).resolve().parents[1]
QUICK_BEAMS = ("uniform-narrow", "tapered")
FULL_BEAMS = ("uniform-narrow", "tapered", "tapered-linear", "stepped-narrow",
              "reference-random")


def main(quick: bool = False,
         out: Path = ROOT / "results" / "examples" / "batch_study") -> dict:
    """Run the batch; returns its spec and its records (one dict per beam)."""
    out = check_out_dir("out", out)  # refused before any work, as --out
    beams_dir = out / "beams"
    beams_dir.mkdir(parents=True, exist_ok=True)
    for name in QUICK_BEAMS if quick else FULL_BEAMS:
        shutil.copy(ROOT / "examples" / "beams" / f"{name}.json", beams_dir)

    if quick:
        settings = pp.FitSettings(joints=3, truth_model="beam",
                                  options=pp.FitOptions(stiffness="joint", starts=4))
        workers = 1
    else:
        settings = pp.FitSettings(joints=4, truth_model="plate", cache_dir=str(out / "cache"),
                                  options=pp.FitOptions(stiffness="joint", starts=16))
        workers = 2
    spec = pp.BatchSpec(seed=7, settings=settings, beams_dir=str(beams_dir))
    summary = pp.run_batch(spec, out / "study", backend=LocalPool(workers), progress=False)
    print(f"{summary.n_ok} beams fitted, {summary.n_failed} failed, {summary.n_skipped} "
          f"resumed, in {summary.wall_s:.1f} s")

    records = sorted(read_records(out / "study" / "results.jsonl"),
                     key=lambda r: r["beam_index"])
    for r in records:
        if r["status"] != "ok":
            print(f"  {r['beam_name']}: {r['error']}")
            continue
        gamma = ", ".join(f"{g:.3f}" for g in r["gamma"])
        print(f"  {r['beam_name']}: worst mode {r['worst_mode_error_pct']:.2g} %, "
              f"links / L = {gamma}, truth {r['truth_s']:.2f} s, fit {r['fit_s']:.2f} s")

    ok = [r for r in records if r["status"] == "ok"]
    fig = new_figure((7.0, 0.5 + 0.45 * len(ok)))
    ax = fig.subplots()
    for row, r in enumerate(ok):
        starts = np.r_[0.0, np.cumsum(r["gamma"])[:-1]]
        ax.barh(row, r["gamma"], left=starts, color=[f"C{j}" for j in range(len(starts))],
                edgecolor="k", height=0.6)
    ax.set_yticks(range(len(ok)), [r["beam_name"] for r in ok])
    ax.invert_yaxis()
    ax.set(xlabel="link lengths (fractions of L); joints at the boundaries", xlim=(0.0, 1.0),
           title=f"fitted {settings.joints}R layouts, {settings.truth_model} truth")
    fig.tight_layout()
    figure = save_png(fig, out / "batch_study.png")
    return {"spec": spec, "records": records, "beams_dir": beams_dir, "figure": figure}


if __name__ == "__main__":
    # no SystemExit on success: sphinx-gallery runs this block in the build's process
    if code := run_example(__doc__, ROOT / "results" / "examples" / "batch_study", main):
        raise SystemExit(code)
