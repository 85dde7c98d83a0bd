"""The co-design page (docs/ccd_slew/ccd_slew.md) written from what ``scripts/ccd_slew.py`` wrote.

Reads ``summary.json`` (the set-up: hub, truth frequencies, bandwidth), ``open_loop.csv``,
``closed_loop.csv`` and ``codesign.csv`` of a folder and writes there the page (prose, narrow
tables, every number from those files) and ``ccd_slew_maps.png`` (the strain path's open- and
closed-loop errors per strain map, a comparison the tables hold only row by row). The study's
own figure, ``ccd_slew.png``, is drawn by ``ccd_slew.py``; the page shows both.

    python scripts/ccd_slew_page.py [docs/ccd_slew]
"""

from __future__ import annotations

import csv
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402

HUB_PAIRS = ("hub_torque->hub_angle", "hub_torque->hub_rate", "hub_torque->tip_z",
             "hub_torque->tip_z_rate")
STRAIN_PAIRS = ("strain->hub_angle", "strain->hub_rate", "strain->tip_z", "strain->tip_z_rate")
MAPS = ("virtual-work", "fitted", "fitted-tip_z")


def _rows(path: Path) -> list[dict[str, str]]:
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def _pct(v: str) -> str:
    return f"{100 * float(v):.3g} %" if v else ""


def _table(head: list[str], rows: list[list[str]]) -> list[str]:
    return ["| " + " | ".join(head) + " |", "|" + "---|" * len(head),
            *("| " + " | ".join(r) + " |" for r in rows), ""]


def summary(res: dict, case, beam, truth) -> str:
    """The set-up the page states, as ``summary.json``: ``ccd_slew.run``'s result ``res``, its
    ``Case``, the beam and the truth (hub, truth frequencies, bandwidth, the design model)."""
    return json.dumps({
        "beam": beam.name, "truth_model": truth.model, "design": res["design"],
        "J_h_kg_m2": res["J_h"], "r_m": res["r"], "stiffening": case.stiffening,
        "truth_omega_rad_s": [float(w) for w in res["truth_w"]],
        "damping_ratio": case.damping_ratio, "omega_c_rad_s": res["wc"],
        "slew_angle_rad": case.design.angle_rad, "patch_frac": case.patch_frac,
        "nominal_start_frac": case.nominal_start_frac, "frf_start_frac": case.frf_start_frac,
    }, indent=1) + "\n"


def maps_figure(open_rows, closed_rows, path: Path) -> Path:
    """strain -> tip z FRF error (open loop) and closed-loop tip error, per fit and strain map."""
    from prbdm_pin.views.plots import new_figure, save_png

    fits = list(dict.fromkeys((r["model"], r["objective"]) for r in open_rows))
    frf = {(r["model"], r["objective"], r["map"]): float(r["strain->tip_z"]) for r in open_rows}
    tip = {tuple(r["plant"].split(" ", 2)): float(r["tip_l2"]) for r in closed_rows
           if r["plant"] != "truth"}
    fig = new_figure((11.0, 3.6))
    ax = fig.subplots(1, 2, sharey=True)
    x = np.arange(len(fits))
    for k, m in enumerate(MAPS):
        off = (k - 1) * 0.27
        ax[0].bar(x + off, [100 * frf[(*f, m)] for f in fits], 0.27, label=m)
        ax[1].bar(x + off, [100 * tip[(*f, m)] for f in fits], 0.27, label=m)
    for a, title in zip(ax, ("open loop: strain -> tip z FRF error",
                             "closed loop: tip vibration error, same LQG"), strict=True):
        a.set_xticks(x, [f"{n} {o}" for n, o in fits], fontsize=8)
        a.set_yscale("log")
        a.set_title(title, fontsize=10)
        a.grid(axis="y", alpha=0.3)
    ax[0].set_ylabel("relative L2 error against the truth (%)")
    handles, labels = ax[0].get_legend_handles_labels()
    fig.legend(handles, labels, title="strain map", fontsize=8, ncol=3, loc="upper center")
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 0.83))
    return save_png(fig, path)


