"""Control co-design, the short version: a hub slews a flexible panel, PRBDM against the truth.
============================================================================================

A rigid hub (inertia J_h, panel root at radius r = 0.1 L) carries the panel and a full-width
strain patch over [0, 0.2 L]. J_h is solved for so that the hub raises the truth's first
flexible mode by 20 %. A fitted PRBDM goes on the same hub, its patch map fitted to the truth's
modal gains (``fit_strain_actuators``), and is linearised with the slew's inputs (hub torque,
patch moment) and outputs (hub angle and rate, tip z and rate). An LQG compensator designed on
the PRBDM (``prbdm_pin.plant.slew``) slews the hub by 0.1 rad on the PRBDM and on the truth's
own plant (Likins' hybrid coordinates), by exact linear simulation; the regulator's state
feedback also drives the nonlinear PRBDM through ``prbdm_pin.simulate``. The full study (three
strain maps, 3-5 joints, the patch position swept) is ``scripts/ccd_slew.py``.

Full mode: the reference panel, plate truth, 4R combined fit (8 starts).
Quick mode (``--quick``): the uniform strip, 1D beam truth, 3R combined fit (4 starts).

Run it with::

    python examples/ccd_slew.py [--quick] [--out results/examples/ccd_slew]
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import prbdm_pin as pp
from prbdm_pin.commands.script_cli import run_example
from prbdm_pin.io.paths import check_out_dir
from prbdm_pin.plant import slew
from prbdm_pin.plant.slew_study import hub_inertia_for_stiffening
from prbdm_pin.truth.plant import hybrid_model, truth_modal_gains
from prbdm_pin.views.plots import new_figure, save_png

# sphinx-gallery runs the script without __file__, from the examples folder
ROOT = Path(globals().get("__file__", "ccd_slew.py")).resolve().parents[1]
DAMPING_RATIO = 0.02  # every flexible mode, PRBDM and truth alike
DESIGN = slew.SlewDesign(angle_rad=0.1)


def main(quick: bool = False, out: Path = ROOT / "results" / "examples" / "ccd_slew") -> dict:
    """Fit, hub, LQG, slews; returns the responses, the linear plant and the gain."""
    out = check_out_dir("out", out)  # refused before any work, as --out
    out.mkdir(parents=True, exist_ok=True)
    if quick:
        beam = pp.load_beam(ROOT / "examples" / "beams" / "uniform-narrow.json")
        truth = pp.compute_truth(beam, model="beam", modes=5)
        joints, starts = 3, 4
    else:
        beam = pp.load_beam(ROOT / "examples" / "beams" / "reference-random.json")
        truth = pp.compute_truth(beam, model="plate", cache_dir=out / "cache")
        joints, starts = 4, 8
    fit = pp.fit(beam, pp.target_from_truth(truth, beam.tip_force_N), joints,
                 stiffness="joint", objective="combined", starts=starts, progress=False)

    # the hub that stiffens the truth's first mode by 20 %, and the PRBDM on it
    L = beam.length_m
    radius, patch = 0.1 * L, (0.0, 0.2 * L)
    J_h = hub_inertia_for_stiffening(truth_modal_gains(truth, beam, (patch,)), radius, 1.2)
    model = pp.build_model(beam, fit.lengths_m, fit.stiffness_Nm_per_rad,
                           hub=pp.Hub(J_h, radius))
    actuators = pp.fit_strain_actuators(model, truth, beam, [patch])
    lin = pp.linearize(model, inputs=slew.INPUTS, outputs=slew.OUTPUTS, actuators=actuators,
                       damping_ratio=DAMPING_RATIO)
    prbdm = slew.plant_from_linear(lin, radius + L)
    truth_plant = slew.plant_from_hybrid(hybrid_model(
        truth, beam, J_h, radius, actuators=(patch,), damping_ratio=DAMPING_RATIO,
        damping="modal"))
    print(f"J_h = {J_h:.4g} kg m^2; hub-stiffened modes (rad/s): PRBDM "
          f"{np.round(prbdm.frequencies_rad_s[:joints], 2)}, truth "
          f"{np.round(truth_plant.frequencies_rad_s[:joints], 2)}")

    # the LQG designed on the PRBDM, run on both plants (exact linear responses)
    scales = slew.slew_scales(prbdm, DESIGN)
    comp = slew.slew_controller(prbdm, DESIGN, scales)
    t = np.linspace(0.0, 30.0 / scales.omega_c_rad_s, 601 if quick else 1501)
    on_prbdm = slew.slew_response(prbdm, comp, DESIGN, scales, t)
    on_truth = slew.slew_response(truth_plant, comp, DESIGN, scales, t)
    print(f"final hub angle: PRBDM {on_prbdm.hub_angle_rad[-1]:.6f} rad, truth "
          f"{on_truth.hub_angle_rad[-1]:.6f} rad (commanded {DESIGN.angle_rad} rad); cost "
          f"PRBDM {on_prbdm.cost:.4g}, truth {on_truth.cost:.4g}")

    # the regulator's full-state feedback on the nonlinear PRBDM
    x_ref = np.zeros(lin.A.shape[0])
    x_ref[0] = DESIGN.angle_rad
    traj = pp.simulate(model, t[-1], inputs=slew.INPUTS, actuators=actuators,
                       u=pp.StateFeedback(comp.state_gain, x_ref=x_ref),
                       outputs=("hub_angle",), damping_ratio=DAMPING_RATIO,
                       output_dt_s=t[1] - t[0])

    fig = new_figure((9.0, 3.4))
    ax = fig.subplots(1, 2)
    ax[0].plot(t, on_truth.hub_angle_rad, "k", lw=2.5, label=f"truth ({truth.model}), LQG")
    ax[0].plot(t, on_prbdm.hub_angle_rad, "C1", label=f"{joints}R PRBDM, LQG")
    ax[0].plot(traj.t_s, traj.output("hub_angle"), "C0--",
               label=f"{joints}R nonlinear, LQR state feedback")
    ax[1].plot(t, 1e3 * on_truth.tip_vibration_m, "k", lw=2.5)
    ax[1].plot(t, 1e3 * on_prbdm.tip_vibration_m, "C1")
    ax[0].set(xlabel="t (s)", ylabel="hub angle (rad)", title=f"{beam.name}: 0.1 rad slew")
    ax[1].set(xlabel="t (s)", ylabel="elastic tip deflection (mm)", title="tip vibration")
    ax[0].legend(fontsize=7)
    fig.tight_layout()
    figure = save_png(fig, out / "ccd_slew.png")
    return {"t_s": t, "on_prbdm": on_prbdm, "on_truth": on_truth, "trajectory": traj,
            "linear": lin, "gain": comp.state_gain, "angle_rad": DESIGN.angle_rad,
            "figure": figure}


if __name__ == "__main__":
    # no SystemExit on success: sphinx-gallery runs this block in the build's process
    if code := run_example(__doc__, ROOT / "results" / "examples" / "ccd_slew", main):
        raise SystemExit(code)
