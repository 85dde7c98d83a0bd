"""Control co-design example: a hub slewing a flexible panel, PRBDM against the truth.

A rigid hub (inertia J_h about the bending axis, panel root at radius r) carries the panel and a
full-width strain actuator. J_h is chosen so that the hub raises the first flexible mode a given
ratio above the clamped panel's (default +20 %), from the truth's hybrid model. PRBDMs of 3, 4
and 5 joints (eigen and combined fits, joint springs) are built on the hub and linearised, each
with three strain maps: the virtual-work map (the joints inside the patch), the map fitted to the
truth's clamped modal gains (``prbdm_pin.fit_strain_actuators``) and the map fitted to its
strain -> tip z residues (``match="tip_z"``). An LQG output-feedback
compensator (``prbdm_pin.plant.slew``) designed on the 5R combined model with the fitted map
slews the hub by 0.1 rad on every PRBDM and on the truth's hybrid model (both with modal damping
on the hub-stiffened modes), by exact linear simulation. Reported: the open-loop FRF errors per
input/output pair over [f omega_1, 1.2 omega_n] of the truth (a linear grid from the fraction f
of omega_1, the rigid mode's 1/omega^2 at 0 left out), the flexible frequencies' errors, and the
closed-loop responses. The co-design step sweeps the patch's position, redesigns the LQG on each
PRBDM and on the truth for every position, and compares the best positions.

usage: python scripts/ccd_slew.py [--beam examples/beams/reference-random.json]
       [--truth-model plate|beam] [--joints 3,4,5] [--starts 8] [--out results/ccd_slew]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import sys  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "scripts"))

from ccd_slew_page import summary, write_page  # noqa: E402

from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.fitting import fit  # noqa: E402
from prbdm_pin.fitting.target import target_from_truth  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.model.hub import Hub  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402
from prbdm_pin.plant import slew  # noqa: E402
from prbdm_pin.plant.actuator_fit import profile_stations  # noqa: E402
from prbdm_pin.plant.linearize import linearize  # noqa: E402
from prbdm_pin.plant.slew_study import (  # noqa: E402
    MAPS,
    PAIR_NAMES,
    frf_errors,
    hub_inertia_for_stiffening,
    patch_actuators,
    slew_metrics,
)
from prbdm_pin.simulation.response import relative_l2  # noqa: E402
from prbdm_pin.truth import compute_truth  # noqa: E402
from prbdm_pin.truth.plant import hybrid_from_gains, truth_modal_gains  # noqa: E402


@dataclass(frozen=True)
class Case:
    """The example's settings (lengths as fractions of L)."""

    stiffening: float = 1.2
    radius_frac: float = 0.1
    patch_frac: float = 0.2
    starts_frac: tuple[float, ...] = (0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8)
    nominal_start_frac: float = 0.0
    damping_ratio: float = 0.02
    frf_start_frac: float = 0.05
    horizon_per_wc: float = 60.0
    residual_per_wc: float = 8.0
    samples: int = 12001
    design: slew.SlewDesign = slew.SlewDesign()


def stations(beam, case: Case) -> tuple[tuple[float, float], ...]:
    """The swept patches (x_a, x_b), m."""
    L = beam.length_m
    return tuple((s * L, (s + case.patch_frac) * L) for s in case.starts_frac)


def truth_plants(truth, beam, case: Case):
    """J_h (kg m^2), r (m), the truth's modal gains (the swept patches, then the profile the
    fitted map's sign alignment needs) and its slew plant for every swept patch."""
    r = case.radius_frac * beam.length_m
    gains = truth_modal_gains(truth, beam, (*stations(beam, case),
                                            *profile_stations(beam.length_m)))
    J_h = hub_inertia_for_stiffening(gains, r, case.stiffening)
    h = hybrid_from_gains(gains, J_h, r, case.damping_ratio, damping="modal")
    return J_h, r, gains, [slew.plant_from_hybrid(h, a) for a in range(len(case.starts_frac))]