def write_page(folder: str | Path) -> Path:
    """Write ``folder/ccd_slew.md`` and ``folder/ccd_slew_maps.png`` from the study's files."""
    folder = Path(folder)
    s = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    open_rows = _rows(folder / "open_loop.csv")
    closed_rows = _rows(folder / "closed_loop.csv")
    sweep = _rows(folder / "codesign.csv")
    maps_figure(open_rows, closed_rows, folder / "ccd_slew_maps.png")
    w = ", ".join(f"{v:.2f}" for v in s["truth_omega_rad_s"])
    design = s["design"]
    largest = design.split()[0]
    md = [f"# Slew co-design: {s['beam']} on a hub, {s['truth_model']} truth", "",
          "Can a pseudo-rigid-body model stand in for the finite-element truth when a controller "
          "is designed and an actuator placed? This page answers it for one problem, a rigid hub "
          "that slews a flexible panel, and every number on it comes from "
          "`python scripts/ccd_slew.py --out docs/ccd_slew` (the tables below are written from "
          "its CSV files by `scripts/ccd_slew_page.py`).", "",
          "## The problem", "",
          f"The panel is clamped to a rigid hub at radius r = {s['r_m']:.3g} m; the hub turns "
          f"about the panel's bending axis. Its inertia, J_h = {s['J_h_kg_m2']:.4g} kg m^2, is "
          f"chosen so that the hub raises the first flexible mode "
          f"{100 * (s['stiffening'] - 1):.0f} % above the clamped panel's; the truth's "
          f"hub-stiffened frequencies are then {w} rad/s. Two inputs act on it, a hub torque and "
          f"a full-width strain patch {s['patch_frac']} L long (from {s['nominal_start_frac']} L "
          "in the nominal design); four outputs are measured, the hub angle and rate and the "
          "tip's z displacement and rate. Every mode has the modal damping ratio "
          f"{s['damping_ratio']}.", "",
          f"The task: slew the hub by {s['slew_angle_rad']} rad and leave the tip still. An LQG "
          "compensator (an LQR and a Kalman filter) is designed on a plant, with the bandwidth "
          f"omega_c = {s['omega_c_rad_s']:.3g} rad/s, and run, by exact linear simulation, on "
          "that plant and on the truth's (the truth's modal model in hybrid coordinates: a "
          "different model from any chain).", "",
          "## The models compared", "",
          "Each PRBDM is a chain of n joints with one spring per joint, fitted to the truth "
          "either on its frequencies alone (`eigen`) or on its frequencies and its "
          "large-deflection tip (`combined`), then put on the hub and linearised. The strain "
          "patch enters a chain through one of three maps:", "",
          "- `virtual-work`: the chain's own kinematics, the patch moment acting on the joints "
          "inside the patch;",
          "- `fitted`: joint weights fitted to the truth's clamped modal gains "
          "({py:func}`prbdm_pin.fit_strain_actuators`);",
          "- `fitted-tip_z`: weights fitted to the truth's strain -> tip z residues "
          "(`match=\"tip_z\"`).", "",
          "## Open loop: how well each plant matches the truth", "",
          "The frequency errors do not depend on the strain map, nor do the hub-torque paths: "
          "one row per fit. FRF errors are relative L2 errors over "
          f"[{s['frf_start_frac']} omega_1, 1.2 omega_n] of the truth.", ""]
    per_fit = list({(r["model"], r["objective"]): r for r in open_rows}.values())
    md += _table(["model", "fit", "frequency errors (%)"],
                 [[r["model"], r["objective"], r["freq_errors_pct"].replace("/", " / ")]
                  for r in per_fit])
    md += _table(["model", "fit", *(p.replace("hub_torque->", "torque -> ") for p in HUB_PAIRS)],
                 [[r["model"], r["objective"], *(_pct(r[p]) for p in HUB_PAIRS)]
                  for r in per_fit])
    md += ["The strain paths depend on the map: the patch is short, and a map that only knows "
           "which joints lie inside it misses how the truth's modes are strained there.", ""]
    md += _table(["model", "fit", "map", *(p.replace("strain->", "strain -> ")
                                          for p in STRAIN_PAIRS)],
                 [[r["model"], r["objective"], r["map"], *(_pct(r[p]) for p in STRAIN_PAIRS)]
                  for r in open_rows])
    md += ["```{figure} ccd_slew_maps.png", ":alt: strain path errors per fit and strain map", "",
           "Left: the open-loop strain -> tip z FRF error of every fit under each strain map. "
           f"Right: the tip vibration error of the same fits under the {design} model's LQG, "
           "against the truth's under that LQG (log scales).", "```", "",
           "## Closed loop: one controller on every plant", "",
           f"The LQG designed on the {design} model runs on every PRBDM and on the truth. The "
           "errors are relative L2 errors of each PRBDM's response against the truth's.", ""]
    truth = next(r for r in closed_rows if r["plant"] == "truth")
    others = [r for r in closed_rows if r["plant"] != "truth"]
    md += _table(["plant", "hub angle error", "tip vibration error", "cost"],
                 [["truth", "", "", f"{float(truth['cost']):.4g}"]]
                 + [[r["plant"], _pct(r["hub_l2"]), _pct(r["tip_l2"]),
                     f"{float(r['cost']):.4g}"] for r in others])
    md += ["Settling times and the vibration left at the end of the slew, on each plant under "
           "that LQG, and on the truth under an LQG designed on the plant itself:", ""]
    md += _table(["plant", "hub settling (s)", "tip settling (s)", "residual tip (m)",
                  "own LQG on truth: cost"],
                 [[r["plant"], f"{float(r['settle_hub_s']):.3g}",
                   f"{float(r['settle_tip_s']):.3g}", f"{float(r['residual_tip_m']):.3g}",
                   f"{float(r['own_truth_cost']):.4g}" if r["own_truth_cost"] else ""]
                  for r in [truth, *others]])
    md += ["```{figure} ccd_slew.png", ":alt: hub angle, tip vibration and co-design cost", "",
           f"Left and centre: the slew on the truth (black) and on the {design.split()[1]} fits "
           f"under the {design} model's LQG. Right: the co-design sweep, the LQG cost against "
           f"the patch's start as the {largest} models predict it and as the truth-designed LQG "
           "achieves it.", "```", "",
           "## Co-design: where to put the patch", "",
           "The patch start is swept; at each position the LQG is redesigned on each PRBDM and "
           "on the truth itself. A PRBDM is useful for co-design if its controller, run on the "
           "truth, costs what the truth's own does, and if it ranks the positions as the truth "
           f"does. The {largest} models' costs on the truth, per strain map (the full sweep, "
           "with every model's predicted cost, is in {download}`codesign.csv`):", ""]
    cols = ["truth_designed", *(f"{largest} on truth" if m == "virtual-work"
                                else f"{largest} {m} on truth" for m in MAPS)]
    best = {c: min(sweep, key=lambda r, c=c: float(r[c]))["start_frac"] for c in cols}
    md += _table(["start (L)", "truth-designed", *MAPS],
                 [[r["start_frac"], *((f"**{float(r[c]):.4g}**" if r["start_frac"] == best[c]
                                       else f"{float(r[c]):.4g}") for c in cols)]
                  for r in sweep])
    agree = [c for c in sweep[0] if c != "start_frac" and min(
        sweep, key=lambda r, c=c: float(r[c]))["start_frac"] == best["truth_designed"]]
    md += [f"The truth's best start is {best['truth_designed']} L (bold: each column's "
           f"minimum); {len(agree) - 1} of the {len(sweep[0]) - 2} PRBDM columns of the sweep "
           "(predicted and on the truth, every model and map) pick the same position.", "",
           "The full tables: {download}`open_loop.csv`, {download}`closed_loop.csv` and "
           "{download}`codesign.csv`; what the study is and how it is checked is on the "
           "{doc}`benchmarks page <../benchmarks>`.", ""]
    page = folder / "ccd_slew.md"
    atomic_write_text(page, "\n".join(md))
    return page


if __name__ == "__main__":
    print(write_page(sys.argv[1] if len(sys.argv) > 1 else ROOT / "docs" / "ccd_slew"))
