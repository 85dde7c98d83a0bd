"""Spatial panel: a wide panel's planar and spatial fits side by side against the plate.
=====================================================================================

A wide panel twists: among the plate's first modes, torsion modes sit between the bending ones,
and a force at a tip corner (a sensor, an actuator, a load off the centre line) excites them at
once. The planar chain (joints about y) has bending modes only; the spatial ``xy`` chain adds a
torsion joint at each node, fitted to the plate's torsion modes, and with ``gain_points`` also
to how much each of its modes moves the corner. The script prints the frequencies by kind, writes
the FRF of a tip-corner force to the tip-corner displacement (truth, planar, spatial) as a
figure, and exports the spatial model.

Full mode: the reference panel, plate truth (30 modes), 5 joints, 8 starts.
Quick mode (``--quick``): the uniform strip, plate truth at mesh level 1, 3 joints, 4 starts.

Run it with::

    python examples/spatial_panel.py [--quick] [--out results/examples/spatial_panel]
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import prbdm_pin as pp
from prbdm_pin.commands.script_cli import run_example
from prbdm_pin.fitting.spatial_gains import with_point_gains
from prbdm_pin.io.paths import check_out_dir
from prbdm_pin.simulation.response import ModalTip, modal_frf, relative_l2

# sphinx-gallery runs the script without __file__, from the examples folder
ROOT = Path(globals().get("__file__", "spatial_panel.py")).resolve().parents[1]
POINT = "tip_corner_left"
ZETA = 0.02


def corner_frf(model, w_rad_s: np.ndarray) -> np.ndarray:
    """Return the chain's corner force to corner displacement FRF (m/N), its modes summed."""
    om, phi = model.modes()
    a = model.point_kinematics(POINT)[1][2] @ phi  # mass-normalised corner amplitudes
    return modal_frf(ModalTip(om, a**2), w_rad_s, ZETA)


def main(quick: bool = False, out: Path = ROOT / "results" / "examples" / "spatial_panel"
         ) -> dict:
    """Fit planar and spatial chains, compare them by kind and at the corner."""
    out = check_out_dir("out", out)  # refused before any work, as --out
    out.mkdir(parents=True, exist_ok=True)
    if quick:
        beam = pp.load_beam(ROOT / "examples" / "beams" / "uniform-narrow.json")
        truth = pp.compute_truth(beam, model="plate", mesh_level=1, modes=3, static=False)
        joints, starts = 3, 4
    else:
        beam = pp.load_beam(ROOT / "examples" / "beams" / "reference-random.json")
        truth = pp.compute_truth(beam, model="plate", modes=5, static=False, n_computed=30,
                                 cache_dir=out / "cache")
        joints, starts = 5, 8
    # every computed plate mode, its kind, and its amplitude at the tip points
    target = with_point_gains(pp.target_from_truth(truth, beam.tip_force_N), truth, beam)
    planar = pp.fit(beam, target, joints, stiffness="joint", starts=starts, progress=False)
    spatial = pp.fit(beam, target, joints, axes="xy", stiffness="joint", starts=starts,
                     gain_points=(POINT,), progress=False)
    print(f"{beam.name}: {joints} joints, plate truth modes by kind (rad/s):")
    for m in spatial.modes:
        model_w = "not modelled" if m["omega_model_rad_s"] is None else \
            f"{m['omega_model_rad_s']:10.2f} ({m['error_pct']:+.1e} %)"
        print(f"  {m['kind']:<10} {m['omega_truth_rad_s']:10.2f}  spatial {model_w}")
    for g in spatial.gains:
        print(f"  corner amplitude, {g['kind']} mode at {g['omega_truth_rad_s']:.1f} rad/s: "
              f"truth {g['truth_per_sqrt_kg']:.4f}, spatial {g['model_per_sqrt_kg']:.4f} 1/kg^0.5")

    models = {"planar": pp.build_model(beam, planar.lengths_m, planar.stiffness_Nm_per_rad),
              "spatial": pp.build_model(beam, spatial.lengths_m, spatial.stiffness_Nm_per_rad,
                                        axes="xy")}
    w_max = max(m["omega_truth_rad_s"] for m in spatial.modes
                if m["omega_model_rad_s"] is not None)
    w = np.linspace(0.0, 1.2 * w_max, 4001)[1:]
    corner = dict(target.point_gains)[POINT]
    H_truth = modal_frf(ModalTip(target.all_omega_rad_s, corner**2), w, ZETA)
    H = {name: corner_frf(m, w) for name, m in models.items()}
    errors = {name: relative_l2(h, H_truth) for name, h in H.items()}
    print("corner FRF, relative L2 against the plate: " + ", ".join(
        f"{name} {100 * e:.1f} %" for name, e in errors.items()))

    pp.save_fit(spatial, out / "fit.json", beam=beam)
    mjcf = pp.export_model(models["spatial"], out / "model.xml", "mjcf",
                           omega_truth_rad_s=spatial.omega_truth_rad_s)
    print(f"wrote {out / 'fit.json'} and {mjcf}")
    figure = out / "spatial_panel.png"
    _plot(w, H_truth, H, errors, figure, f"{beam.name}: {joints} joints, corner FRF")
    return {"beam": beam, "truth": truth, "planar": planar, "spatial": spatial,
            "models": models, "w_rad_s": w, "frf_truth": H_truth, "frf": H,
            "frf_errors": errors, "figure": figure}


def _plot(w, H_truth, H, errors, path: Path, title: str) -> Path:
    from prbdm_pin.views.plots import new_figure, save_figure

    fig = new_figure((7.5, 4.2))
    ax = fig.add_subplot()
    ax.semilogy(w, np.abs(H_truth), color="k", lw=2.0, label="plate truth (modal)")
    for (name, h), style in zip(H.items(), ("--", "-"), strict=True):
        ax.semilogy(w, np.abs(h), style, lw=1.2,
                    label=f"{name} chain (L2 error {100 * errors[name]:.1f} %)")
    ax.set_xlabel("frequency (rad/s)")
    ax.set_ylabel("|corner z / corner force| (m/N)")
    ax.set_title(title)
    ax.legend(loc="upper right", fontsize=8)
    return save_figure(fig, path)


if __name__ == "__main__":
    # no SystemExit on success: sphinx-gallery runs this block in the build's process
    if code := run_example(__doc__, ROOT / "results" / "examples" / "spatial_panel",
                           main):
        raise SystemExit(code)
