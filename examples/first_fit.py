"""First fit: a shipped beam through the Python API, from truth to an exported URDF.
=================================================================================

The finite-element truth of a beam gives the natural frequencies (and the large-deflection tip)
to match; a multistart fit places the joints and sizes the springs of an nR chain; the result
reports the signed error of every mode; the model goes out as a URDF and comes back through
``prbdm_pin.load_urdf`` with the same frequencies.

Full mode: the reference panel, plate truth, 4R joint springs, combined objective, 8 starts.
Quick mode (``--quick``): the uniform strip, 1D Euler-Bernoulli truth, 3R eigen fit, 4 starts.

Run it with::

    python examples/first_fit.py [--quick] [--out results/examples/first_fit]
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import prbdm_pin as pp
from prbdm_pin.commands.script_cli import run_example
from prbdm_pin.io.paths import check_out_dir
from prbdm_pin.views.plots import plot_planform

# sphinx-gallery runs the script without __file__, from the examples folder
ROOT = Path(globals().get("__file__", "first_fit.py")).resolve().parents[1]


def main(quick: bool = False, out: Path = ROOT / "results" / "examples" / "first_fit") -> dict:
    """Fit, report and export; returns the truth's and the models' frequencies (rad/s)."""
    out = check_out_dir("out", out)  # refused before any work, as --out
    out.mkdir(parents=True, exist_ok=True)
    if quick:
        beam = pp.load_beam(ROOT / "examples" / "beams" / "uniform-narrow.json")
        truth = pp.compute_truth(beam, model="beam", modes=3)
        joints, options = 3, pp.FitOptions(stiffness="joint", objective="eigen", starts=4)
    else:
        beam = pp.load_beam(ROOT / "examples" / "beams" / "reference-random.json")
        truth = pp.compute_truth(beam, model="plate", modes=4, cache_dir=out / "cache")
        joints, options = 4, pp.FitOptions(stiffness="joint", objective="combined", starts=8)

    # what the fit matches: the truth's selected frequencies and its tip under the beam's load
    target = pp.target_from_truth(truth, beam.tip_force_N)
    result = pp.fit(beam, target, joints, options, progress=False)
    print(f"{beam.name}: {joints}R, loss {result.loss_pct:.3g} %, worst mode "
          f"{result.worst_mode_error_pct:.3g} %")
    for k, (w_t, e) in enumerate(zip(result.omega_truth_rad_s, result.omega_errors_pct[0],
                                     strict=True)):
        print(f"  mode {k + 1}: truth {w_t:9.3f} rad/s, model error {e:+.2e} %")
    for line in result.warnings:
        print("  fit warning:", line)

    # the exported model: its file records its own frequencies and per-mode errors
    model = pp.build_model(beam, result.lengths_m, result.stiffness_Nm_per_rad)
    urdf = pp.export_model(model, out / "model.urdf", "urdf",
                           omega_truth_rad_s=result.omega_truth_rad_s)
    pp.save_fit(result, out / "fit.json", beam=beam)
    reloaded = pp.load_urdf(urdf)  # springs from the file, gravity off
    print(f"wrote {urdf} and {out / 'fit.json'}")

    figure = out / "first_fit.png"
    plot_planform(beam, result.lengths_m, figure, title=f"{beam.name}: fitted {joints}R PRBDM")
    return {"beam": beam, "result": result, "figure": figure,
            "omega_truth_rad_s": np.asarray(result.omega_truth_rad_s),
            "omega_model_rad_s": model.natural_frequencies(),
            "omega_urdf_rad_s": reloaded.natural_frequencies()}


if __name__ == "__main__":
    # no SystemExit on success: sphinx-gallery runs this block in the build's process
    if code := run_example(__doc__, ROOT / "results" / "examples" / "first_fit", main):
        raise SystemExit(code)
