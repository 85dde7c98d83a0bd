"""Start-up cost of the ``prbdm`` command line: ``--help`` of the CLI and of each command, and the
command's own overhead around a fit on a cached truth.

Every figure is the median over ``--runs`` fresh processes (``python -m prbdm_pin ...``) with BLAS
pinned to one thread, as wall time and as the process's CPU time (user + system): on a shared
machine the wall time is inflated by other processes, the CPU time much less. The fit overhead is
the process's wall time minus the fit's own ``wall_time_s`` (recorded in the fit.json it writes):
reading the beam, importing, loading the cached truth, writing fit.json, model.urdf and the
plots. The truth is computed once into a temporary cache before the timed runs. Writes a
Markdown table (default results/bench_cli.md).

usage: python scripts/bench_cli.py [--runs 5] [--out PATH] [--beam BEAM.json] [--starts 8]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
COMMANDS = ("truth", "fit", "pareto", "simulate", "export", "batch", "batch-report", "bench")
HELP_BUDGET_S = 0.5
FIT_OVERHEAD_BUDGET_S = 1.5


def _env() -> dict[str, str]:
    env = dict(os.environ)
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        env[var] = "1"
    # the checkout under test, whatever the installed copy points at
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    return env


def _cpu_children() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _run(args: list[str]) -> tuple[float, float]:
    """(wall, CPU) time in s of one ``python -m prbdm_pin ARGS`` process (which must succeed)."""
    c0, t0 = _cpu_children(), time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "prbdm_pin", *args], env=_env(), cwd=ROOT,
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall, cpu = time.perf_counter() - t0, _cpu_children() - c0
    if proc.returncode != 0:
        raise SystemExit(f"prbdm {' '.join(args)} failed ({proc.returncode}): {proc.stderr}")
    return wall, cpu


def _median(args: list[str], runs: int) -> tuple[float, float]:
    times = [_run(args) for _ in range(runs)]
    return statistics.median(t[0] for t in times), statistics.median(t[1] for t in times)


def fit_overhead(beam: str, starts: int, runs: int) -> tuple[float, float, float]:
    """(median wall, median fit wall_time_s, median overhead) in s of ``prbdm fit`` on a
    cached truth."""
    with tempfile.TemporaryDirectory() as tmp:
        cache, out = Path(tmp) / "cache", Path(tmp) / "fit"
        args = ["fit", beam, "--joints", "3", "--starts", str(starts), "--seed", "0",
                "--cache-dir", str(cache), "--out", str(out), "-q"]
        _run(args)  # computes and caches the truth
        walls, fits = [], []
        for _ in range(runs):
            walls.append(_run(args)[0])
            fits.append(float(json.loads((out / "fit.json").read_text())["wall_time_s"]))
    overheads = [w - f for w, f in zip(walls, fits, strict=True)]
    return statistics.median(walls), statistics.median(fits), statistics.median(overheads)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5, help="processes per figure (median)")
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_cli.md"))
    ap.add_argument("--beam", default="examples/beams/reference-random.json")
    ap.add_argument("--starts", type=int, default=8)
    ap.add_argument("--skip-fit", action="store_true", help="only the --help timings")
    a = ap.parse_args()

    # other processes inflate every wall time (and hide the fit's figure worker, which needs a
    # free core): the load is part of the result
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    rows = [("`prbdm --help`", *_median(["--help"], a.runs))]
    for cmd in COMMANDS:
        rows.append((f"`prbdm {cmd} --help`", *_median([cmd, "--help"], a.runs)))
    fit_line = "fit overhead: not measured (--skip-fit)."
    if not a.skip_fit:
        wall, fit_s, overhead = fit_overhead(a.beam, a.starts, a.runs)
        fit_line = (f"`prbdm fit {a.beam} --joints 3 --starts {a.starts}` on a cached truth: "
                    f"wall {wall:.3f} s, of which the fit {fit_s:.3f} s; CLI overhead "
                    f"{overhead:.3f} s (budget {FIT_OVERHEAD_BUDGET_S:.1f} s).")

    lines = [
        "# CLI start-up (scripts/bench_cli.py)",
        "",
        f"Python {platform.python_version()}, {platform.machine()}, {os.cpu_count()} cores; "
        f"median of {a.runs} processes, BLAS on one thread; load average {load:.2f} at the "
        "start.",
        "",
        "| command | wall (s) | CPU (s) | budget (s) |",
        "|---|---:|---:|---:|",
        *(f"| {name} | {w:.3f} | {c:.3f} | {HELP_BUDGET_S:.1f} |" for name, w, c in rows),
        "",
        fit_line,
        "",
    ]
    out = Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
