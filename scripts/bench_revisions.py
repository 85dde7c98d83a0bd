"""Nothing else gets slower: public calls and one-shot CLI commands timed at two revisions side by
side.

Every measurement runs in its own process with that revision's tree first on ``PYTHONPATH`` and
BLAS on one thread, interleaved (base, head, base, head, ...) so that the load of a shared
machine falls on both alike; each figure is the least CPU time over ``--repeats`` processes.
A call (``bench_revisions_calls.py``, the same file for both revisions) is timed warm, its first
call untimed; a CLI command (``python -m prbdm_pin ...``) is timed whole, the process's wall and
CPU time (user + system), after one untimed run per revision that computes the truth into the
revision's own temporary cache and compiles (or loads) what the revision compiles.

The simulations run the revision's default integrator (0dd6ba3: the exponential integrator;
later ``Auto()``); beside the cost each records its error, the largest tip deviation over the
run against scipy's DOP853 at rtol 1e-11 (run once, on the head tree), over the peak tip
excursion.

``--base`` is a tree (a folder holding ``prbdm_pin/``) or a git revision, checked out into a
temporary ``git worktree`` that is removed afterwards; ``--head`` the same, by default this
checkout. Writes a Markdown table to ``--out`` (default docs/benchmarks/bench_revisions.md).
A row whose head/base ratio exceeds ``SLOWER`` is flagged.

usage: python scripts/bench_revisions.py [--base 0dd6ba3] [--head PATH|REV] [--repeats 3]
                                         [--out FILE] [--only SUBSTRING]
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import platform
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
CALLS_SCRIPT = Path(__file__).resolve().parent / "bench_revisions_calls.py"
SLOWER = 1.1  # head/base above this is flagged
CALLS = (
    "build_model 5R",
    "frequencies 5R, one pose",
    "frequencies 5R, batch of 32 poses",
    "static_deflection 5R small load",
    "static_deflection 5R large load",
    "linearize 5R straight",
    "linearize 5R loaded",
    "evaluate 5R combined joint design",
    "fit 3R joint eigen, 4 starts",
    "simulate 5R step",
    "simulate 3R release",
    "simulate 5R step, exponential",
    "simulate 3R release, exponential",
    "export_model 5R URDF",
    "export_model 5R MJCF",
    "truth: plate modes (uniform-narrow)",
)
SIMULATIONS = ("simulate 5R step", "simulate 3R release", "simulate 5R step, exponential",
               "simulate 3R release, exponential")
FIT_ARGS = ("fit", "examples/beams/uniform-narrow.json", "--joints", "3", "--objective",
            "combined", "--stiffness", "joint", "--truth-model", "beam", "--starts", "4",
            "--seed", "0", "--workers", "1", "-q")
CLI = {  # label: arguments after ``python -m prbdm_pin``; {fit} is the fit's folder
    "prbdm --help": ("--help",),
    "prbdm fit (3R joint combined, beam truth, 4 starts)": FIT_ARGS,
    "prbdm fit (the same at the default 64 starts)": (*FIT_ARGS[:10], *FIT_ARGS[12:]),
    "prbdm simulate (3R fit, 1 s step load)": (
        "simulate", "{fit}/fit.json", "--duration", "1", "--tip-force", "0,0,-0.5", "-q"),
    "prbdm simulate --method exponential (the same)": (
        "simulate", "{fit}/fit.json", "--duration", "1", "--tip-force", "0,0,-0.5", "--method",
        "exponential", "-q"),
    "prbdm linearize (3R fit)": ("linearize", "{fit}/fit.json", "-q"),
    "prbdm statics (3R fit, -0.5 N tip force)": (
        "statics", "{fit}/fit.json", "--tip-force", "0,0,-0.5", "-q"),
    "prbdm export --format mjcf (3R fit)": (
        "export", "{fit}/fit.json", "--format", "mjcf", "-q"),
}


def env_for(tree: Path) -> dict[str, str]:
    env = dict(os.environ)
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        env[var] = "1"
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(tree), env.get("PYTHONPATH")]))
    return env


def children_cpu_s() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_call(tree: Path, call: str, tip: Path | None = None) -> dict:
    """One process of ``bench_revisions_calls.py CALL`` on ``tree``: its JSON record."""
    args = [sys.executable, str(CALLS_SCRIPT), call] + (["--tip", str(tip)] if tip else [])
    proc = subprocess.run(args, env=env_for(tree), cwd=tree, capture_output=True, text=True)
    if proc.returncode != 0 or not proc.stdout.strip():
        raise SystemExit(f"{call!r} on {tree} failed ({proc.returncode}): {proc.stderr[-2000:]}")
    record = json.loads(proc.stdout.strip().splitlines()[-1])
    if Path(record["prbdm_pin"]).resolve().parents[1] != tree.resolve():
        raise SystemExit(f"{call!r} imported {record['prbdm_pin']}, not the tree {tree}")
    return record


def run_cli(tree: Path, work: Path, args: tuple[str, ...], out: Path) -> tuple[float, float]:
    """(wall, CPU) s of one ``python -m prbdm_pin ARGS --out OUT`` on ``tree`` (must succeed)."""
    argv = [a.format(fit=work / "fit") for a in args]
    if argv != ["--help"]:
        argv += ["--cache-dir", str(work / "cache")] if argv[0] in ("fit", "simulate") else []
        argv += ["--out", str(out)]
    c0, t0 = children_cpu_s(), time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "prbdm_pin", *argv], env=env_for(tree),
                          cwd=tree, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall, cpu = time.perf_counter() - t0, children_cpu_s() - c0
    if proc.returncode != 0:
        raise SystemExit(f"prbdm {' '.join(argv)} on {tree} failed: {proc.stderr[-2000:]}")
    return wall, cpu


def out_path(work: Path, args: tuple[str, ...]) -> Path:
    """Where a timed command writes (never the fit folder the others read)."""
    return work / ("model.xml" if args[0] == "export" else f"out_{args[0].strip('-')}")


def tip_error(tip: np.ndarray, ref: np.ndarray) -> float:
    """Largest |tip - ref| over the samples over the reference's peak excursion from its start."""
    peak = np.linalg.norm(ref - ref[0], axis=1).max()
    return float(np.linalg.norm(tip - ref, axis=1).max() / peak)