def prbdm_plants(beam, result, gains, J_h: float, r: float, case: Case, kind: str):
    """A fitted PRBDM on the hub with the ``kind`` of strain map: (LinearModel, slew plant) for
    every swept patch."""
    model = build_model(beam, result.lengths_m, result.stiffness_Nm_per_rad, hub=Hub(J_h, r))
    out = []
    for act in patch_actuators(model, gains, stations(beam, case), kind):
        lin = linearize(model, inputs=slew.INPUTS, outputs=slew.OUTPUTS, actuators=(act,),
                        damping_ratio=case.damping_ratio)
        out.append((lin, slew.plant_from_linear(lin, r + beam.length_m)))
    return out


def metrics(resp: slew.SlewResponse, wc: float, case: Case) -> dict:
    """Settling, residual tip vibration and cost of a slew (``slew_metrics``)."""
    return slew_metrics(resp, case.design.angle_rad, wc, case.residual_per_wc)


def run(beam, truth, case: Case, joints=(3, 4, 5), objectives=("eigen", "combined"),
        starts: int = 8, design_model=(5, "combined", "fitted")):
    """Fits, open-loop errors, closed loops and the co-design sweep, with either strain map
    (``MAPS``); ``design_model``: (joints, objective, map) of the plant the LQG is designed on.
    Returns a dict of rows and the responses to plot."""
    J_h, r, gains, t_plants = truth_plants(truth, beam, case)
    target = target_from_truth(truth, beam.tip_force_N)
    fits = {(n, o): fit(beam, target, n, objective=o, stiffness="joint", starts=starts,
                        seed=0, progress=False) for n in joints for o in objectives}
    plants = {(n, o, m): prbdm_plants(beam, f, gains, J_h, r, case, m)
              for (n, o), f in fits.items() for m in MAPS}
    nom = case.starts_frac.index(case.nominal_start_frac)
    d_plant = plants[design_model][nom][1]
    scales = slew.slew_scales(d_plant, case.design)
    wc = scales.omega_c_rad_s
    t = np.linspace(0.0, case.horizon_per_wc / wc, case.samples)
    comp = slew.slew_controller(d_plant, case.design, scales)
    t_resp = slew.slew_response(t_plants[nom], comp, case.design, scales, t)
    rows, curves = [], {"truth": t_resp}
    for (n, o, m), pl in plants.items():
        lin, p = pl[nom]
        w_t = t_plants[nom].frequencies_rad_s[:n]
        resp = slew.slew_response(p, comp, case.design, scales, t)
        if o == design_model[1]:
            curves[f"{n}R {o} {m}"] = resp
        own_s = slew.slew_scales(p, case.design)
        own = slew.slew_controller(p, case.design, own_s)
        own_p = slew.slew_response(p, own, case.design, own_s, t)
        own_t = slew.slew_response(t_plants[nom], own, case.design, own_s, t)
        rows.append({
            "model": f"{n}R", "objective": o, "map": m,
            "freq_err_pct": 100.0 * (p.frequencies_rad_s[:n] / w_t - 1.0),
            "frf_err": frf_errors(lin, t_plants[nom], n, case.frf_start_frac),
            "hub_l2": relative_l2(resp.hub_angle_rad - case.design.angle_rad,
                                  t_resp.hub_angle_rad - case.design.angle_rad),
            "tip_l2": relative_l2(resp.tip_vibration_m, t_resp.tip_vibration_m),
            "prbdm": metrics(resp, wc, case), "own_prbdm": metrics(own_p, wc, case),
            "own_truth": metrics(own_t, wc, case)})
    sweep = codesign(t_plants, plants, case, objective="combined")
    return {"design": " ".join(str(v) for v in (f"{design_model[0]}R", *design_model[1:])),
            "J_h": J_h, "r": r,
            "wc": wc, "truth": metrics(t_resp, wc, case), "rows": rows, "sweep": sweep,
            "curves": curves, "truth_w": t_plants[nom].frequencies_rad_s}


def codesign(t_plants, plants, case: Case, objective: str) -> dict:
    """Realised LQG cost per patch position: each PRBDM's own prediction, the truth under that
    PRBDM's controller, and the truth under a controller designed on the truth itself."""
    out = {"truth_designed": []}
    for tp in t_plants:
        s = slew.slew_scales(tp, case.design)
        c = slew.slew_controller(tp, case.design, s)
        out["truth_designed"].append(_cost(tp, c, case, s))
    for (n, o, m), pl in plants.items():
        if o != objective:
            continue
        pred, on_truth = [], []
        for a, (_, p) in enumerate(pl):
            s = slew.slew_scales(p, case.design)
            c = slew.slew_controller(p, case.design, s)
            pred.append(_cost(p, c, case, s))
            on_truth.append(_cost(t_plants[a], c, case, s))
        tag = f"{n}R" if m == "virtual-work" else f"{n}R {m}"
        out[f"{tag} predicted"], out[f"{tag} on truth"] = pred, on_truth
    return {k: np.array(v) for k, v in out.items()}


