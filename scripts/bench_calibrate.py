"""Calibration cost and accuracy: E and two modal damping ratios of the 5R strip fitted to a
10 s ring-down sampled at 250 Hz (the issue's target: under 5 s of CPU).

The strip is examples/beams/uniform-narrow.json; its chain is the 5R eigen fit against the 1D
beam truth (``prbdm fit --truth-model beam --objective eigen --stiffness joint --starts 2``),
whose five frequencies are the truth's. The data: the truth's clamped modal model (its first
two modes) with E scaled by 1.07, rho by 0.96 and damping ratios 0.012 and 0.006, stepped by the
matrix exponential (tests/ring_down_truth.py), tip z with Gaussian noise of 2 % of its peak;
one channel (tip z) and two (tip z and its rate). Per case, over 50 seeds: the CPU time of
``calibrate`` alone (process time; the model's linearisation included, the truth and the fit
not), the median, and how often each parameter lies within 2 standard errors of the truth's
(E: E0 s_E / s_rho, which is what a ring-down sees), and the standard deviation of the errors
divided by their standard errors (1 when the standard errors are right).

Writes a Markdown table to results/bench_calibrate.md and docs/benchmarks/bench_calibrate.md
(or the path given with --out). BLAS is pinned to one thread before numpy is imported.

    python scripts/bench_calibrate.py [--out results/bench_calibrate.md] [--seeds 50]
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
from ring_down_truth import truth_ring_down  # noqa: E402

from prbdm_pin.cli import main as prbdm  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.files.model_source import load_model  # noqa: E402
from prbdm_pin.fitting.calibrate import calibrate  # noqa: E402
from prbdm_pin.fitting.calibration_data import ring_down  # noqa: E402
from prbdm_pin.truth import compute_truth  # noqa: E402
from prbdm_pin.truth.plant import clamped_model  # noqa: E402
from prbdm_pin.truth.request import TruthRequest  # noqa: E402

BEAM = ROOT / "examples" / "beams" / "uniform-narrow.json"
S_E, S_RHO, ZETA = 1.07, 0.96, np.array([0.012, 0.006])
ETA0 = np.array([0.05, 0.01, 0.0, 0.3])
PARAMS = ("E", "damping[0]", "damping[1]")


def case(chain, plant, want, rates: bool, seeds: int) -> str:
    t = np.arange(2500) / 250.0  # 10 s at 250 Hz
    clean = truth_ring_down(plant, S_E, S_RHO, ZETA, t, ETA0, rates=rates)
    names = ["tip_z_m", "tip_z_rate_m_s"][:clean.shape[1]]
    cpu, hits, last, zs = [], np.zeros(3, dtype=int), None, []
    for seed in range(seeds):
        rng = np.random.default_rng(seed)
        y = clean + 0.02 * np.abs(clean).max(axis=0) * rng.standard_normal(clean.shape)
        data = ring_down(t, y, names)
        c0 = time.process_time()
        last = calibrate(chain, data, PARAMS)
        cpu.append(time.process_time() - c0)
        hits += np.abs(last.values - want) <= 2 * last.std_errors
        zs.append((last.values - want) / last.std_errors)
    vals = " / ".join(f"{v:.6g} +/- {s:.2g}" for v, s in zip(last.values, last.std_errors,
                                                          strict=True))
    return (f"| {', '.join(n[:-2] if n.endswith('_m') else n[:-4] for n in names)} | "
            f"{np.median(cpu):.3f} | {max(cpu):.3f} | {vals} | "
            + " / ".join(f"{h}/{seeds}" for h in hits) + " | "
            + " / ".join(f"{v:.2f}" for v in np.std(zs, axis=0)) + " |")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_calibrate.md"))
    ap.add_argument("--seeds", type=int, default=50)
    args = ap.parse_args()
    beam = load_beam(BEAM)
    plant = clamped_model(compute_truth(beam, TruthRequest(model="beam", modes=4, static=False,
                                                           error_tol_pct=None)),
                          beam, damping_ratio=0.0)
    want = np.r_[beam.material.E_Pa * S_E / S_RHO, ZETA]
    with tempfile.TemporaryDirectory() as tmp:
        assert prbdm(["fit", str(BEAM), "--joints", "5", "--truth-model", "beam", "--objective",
                      "eigen", "--stiffness", "joint", "--starts", "2", "--cache-dir",
                      f"{tmp}/cache", "--out", f"{tmp}/fit", "-q"]) == 0
        chain = load_model(f"{tmp}/fit/fit.json").model
        rows = [case(chain, plant, want, rates, args.seeds) for rates in (False, True)]
    lines = [
        "# Calibration: E and two modal damping ratios from a 10 s ring-down at 250 Hz",
        "",
        f"5R eigen fit of the uniform strip; data from the 1D beam truth's first two modes with "
        f"E x {S_E}, rho x {S_RHO}, damping ratios {ZETA[0]} and {ZETA[1]}, 2 % noise, 2500 "
        f"samples per channel. Truth: E0 s_E / s_rho = {want[0]:.6g} Pa (a ring-down sees "
        "E / rho). CPU of `calibrate` per run, one BLAS thread; target under 5 s.",
        "",
        "| channels | median CPU (s) | max CPU (s) | E (Pa) / damping[0] / damping[1], last "
        "seed | within 2 std errors | std of error / std error |",
        "|---|---|---|---|---|---|",
        *rows,
        "",
        "Written by `python scripts/bench_calibrate.py`.",
    ]
    text = "\n".join(lines) + "\n"
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    write_table(args.out, text, ap.get_default("out"), "bench_calibrate")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