@contextlib.contextmanager
def tree_of(spec: str):
    """A folder holding ``prbdm_pin/`` for ``spec``: the folder itself, or a temporary git
    worktree of the revision ``spec`` (removed on exit). Yields (tree, label)."""
    path = Path(spec)
    if (path / "prbdm_pin").is_dir():
        rev = subprocess.run(["git", "-C", str(path), "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(path), "status", "--porcelain"],
                               capture_output=True, text=True).stdout.strip()
        yield path.resolve(), (rev or path.name) + (" + changes" if dirty else "")
        return
    tmp = Path(tempfile.mkdtemp(prefix="bench_rev_tree_")) / "tree"
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(tmp), spec],
                   check=True, capture_output=True)
    try:
        rev = subprocess.run(["git", "-C", str(tmp), "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True, check=True).stdout.strip()
        yield tmp, rev
    finally:
        subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tmp)],
                       check=False, capture_output=True)
        shutil.rmtree(tmp.parent, ignore_errors=True)


def fmt_s(s: float) -> str:
    """A time with its unit, three significant figures."""
    for scale, unit in ((1.0, "s"), (1e-3, "ms"), (1e-6, "µs")):
        if s >= scale:
            return f"{s / scale:.3g} {unit}"
    return f"{s * 1e9:.3g} ns"