def _cost(plant, comp, case, scales) -> float:
    t = np.linspace(0.0, 1.0 / scales.omega_c_rad_s, 2)  # the cost needs no time history
    return slew.slew_response(plant, comp, case.design, scales, t).cost


def tables(res: dict, case: Case, beam, truth) -> tuple[str, dict[str, str]]:
    """The markdown report and the CSV files (name -> text)."""
    tw = ", ".join(f"{w:.2f}" for w in res["truth_w"])
    md = [f"# Slew co-design: {beam.name}, {truth.model} truth", "",
          f"J_h = {res['J_h']:.4g} kg m^2 (first mode +{100 * (case.stiffening - 1):.0f} % "
          f"over clamped), r = {res['r']:.3g} m, truth hub-stiffened modes {tw} rad/s, "
          f"zeta = {case.damping_ratio}, omega_c = {res['wc']:.3g} rad/s, slew "
          f"{case.design.angle_rad} rad, patch {case.patch_frac} L from "
          f"{case.nominal_start_frac} L; FRF band [{case.frf_start_frac} omega_1, 1.2 omega_n].",
          "", "## Open loop", "",
          "Strain map: virtual-work (the joints inside the patch), fitted (joint weights matching "
          "the truth's clamped modal gains) or fitted-tip_z (matching its strain -> tip z "
          "residues); the hub-torque columns do not depend on it.",
          "", "| model | objective | map | frequency errors (%) | " + " | ".join(PAIR_NAMES)
          + " |", "|---|---|---|---|" + "---|" * len(PAIR_NAMES)]
    csv1 = ["model,objective,map,freq_errors_pct," + ",".join(PAIR_NAMES)]
    for r in res["rows"]:
        fe = " / ".join(f"{e:+.3g}" for e in r["freq_err_pct"])
        md.append(f"| {r['model']} | {r['objective']} | {r['map']} | {fe} | "
                  + " | ".join(f"{100 * e:.3g} %" for e in r["frf_err"]) + " |")
        csv1.append(f"{r['model']},{r['objective']},{r['map']},{fe.replace(' ', '')},"
                    + ",".join(f"{e:.6g}" for e in r["frf_err"]))
    keys = ("settle_hub_s", "settle_tip_s", "residual_tip_m", "cost")
    head = "| plant | hub error L2 | tip error L2 | hub settling (s) | tip settling (s) | " \
           "residual tip (m) | cost | own LQG on truth: hub settling (s) / residual (m) / cost |"
    md += ["", f"## Closed loop: the {res['design']} model's LQG on every plant", "", head,
           "|---|---|---|---|---|---|---|---|"]
    tm = res["truth"]
    md.append(f"| truth | | | {tm['settle_hub_s']:.3g} | {tm['settle_tip_s']:.3g} | "
              f"{tm['residual_tip_m']:.3g} | {tm['cost']:.4g} | |")
    csv2 = ["plant,hub_l2,tip_l2," + ",".join(keys) + ",own_truth_" + ",own_truth_".join(keys)]
    csv2.append("truth,,," + ",".join(f"{tm[k]:.6g}" for k in keys) + ",,,,")
    for r in res["rows"]:
        m, o = r["prbdm"], r["own_truth"]
        md.append(f"| {r['model']} {r['objective']} {r['map']} | {100 * r['hub_l2']:.3g} % | "
                  f"{100 * r['tip_l2']:.3g} % | {m['settle_hub_s']:.3g} | "
                  f"{m['settle_tip_s']:.3g} | {m['residual_tip_m']:.3g} | {m['cost']:.4g} | "
                  f"{o['settle_hub_s']:.3g} / {o['residual_tip_m']:.3g} / {o['cost']:.4g} |")
        csv2.append(f"{r['model']} {r['objective']} {r['map']},{r['hub_l2']:.6g},"
                    f"{r['tip_l2']:.6g},"
                    + ",".join(f"{m[k]:.6g}" for k in keys) + ","
                    + ",".join(f"{o[k]:.6g}" for k in keys))
    sw = res["sweep"]
    names = list(sw)
    md += ["", "## Co-design: realised LQG cost against the patch's start (best in bold)", "",
           "| start (L) | " + " | ".join(names) + " |", "|---|" + "---|" * len(names)]
    best = {k: int(np.argmin(v)) for k, v in sw.items()}
    for a, s in enumerate(case.starts_frac):
        md.append(f"| {s:.1f} | " + " | ".join(
            (f"**{sw[k][a]:.4g}**" if best[k] == a else f"{sw[k][a]:.4g}") for k in names) + " |")
    csv3 = ["start_frac," + ",".join(names)] + [
        f"{s}," + ",".join(f"{sw[k][a]:.6g}" for k in names)
        for a, s in enumerate(case.starts_frac)]
    md += ["", "Best start (L): " + ", ".join(
        f"{k} {case.starts_frac[best[k]]:.1f}" for k in names), ""]
    return "\n".join(md), {"open_loop.csv": "\n".join(csv1) + "\n",
                           "closed_loop.csv": "\n".join(csv2) + "\n",
                           "codesign.csv": "\n".join(csv3) + "\n"}


