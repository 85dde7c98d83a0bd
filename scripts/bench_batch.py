"""Batch throughput: truth + fit per beam on this machine, and the paper's 50,000-beam study
projected onto 100 cores.

Runs ``prbdm_pin.batch.run_batch`` on random beams (each batch folder under
``results/bench_batch/`` has its own truth cache, so the truth is computed, not read) and writes
``results/bench_batch.md``. Rerunning resumes an interrupted bench. The projection assumes the
beams are independent (they are) and the cluster's cores are as fast as these.

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
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.options.objects import FitOptions  # noqa: E402

PAPER_BEAMS = 50_000
PAPER_CORES = 100


def bench(settings: FitSettings, beams: int, workers: int, seed: int, out: Path) -> dict:
    """Run (or resume) one batch in ``out``; per-beam timings, memory and losses."""
    load0 = os.getloadavg()[0]
    s = run_batch(BatchSpec(seed=seed, settings=settings, n_beams=beams), out,
                  backend=LocalPool(workers), progress=True)
    recs = read_records(out / RESULTS_JSONL)
    ok = [r for r in recs if r.get("status") == "ok"]
    nan = float("nan")
    beam_s = statistics.mean(r["wall_s"] for r in ok) if ok else nan
    # one beam occupies one core for its whole wall time (one BLAS thread, workers=1 fits)
    per_core_h = 3600.0 / beam_s if ok else nan
    return {
        "beams": beams, "workers": workers, "ok": len(ok), "failed": len(recs) - len(ok),
        "run_wall_s": s.wall_s,
        "truth_s": [r["truth_s"] for r in ok],
        "fit_s": statistics.mean(r["fit_s"] for r in ok) if ok else nan,
        "beam_s": beam_s,
        "loss": statistics.median(r["eigen_loss_pct"] for r in ok) if ok else nan,
        "per_core_h": per_core_h,
        "projection_h": PAPER_BEAMS / (per_core_h * PAPER_CORES) if ok else nan,
        # only meaningful while this run computed beams (not for a resumed, finished batch)
        "load": (load0 + os.getloadavg()[0]) / 2.0 if s.n_ok + s.n_failed else nan,
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
                   help="comma-separated TRUTH_MODEL:STIFFNESS[:BEAMS]")
    p.add_argument("--seed", type=int, default=12345)
    p.add_argument("--out", default="results/bench_batch.md")
    p.add_argument("--runs", default="results/bench_batch",
                   help="batch folders (resumable: rerun to complete an interrupted bench)")
    a = p.parse_args()
    rows = []
    for config in a.configs.split(","):
        truth_model, kind, *n = config.split(":")
        beams = int(n[0]) if n else a.beams
        settings = FitSettings(joints=a.joints, options=FitOptions(stiffness=kind, starts=a.starts),
                               truth_model=truth_model)
        out = Path(a.runs) / f"{truth_model}-{kind}-{a.joints}R-{beams}"
        r = bench(replace(settings, cache_dir=str(out / "truth-cache")), beams, a.workers,
                  a.seed, out)
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
        "| truth | stiffness | beams | workers | failed | truth / beam (s) "
        "| fit / beam (s) | beam total (s) | median eigen loss (%) | beams / h / core "
        f"| {PAPER_BEAMS:,} beams on {PAPER_CORES} cores (h) | worker peak RSS (GB) "
        "| load avg |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for kind, r in rows:
        lines.append(
            f"| {kind} | {r['ok']} | {r['workers']} | {r['failed']} | "
            f"{' / '.join(f'{t:.0f}' for t in r['truth_s'])} | {r['fit_s']:.1f} | "
            f"{r['beam_s']:.1f} | {r['loss']:.3g} | "
            f"{r['per_core_h']:.1f} | {r['projection_h']:.2f} | {r['peak_rss_gb']:.1f} | "
            f"{r['load']:.1f} |"
        )
    lines += [
        "",
        "Truth / beam lists every beam's truth time. Throughput per core = 3600 s / mean beam "
        "wall time (a beam holds one core: one BLAS thread, fit starts run serially). The "
        "projection divides the study by 100 such cores (beams are independent, so it scales "
        "linearly until the scheduler or the file system limits it). A load average above the "
        "core count means other processes shared the cores and the times are pessimistic.",
    ]
    for kind, r in rows:
        for e in r["errors"]:
            lines.append(f"- {kind}: failure: {e}")
    atomic_write_text(a.out, "\n".join(lines) + "\n")
    print(f"-> {a.out}")


if __name__ == "__main__":
    main()
