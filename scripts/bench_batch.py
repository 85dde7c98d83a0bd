"""Batch throughput: truth + fit per beam on this machine, and the paper's 50,000-beam study
projected onto 100 cores.

Runs ``prbdm_pin.batch.run_batch`` on fresh random beams (empty truth cache) with one worker per
core and writes ``results/bench_batch.md``. Throughput is beams per hour per core: beams divided
by (wall time x workers). The projection assumes the beams are independent (they are) and the
cluster's cores are as fast as these.

    python scripts/bench_batch.py         # plate and beam truth, 4R eigen fit, both stiffness kinds
    python scripts/bench_batch.py --beams 8 --workers 2 --configs plate:paper
"""

from __future__ import annotations

import os

# BLAS reads these once, when it loads: before numpy is imported.
for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from dataclasses import replace  # noqa: E402
from pathlib import Path  # noqa: E402

from prbdm_pin import __version__  # noqa: E402
from prbdm_pin.batch import (  # noqa: E402
    RESULTS_JSONL,
    BatchSpec,
    FitSettings,
    LocalPool,
    read_records,
    run_batch,
)
from prbdm_pin.geometry import atomic_write_text  # noqa: E402

PAPER_BEAMS = 50_000
PAPER_CORES = 100


def bench(settings: FitSettings, beams: int, workers: int, seed: int) -> dict:
    """Run one batch in a temporary folder; timings and losses."""
    with tempfile.TemporaryDirectory() as tmp:
        settings = replace(settings, cache_dir=str(Path(tmp) / "cache"))
        load0 = os.getloadavg()[0]
        t0 = time.perf_counter()
        s = run_batch(BatchSpec(seed=seed, settings=settings, n_beams=beams), Path(tmp) / "out",
                      backend=LocalPool(workers), progress=True)
        wall = time.perf_counter() - t0
        recs = read_records(Path(tmp) / "out" / RESULTS_JSONL)
    ok = [r for r in recs if r.get("status") == "ok"]
    per_core_h = s.n_ok / (wall / 3600.0) / workers if s.n_ok else float("nan")
    return {
        "beams": beams, "workers": workers, "ok": s.n_ok, "failed": s.n_failed, "wall_s": wall,
        "truth_s": statistics.mean(r["truth_s"] for r in ok) if ok else float("nan"),
        "fit_s": statistics.mean(r["fit_s"] for r in ok) if ok else float("nan"),
        "beam_s": statistics.mean(r["wall_s"] for r in ok) if ok else float("nan"),
        "loss": statistics.median(r["eigen_loss_pct"] for r in ok) if ok else float("nan"),
        "per_core_h": per_core_h,
        "projection_h": PAPER_BEAMS / (per_core_h * PAPER_CORES) if ok else float("nan"),
        "load": (load0 + os.getloadavg()[0]) / 2.0,
        "peak_rss_gb": max((r.get("worker_peak_rss_mb") or 0.0 for r in ok), default=0.0)
        / 1024,
        "errors": sorted({r.get("error", "") for r in recs if r.get("status") != "ok"}),
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--beams", type=int, default=6)
    p.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    p.add_argument("--joints", type=int, default=4)
    p.add_argument("--starts", type=int, default=64)
    p.add_argument("--configs", default="plate:paper,beam:paper,beam:joint",
                   help="comma-separated TRUTH_MODEL:STIFFNESS pairs")
    p.add_argument("--seed", type=int, default=12345)
    p.add_argument("--out", default="results/bench_batch.md")
    a = p.parse_args()
    rows = []
    for config in a.configs.split(","):
        truth_model, kind = config.split(":")
        settings = FitSettings(joints=a.joints, stiffness=kind, starts=a.starts,
                               truth_model=truth_model)
        r = bench(settings, a.beams, a.workers, a.seed)
        rows.append((f"{truth_model} | {kind}", r))
        print(config, r, flush=True)
    lines = [
        "# Batch throughput: truth + eigen fit per beam",
        "",
        f"prbdm_pin {__version__}, Python {platform.python_version()}, {platform.machine()}, "
        f"{os.cpu_count()} cores; one BLAS thread per worker; fresh random beams "
        f"(seed {a.seed}, `random_beam` defaults), empty truth cache.",
        f"Truth: default mesh level, the {a.joints} frequencies the fit maps (no static solve); "
        f"fit: {a.joints}R, eigen objective (frequencies as omega), {a.starts} starts.",
        "",
        "| truth | stiffness | beams | workers | failed | wall (s) | truth / beam (s) "
        "| fit / beam (s) | beam total (s) | median eigen loss (%) | beams / h / core "
        f"| {PAPER_BEAMS:,} beams on {PAPER_CORES} cores (h) | worker peak RSS (GB) "
        "| load avg |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for kind, r in rows:
        lines.append(
            f"| {kind} | {r['beams']} | {r['workers']} | {r['failed']} | {r['wall_s']:.1f} | "
            f"{r['truth_s']:.2f} | {r['fit_s']:.2f} | {r['beam_s']:.2f} | {r['loss']:.3g} | "
            f"{r['per_core_h']:.1f} | {r['projection_h']:.2f} | {r['peak_rss_gb']:.1f} | "
            f"{r['load']:.1f} |"
        )
    lines += [
        "",
        "Throughput = fitted beams / (wall time x workers), pool start-up included. The "
        "projection divides the study by 100 such cores (beams are independent, so it scales "
        "linearly until the scheduler or the file system limits it). A load average above the "
        "core count means other processes shared the cores and the numbers are pessimistic.",
    ]
    for kind, r in rows:
        for e in r["errors"]:
            lines.append(f"- {kind}: failure: {e}")
    atomic_write_text(a.out, "\n".join(lines) + "\n")
    print(f"-> {a.out}")


if __name__ == "__main__":
    main()