def ratio_cells(base: float, head: float) -> str:
    r = head / base
    return f"{r:.2f} | {'**slower**' if r > SLOWER else ''}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--base", default="0dd6ba3", help="a tree (folder) or a git revision")
    ap.add_argument("--head", default=str(ROOT), help="a tree (folder) or a git revision")
    ap.add_argument("--repeats", type=int, default=3, help="processes per figure (least CPU)")
    ap.add_argument("--out", default=str(ROOT / "docs" / "benchmarks" / "bench_revisions.md"))
    ap.add_argument("--only", default="", help="only the rows whose label contains this")
    a = ap.parse_args()
    # a kill (SIGTERM) unwinds like Ctrl-C, so a temporary worktree is removed
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))
    load0, c_start, t_start = os.getloadavg(), children_cpu_s(), time.perf_counter()
    with tree_of(a.base) as (base, base_rev), tree_of(a.head) as (head, head_rev), \
            tempfile.TemporaryDirectory() as tmp:
        trees = {"base": base, "head": head}
        calls, sims, cli = [], [], []
        for call in (c for c in CALLS if a.only in c):
            best = {"base": np.inf, "head": np.inf}
            methods, errors = {}, {}
            ref = None
            if call in SIMULATIONS:
                ref_tip = Path(tmp) / "ref.npy"
                run_call(head, f"reference {call.removesuffix(', exponential')}", ref_tip)
                ref = np.load(ref_tip)
            for _ in range(a.repeats):
                for side, tree in trees.items():
                    tip = Path(tmp) / f"{side}.npy" if ref is not None else None
                    record = run_call(tree, call, tip)
                    best[side] = min(best[side], record["cpu_s"])
                    if tip is not None:
                        methods[side] = record["method"]
                        errors[side] = tip_error(np.load(tip), ref)
            print(f"{call}: base {fmt_s(best['base'])}, head {fmt_s(best['head'])}", flush=True)
            calls.append((call, best["base"], best["head"]))
            if ref is not None:
                sims.append((call, methods, errors, best))
        cli_rows = [(k, v) for k, v in CLI.items() if a.only in k]
        if cli_rows:
            works = {side: Path(tmp) / side for side in trees}
            for side, tree in trees.items():  # untimed: truth cache, fit.json, compilation
                works[side].mkdir()
                run_cli(tree, works[side], FIT_ARGS, works[side] / "fit")
                for _, args in cli_rows:
                    if args[0] != "fit" and args[0] != "--help":
                        run_cli(tree, works[side], args, out_path(works[side], args))
            for label, args in cli_rows:
                best = {s: [np.inf, np.inf] for s in trees}
                for _ in range(a.repeats):
                    for side, tree in trees.items():
                        wall, cpu = run_cli(tree, works[side], args,
                                            out_path(works[side], args))
                        best[side] = [min(best[side][0], wall), min(best[side][1], cpu)]
                print(f"{label}: base {best['base']}, head {best['head']}", flush=True)
                cli.append((label, best["base"], best["head"]))
    load1 = os.getloadavg()
    lines = [
        "# Revisions side by side (scripts/bench_revisions.py)",
        "",
        f"Base `{base_rev}` against head `{head_rev}`; {platform.machine()}, "
        f"{os.cpu_count()} cores (shared), Python {platform.python_version()}; BLAS on one "
        f"thread; every figure the least CPU time over {a.repeats} processes, base and head "
        f"interleaved; load average {load0[0]:.2f} at the start, {load1[0]:.2f} at the end; "
        f"the whole run {children_cpu_s() - c_start:.0f} s of CPU in "
        f"{time.perf_counter() - t_start:.0f} s. Flagged: head more than {SLOWER:g}x base.",
        "",
    ]
    if calls:
        lines += [
            "## Public calls (CPU per call, warm)",
            "",
            "| call | base | head | head / base | |",
            "|---|---:|---:|---:|---|",
            *(f"| {c} | {fmt_s(b)} | {fmt_s(h)} | {ratio_cells(b, h)} |" for c, b, h in calls),
            "",
        ]
    if sims:
        lines += [
            "## The simulations: the integrator each ran and its error",
            "",
            "Error: the largest tip deviation over 1 s against DOP853 at rtol 1e-11, over the "
            "peak tip excursion.",
            "",
            "| call | base runs | base error | head runs | head error |",
            "|---|---|---:|---|---:|",
            *(f"| {c} | {m['base']} | {e['base']:.2g} | {m['head']} | {e['head']:.2g} |"
              for c, m, e, _ in sims),
            "",
        ]
    if cli:
        lines += [
            "## One-shot command line (the whole process)",
            "",
            "| command | base CPU | head CPU | head / base | | base wall | head wall |",
            "|---|---:|---:|---:|---|---:|---:|",
            *(f"| `{c}` | {fmt_s(b[1])} | {fmt_s(h[1])} | {ratio_cells(b[1], h[1])} | "
              f"{fmt_s(b[0])} | {fmt_s(h[0])} |" for c, b, h in cli),
            "",
        ]
    text = "\n".join(lines)
    out = Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    print(text)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
