"""How closely a diagonal joint damping (URDF/MJCF) carries per-mode damping ratios.

For the shipped beams' 3R and 5R chains (finite-segment springs on fixed link lengths) and
three sets of asked ratios (every mode 0.02; per-mode ratios as a calibration returns them; the
stiffness form's own ratios xi_1 omega_k / omega_1, which a diagonal damping carries exactly),
the table gives the ratios the fitted diagonal damping (``damping_form="modal_fit"``) achieves
(from the damped chain's complex eigenvalues), each mode's error in % of its asked ratio, the
ratios of the two alternatives (the stiffness form C = beta K with beta from mode 1, which the
files carried before; Rayleigh damping alpha M + beta K anchored at modes 1 and 2, which is not
diagonal and no URDF or MJCF carries), and MuJoCo's own free decay of the exported MJCF (the
modes fitted to the sampled state, as tests/files/test_export_modal_fit.py does) against the
recorded achieved ratios.

Writes a Markdown table to results/bench_modal_fit.md and docs/benchmarks/bench_modal_fit.md
(or the path given with --out).

    python scripts/bench_modal_fit.py [--out results/bench_modal_fit.md]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "scripts"))

from docs_tables import write_table  # noqa: E402

from prbdm_pin.chain.stiffness import finite_segment_stiffness  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.files.export import mjcf_text, read_export_record  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402

BEAMS = ("uniform-narrow", "tapered", "reference-random")
LENGTHS = {3: np.array([0.15, 0.3, 0.3, 0.25]), 5: np.array([0.1, 0.2, 0.2, 0.2, 0.15, 0.15])}
CALIBRATED = np.array([0.03, 0.02, 0.025, 0.02, 0.01])


def mujoco_ratios(text: str) -> np.ndarray:
    """The modes' ratios from MuJoCo free decays of the MJCF (RK4 at 10 us, 1e-6 amplitude)."""
    import mujoco

    m = mujoco.MjModel.from_xml_string(text)
    d = mujoco.MjData(m)
    m.opt.timestep, every = 1e-5, 10
    rng = np.random.default_rng(0)
    X0, X1 = [], []
    for _ in range(2):
        mujoco.mj_resetData(m, d)
        d.qpos[:] = 1e-6 * rng.standard_normal(m.nv)
        d.qvel[:] = 1e-4 * rng.standard_normal(m.nv)
        xs = []
        for _ in range(400):
            xs.append(np.concatenate([d.qpos, d.qvel]))
            for _ in range(every):
                mujoco.mj_step(m, d)
        xs = np.array(xs).T
        X0.append(xs[:, :-1])
        X1.append(xs[:, 1:])
    Phi = np.hstack(X1) @ np.linalg.pinv(np.hstack(X0))
    s = np.log(np.linalg.eigvals(Phi).astype(complex)) / (every * m.opt.timestep)
    s = s[s.imag > 0.0]
    s = s[np.argsort(np.abs(s))]
    return -s.real / np.abs(s)


def vec(v, fmt="{:.4f}") -> str:
    return " ".join(fmt.format(x) for x in v)


def row(beam: str, n: int, label: str, model, xi: np.ndarray) -> str:
    w = np.asarray(model.natural_frequencies())
    text = mjcf_text(model, xi, damping_form="modal_fit")
    rec = read_export_record(text)
    err = 100.0 * rec.damping_ratio_errors / xi
    stiff = xi[0] * w / w[0]
    # Rayleigh xi_k = a / (2 w_k) + b w_k / 2 through modes 1 and 2
    a, b = np.linalg.solve([[0.5 / w[0], 0.5 * w[0]], [0.5 / w[1], 0.5 * w[1]]], xi[:2])
    rayleigh = a / (2.0 * w) + b * w / 2.0
    mj = np.abs(mujoco_ratios(text) / rec.modal_damping_ratios - 1.0).max()
    return (f"| {beam} | {n}R | {label} | {vec(xi, '{:.4g}')} | {vec(rec.modal_damping_ratios)} "
            f"| {vec(err, '{:+.1f}')} | {np.abs(err).max():.1f} | {vec(stiff)} "
            f"| {vec(rayleigh)} | {mj:.1e} |")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_modal_fit.md"))
    args = ap.parse_args()
    rows = []
    for name in BEAMS:
        beam = load_beam(ROOT / "examples" / "beams" / f"{name}.json")
        for n, L0 in LENGTHS.items():
            L = L0 * beam.length_m / L0.sum()
            model = build_model(beam, L, finite_segment_stiffness(beam, L))
            w = np.asarray(model.natural_frequencies())
            xi1 = min(0.02, 0.5 * w[0] / w[-1])  # the stiffness form's top mode underdamped
            for label, xi in (("every mode 0.02", np.full(n, 0.02)),
                              ("calibrated", CALIBRATED[:n]),
                              ("stiffness form's", xi1 * w / w[0])):
                rows.append(row(name, n, label, model, xi))
                print(rows[-1], flush=True)
    text = "\n".join([
        "| beam | chain | asked | asked ratios | modal_fit achieved | error % of asked "
        "| worst % | stiffness form (beta from mode 1) | Rayleigh (modes 1, 2; not diagonal) "
        "| MuJoCo decay vs record (max rel.) |",
        "|---|---|---|---|---|---|---|---|---|---|",
        *rows, "",
        "Written by `python scripts/bench_modal_fit.py`; the chains are finite-segment springs on "
        "link lengths 0.15:0.3:0.3:0.25 (3R) and 0.1:0.2:0.2:0.2:0.15:0.15 (5R) of the beam "
        "length.", ""])
    for path in write_table(args.out, text, ap.get_default("out"), "bench_modal_fit"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