def figure(res: dict, case: Case, path: Path) -> Path:
    """Hub angle and tip vibration of every plant; the co-design cost against position."""
    from prbdm_pin.views.plots import new_figure, save_png

    fig = new_figure((12.0, 4.0))
    ax = fig.subplots(1, 3)
    for name, resp in res["curves"].items():
        style = {"color": "k", "lw": 2.0} if name == "truth" else {"lw": 1.0}
        ax[0].plot(resp.t_s, resp.hub_angle_rad, label=name, **style)
        ax[1].plot(resp.t_s, 1e3 * resp.tip_vibration_m, **style)
    ax[0].set(xlabel="t (s)", ylabel="hub angle (rad)", title=f"slew, {res['design']} LQG")
    ax[1].set(xlabel="t (s)", ylabel="elastic tip deflection (mm)", title="tip vibration")
    ax[0].legend(fontsize=7)
    for a in ax[:2]:
        a.set_xlim(0.0, 20.0 / res["wc"])  # the slew; the rest of the horizon is at rest
    # the design model's predictions per strain map; every curve is in the CSV and the tables
    largest = res["design"].split()[0]
    for k, v in res["sweep"].items():
        if k != "truth_designed" and not (k.startswith(largest) and "predicted" in k):
            continue
        style = {"color": "k", "lw": 2.0, "marker": "o"} if k == "truth_designed" else \
            {"marker": "."}
        ax[2].plot(case.starts_frac, v, label=k, **style)
    ax[2].set(xlabel="patch start (x / L)", ylabel="LQG cost",
              title=f"co-design: {largest} predictions, truth")
    ax[2].legend(fontsize=7)
    fig.tight_layout()
    return save_png(fig, path)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--beam", default=str(ROOT / "examples" / "beams" / "reference-random.json"))
    ap.add_argument("--truth-model", choices=("plate", "beam"), default="plate")
    ap.add_argument("--joints", default="3,4,5", help="the largest one's combined fit "
                    "designs the controller")
    ap.add_argument("--starts", type=int, default=8)
    ap.add_argument("--cache-dir", default=str(ROOT / "results" / "truth-cache"))
    ap.add_argument("--out", default=str(ROOT / "results" / "ccd_slew"))
    args = ap.parse_args(argv)
    beam = load_beam(args.beam)
    truth = compute_truth(beam, model=args.truth_model, cache_dir=args.cache_dir)
    case = Case()
    joints = tuple(int(v) for v in args.joints.split(","))
    res = run(beam, truth, case, joints=joints, starts=args.starts,
              design_model=(max(joints), "combined", "fitted"))
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    md, csvs = tables(res, case, beam, truth)
    csvs["summary.json"] = summary(res, case, beam, truth)
    for name, text in csvs.items():
        atomic_write_text(out / name, text)
    print(md)
    png = figure(res, case, out / "ccd_slew.png")
    print(f"wrote {png}, {write_page(out)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
