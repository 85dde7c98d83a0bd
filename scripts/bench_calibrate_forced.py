"""Calibration to an FRF and to a driven trajectory: cost, model-form error and coverage.

The strip is examples/beams/uniform-narrow.json; its chain is the 5R eigen fit against the 1D
beam truth (``prbdm fit --truth-model beam --objective eigen --stiffness joint --starts 2``),
whose five frequencies are the truth's. The data: the truth's clamped modal model (its first
four modes) with E scaled by 1.07, rho by 0.96 and damping ratios 0.012, 0.006, 0.02, 0.02
(tests/forced_truth.py: its own state space, solved per frequency for the FRF, scipy's zero-
order hold for the trajectory). Four cases: the FRF tip z per tip force and per base
acceleration (400 frequencies, 2 to 80 Hz, modes 1 and 2 inside; complex noise of 2 % of the
FRF's RMS), and tip z driven by a white tip force or base acceleration held over each sample
(10 s at 250 Hz, one input record; noise 2 % of the peak, one draw per seed). Per case: the
noiseless fit's relative error against the truth's parameters (the chain's model-form error:
its modal gains differ from the truth's), the CPU time of ``calibrate`` alone over 50 seeds
(median and max), how often each parameter lies within 2 standard errors of the truth's and of
the noiseless fit's, and the standard deviation of the errors about the noiseless fit divided
by their standard errors (1 when the standard errors are right). A base acceleration's load
scales with rho, so that response sees E/rho only: E is fitted as E0 s_E / s_rho there.

Writes a Markdown table to results/bench_calibrate_forced.md and
docs/benchmarks/bench_calibrate_forced.md (or the path given with --out). BLAS is pinned to one
thread before numpy is imported.

    python scripts/bench_calibrate_forced.py [--out results/bench_calibrate_forced.md] [--seeds 50]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "scripts"))

from docs_tables import write_table  # noqa: E402
from forced_truth import truth_driven, truth_frf  # noqa: E402

from prbdm_pin.cli import main as prbdm  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.files.model_source import load_model  # noqa: E402
from prbdm_pin.fitting.calibrate import calibrate  # noqa: E402
from prbdm_pin.fitting.calibration_measured import (  # noqa: E402
    driven_trajectory,
    frequency_response,
)
from prbdm_pin.truth import compute_truth  # noqa: E402
from prbdm_pin.truth.plant import clamped_model  # noqa: E402
from prbdm_pin.truth.request import TruthRequest  # noqa: E402

BEAM = ROOT / "examples" / "beams" / "uniform-narrow.json"
S_E, S_RHO, ZETA = 1.07, 0.96, np.array([0.012, 0.006, 0.02, 0.02])
F_HZ = np.linspace(2.0, 80.0, 400)
T_S = np.arange(2500) / 250.0  # 10 s at 250 Hz
NOISE = 0.02


def frf_data(plant, inp, seed):
    H = truth_frf(plant, S_E, S_RHO, ZETA, F_HZ, (inp,))[:, 0, 0]
    if seed is not None:
        rng = np.random.default_rng(seed)
        e = (rng.standard_normal(H.shape) + 1j * rng.standard_normal(H.shape)) / np.sqrt(2)
        H = H + NOISE * np.sqrt(np.mean(np.abs(H) ** 2)) * e
    return frequency_response(F_HZ, H[:, None], ["tip_z"], [inp])


def driven_data(plant, inp, seed):
    u = np.random.default_rng(1000).standard_normal((T_S.size, 1))  # one input, noise varies
    y = truth_driven(plant, S_E, S_RHO, ZETA, T_S, u, (inp,))[:, :1]
    if seed is not None:
        y = y + NOISE * np.abs(y).max() * np.random.default_rng(seed).standard_normal(y.shape)
    return driven_trajectory(T_S, u, [inp], y, ["tip_z_m"])


def case(chain, plant, beam, label, make, inp, params, seeds):
    mat = beam.material
    if inp.startswith("base_accel"):
        want = np.r_[mat.E_Pa * S_E / S_RHO, ZETA[:len(params) - 1]]
    else:
        want = np.r_[mat.E_Pa * S_E, mat.rho_kg_m3 * S_RHO, ZETA[:len(params) - 2]]
    clean = calibrate(chain, make(plant, inp, None), params)
    bias = clean.values / want - 1
    cpu, hits, near, zs = [], np.zeros(len(params), int), np.zeros(len(params), int), []
    for seed in range(seeds):
        data = make(plant, inp, seed)
        c0 = time.process_time()
        r = calibrate(chain, data, params)
        cpu.append(time.process_time() - c0)
        hits += np.abs(r.values - want) <= 2 * r.std_errors
        near += np.abs(r.values - clean.values) <= 2 * r.std_errors
        zs.append((r.values - clean.values) / r.std_errors)
    return (f"| {label} | {', '.join(params)} | "
            + " / ".join(f"{b:+.2e}" for b in bias) + f" | {np.median(cpu):.3f} | "
            f"{max(cpu):.3f} | " + " / ".join(f"{h}/{seeds}" for h in hits) + " | "
            + " / ".join(f"{h}/{seeds}" for h in near) + " | "
            + " / ".join(f"{v:.2f}" for v in np.std(zs, axis=0)) + " |")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_calibrate_forced.md"))
    ap.add_argument("--seeds", type=int, default=50)
    args = ap.parse_args()
    beam = load_beam(BEAM)
    plant = clamped_model(compute_truth(beam, TruthRequest(model="beam", modes=4, static=False,
                                                           error_tol_pct=None)),
                          beam, damping_ratio=0.0)
    both, ratio = ["E", "rho", "damping[0]", "damping[1]"], ["E", "damping[0]", "damping[1]"]
    with tempfile.TemporaryDirectory() as tmp:
        assert prbdm(["fit", str(BEAM), "--joints", "5", "--truth-model", "beam", "--objective",
                      "eigen", "--stiffness", "joint", "--starts", "2", "--cache-dir",
                      f"{tmp}/cache", "--out", f"{tmp}/fit", "-q"]) == 0
        chain = load_model(f"{tmp}/fit/fit.json").model
        rows = [case(chain, plant, beam, "FRF tip z / tip force", frf_data, "tip_force_z", both,
                     args.seeds),
                case(chain, plant, beam, "FRF tip z / base accel", frf_data, "base_accel_z",
                     ratio, args.seeds),
                case(chain, plant, beam, "driven by tip force", driven_data, "tip_force_z",
                     both, args.seeds),
                case(chain, plant, beam, "driven by base accel", driven_data, "base_accel_z",
                     ratio, args.seeds)]
    lines = [
        "# Calibration to an FRF and to a driven trajectory",
        "",
        f"5R eigen fit of the uniform strip; data from the 1D beam truth's first four modes with "
        f"E x {S_E}, rho x {S_RHO}, damping ratios {', '.join(str(z) for z in ZETA)}; FRF: "
        f"{F_HZ.size} frequencies from {F_HZ[0]:g} to {F_HZ[-1]:g} Hz, complex noise 2 % of its "
        f"RMS; driven: white input held over each sample, {T_S.size} samples at 250 Hz, noise "
        "2 % of the peak. Base acceleration: E is E0 s_E / s_rho. Noiseless error: the chain's "
        "model-form error (its modal gains are not the truth's). CPU of `calibrate` per run, "
        "one BLAS thread.",
        "",
        "| data | parameters | noiseless relative error | median CPU (s) | max CPU (s) | "
        "within 2 std errors of the truth | within 2 std errors of the noiseless fit | "
        "std of error / std error (about the noiseless fit) |",
        "|---|---|---|---|---|---|---|---|",
        *rows,
        "",
        "Written by `python scripts/bench_calibrate_forced.py`.",
    ]
    text = "\n".join(lines) + "\n"
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    write_table(args.out, text, ap.get_default("out"), "bench_calibrate_forced")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
