"""Figures of the guide pages that no example draws: the calibration and the robustness pages.

``calibration_ring_down.png``: the uniform strip's 5R eigen fit (1D beam truth, as
``scripts/bench_calibrate.py`` makes it) calibrated to a 4 s ring-down of the truth's first two
modes with E x 1.07, rho x 0.96, damping ratios 0.012 and 0.006 and 2 % noise (seed 0), drawn by
``write_calibration`` (data against the calibrated model).

``robustness_mesh_budget.png``: the plate truth's degrees of freedom per mesh level for the
shipped beams, the mesh built (levels 0-1) and the estimate the cap is checked on before meshing
(levels 0-3), against the default cap ``max_mesh_dofs``.

Writes both into docs/guide/figures/ (or ``--out``). BLAS is pinned to one thread.

    python scripts/guide_figures.py [--out docs/guide/figures]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import shutil  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from ring_down_truth import truth_ring_down  # noqa: E402

import prbdm_pin as pp  # noqa: E402
from prbdm_pin.fitting.calibration_data import ring_down  # noqa: E402
from prbdm_pin.truth.plant import clamped_model  # noqa: E402

BEAMS = ROOT / "examples" / "beams"
S_E, S_RHO, ZETA = 1.07, 0.96, np.array([0.012, 0.006])
ETA0 = np.array([0.05, 0.01, 0.0, 0.3])  # modal coordinates (sqrt(kg) m) and rates


def calibration_figure(out: Path) -> Path:
    """Calibrate the strip's 5R chain to a noisy truth ring-down; copy write_calibration's plot."""
    beam = pp.load_beam(BEAMS / "uniform-narrow.json")
    truth = pp.compute_truth(beam, model="beam", modes=5, error_tol_pct=None)
    result = pp.fit(beam, pp.target_from_truth(truth, beam.tip_force_N), 5, objective="eigen",
                    stiffness="joint", starts=2, progress=False)
    chain = pp.build_model(beam, result.lengths_m, result.stiffness_Nm_per_rad)
    plant = clamped_model(truth, beam, damping_ratio=0.0)
    t = np.arange(1000) / 250.0  # 4 s at 250 Hz
    clean = truth_ring_down(plant, S_E, S_RHO, ZETA, t, ETA0)
    y = clean + 0.02 * np.abs(clean).max() * np.random.default_rng(0).standard_normal(clean.shape)
    cal = pp.calibrate(chain, ring_down(t, y, ["tip_z_m"]), ["E", "damping[0]", "damping[1]"])
    with tempfile.TemporaryDirectory() as tmp:
        folder = pp.write_calibration(cal, Path(tmp) / "cal")
        target = out / "calibration_ring_down.png"
        shutil.copyfile(folder / "calibration.png", target)
    print(f"calibrated E {cal.values[0]:.5g} Pa (data: {beam.material.E_Pa * S_E / S_RHO:.5g}), "
          f"ratios {cal.values[1]:.4g}, {cal.values[2]:.4g} (data: {ZETA[0]}, {ZETA[1]})")
    return target


def mesh_budget_figure(out: Path) -> Path:
    """Plate DOFs per level: built (levels 0-1) and estimated (0-3), with the default cap."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from skfem import Basis

    from prbdm_pin.options.limits import Limits
    from prbdm_pin.truth.mesh import planform_tri_mesh
    from prbdm_pin.truth.mesh_budget import estimate_plate_dofs
    from prbdm_pin.truth.plate_elements import ElementTriArgyrisLocal

    cap = Limits().max_mesh_dofs
    fig, ax = plt.subplots(figsize=(7.0, 3.6))
    levels = np.arange(4)
    for k, path in enumerate(sorted(BEAMS.glob("*.json"))):
        beam = pp.load_beam(path)
        colour = f"C{k}"
        estimate = [estimate_plate_dofs(beam, int(lev)) for lev in levels]
        built = [Basis(planform_tri_mesh(beam, int(lev)), ElementTriArgyrisLocal()).N
                 for lev in levels[:2]]
        ax.plot(levels, estimate, "--", color=colour, marker="o", mfc="none")
        ax.plot(levels[:2], built, "-", color=colour, marker="o", label=beam.name)
    ax.axhline(cap, color="k", lw=1.5)
    ax.text(0.02, cap * 1.15, f"default cap max_mesh_dofs = {cap:,}", fontsize=8)
    ax.set_yscale("log")
    ax.set_ylim(top=cap * 3)
    ax.set_xticks(levels)
    ax.set_xlabel("plate mesh level")
    ax.set_ylabel("degrees of freedom")
    ax.set_title("plate truth: mesh built (solid) and estimated before meshing (dashed)")
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    target = out / "robustness_mesh_budget.png"
    fig.savefig(target, dpi=110)
    plt.close(fig)
    return target


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "docs" / "guide" / "figures"))
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for path in (calibration_figure(out), mesh_budget_figure(out)):
        print(f"wrote {path} ({path.stat().st_size / 1024:.0f} kB)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
