"""A Pareto run: the trade-off between matching the frequencies and the large-deflection tip.
==========================================================================================

NSGA-II (``prbdm_pin.fit_pareto``) evolves designs of an nR joint-spring chain against two
objectives, the eigen loss (frequencies) and the deflection loss (the tip under the beam's load).
Its initial population holds the single-objective optima, so the front spans from the eigen fit
to the deflection fit; its knee (Eq. 27, the smallest combined loss) is polished by the local
solver. The figure shows the front, its knee and the single-objective fits run alone.

Full mode: the uniform strip against its plate truth, 4R, population 60, 60 generations.
Quick mode (``--quick``): the uniform strip, 1D beam truth, 3R, population 20, 10 generations.

Run it with::

    python examples/pareto_run.py [--quick] [--out results/examples/pareto_run]
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import prbdm_pin as pp
from prbdm_pin.commands.script_cli import run_example
from prbdm_pin.io.paths import check_out_dir
from prbdm_pin.views.plots import new_figure, save_png

# sphinx-gallery runs the script without __file__, from the examples folder
ROOT = Path(globals().get("__file__", "pareto_run.py")).resolve().parents[1]
FLOOR_PCT = 1e-9  # losses drawn on log axes: an exact match (rounding, about 1e-13 %) drawn here


def main(quick: bool = False, out: Path = ROOT / "results" / "examples" / "pareto_run") -> dict:
    """Front, knee and the single-objective fits alone; returns them (losses in %)."""
    out = check_out_dir("out", out)  # refused before any work, as --out
    out.mkdir(parents=True, exist_ok=True)
    beam = pp.load_beam(ROOT / "examples" / "beams" / "uniform-narrow.json")
    if quick:
        truth = pp.compute_truth(beam, model="beam", modes=3)
        joints, pop, generations = 3, 20, 10
    else:
        truth = pp.compute_truth(beam, model="plate", modes=4, cache_dir=out / "cache")
        joints, pop, generations = 4, 60, 60
    target = pp.target_from_truth(truth, beam.tip_force_N)

    options = pp.ParetoOptions(stiffness="joint", pop=pop, generations=generations,
                               seed_starts=2, seed=0)
    front = pp.fit_pareto(beam, target, joints, options, progress=False)
    (out / "pareto.csv").write_text(front.to_csv())
    knee = front.knee
    print(f"front of {front.F_pct.shape[0]} designs; knee: eigen {knee.eigen_loss_pct:.4g} %, "
          f"deflection {knee.deflection_loss_pct:.4g} %")

    # each objective alone, from other starts (seed 1): the ends the front should reach
    alone = {obj: pp.fit(beam, target, joints, stiffness="joint", objective=obj, starts=4,
                         seed=1, progress=False) for obj in ("eigen", "deflection")}
    for obj, r in alone.items():
        print(f"{obj} fit alone: eigen {r.eigen_loss_pct:.3g} %, "
              f"deflection {r.deflection_loss_pct:.3g} %")

    fig = new_figure((6.0, 4.2))
    ax = fig.subplots()
    F = np.maximum(front.F_pct, FLOOR_PCT)
    ax.plot(F[:, 0], F[:, 1], ".", color="C0", label="NSGA-II front")
    ax.plot(*F[front.knee_index], "*", ms=14, color="C0", mec="k",
            label=f"knee: combined {np.hypot(*front.F_pct[front.knee_index]):.3g} %")
    for (obj, r), mark in zip(alone.items(), ("s", "D"), strict=True):
        ax.plot(max(r.eigen_loss_pct, FLOOR_PCT), max(r.deflection_loss_pct, FLOOR_PCT), mark,
                mfc="none", ms=9, color="C3", label=f"{obj} fit alone")
    ax.set(xscale="log", yscale="log",
           xlabel=f"eigen loss (%; exact matches drawn at {FLOOR_PCT:g})",
           ylabel=f"deflection loss (%, {front.deflection_norm})",
           title=f"{beam.name}, {truth.model} truth: {joints}R joint springs")
    ax.legend(fontsize=8)
    fig.tight_layout()
    figure = save_png(fig, out / "pareto_run.png")
    return {"front": front, "alone": alone, "beam": beam, "target": target, "joints": joints,
            "figure": figure}


if __name__ == "__main__":
    # no SystemExit on success: sphinx-gallery runs this block in the build's process
    if code := run_example(__doc__, ROOT / "results" / "examples" / "pareto_run", main):
        raise SystemExit(code)
