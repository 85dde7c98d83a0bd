"""CLI options: bad --out / --cache-dir paths in every subcommand, numbers out of range, work
without bound (a picosecond output step, 1000 joints), and argparse's own errors.

Each case wants exit 2 with one line naming the option, refused before any work: no truth in
the (fresh) cache folder and no output folder created. To keep the run short, the command lines
go through ``prbdm_pin.cli.main`` in one child process (a case that kills it fails with the rest
of the batch); a few run as ``python -m prbdm_pin.cli`` of their own as well.
"""

from __future__ import annotations

import functools
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from ._common import BEAMS, ROOT, expect_exit2, run_cli

BEAM = str(BEAMS / "uniform-narrow.json")
TIMEOUT_S = 90

# Runs each [argv, env] of stdin's JSON list through main() and prints [rc, stderr] per case.
_DRIVER = r"""
import contextlib, io, json, os, sys, traceback
from prbdm_pin.cli import main
out = []
for argv, env in json.load(sys.stdin):
    saved = {k: os.environ.get(k) for k in env}
    os.environ.update(env)
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            rc = main(argv)
        except SystemExit as exc:
            rc = exc.code
        except BaseException:
            traceback.print_exc()
            rc = -1
    for k, v in saved.items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v
    out.append([rc, err.getvalue()])
print(json.dumps(out))
"""


@functools.lru_cache(maxsize=1)
def _scratch() -> Path:
    d = Path(tempfile.mkdtemp(prefix="prbdm-options-"))
    (d / "afile").write_text("a file, not a folder\n")
    return d


@functools.lru_cache(maxsize=1)
def _fit_json() -> Path:
    """A 2R fit against the 1D beam truth (seconds), for simulate and export."""
    out = _scratch() / "fit"
    proc = run_cli("fit", BEAM, "--joints", "2", "--stiffness", "joint", "--starts", "2",
                   "--truth-model", "beam", "--cache-dir", _scratch() / "fit-cache",
                   "--out", out, "-q", timeout=300)
    assert proc.returncode == 0, f"the 2R fit failed: {proc.stderr[-300:]!r}"
    return out / "fit.json"


def _fresh(name: str) -> Path:
    return _scratch() / "fresh" / name


FIT = "<fit.json>"  # replaced by the fit's path when the batch runs
_SPECS: list[tuple[list, dict]] = []


@functools.lru_cache(maxsize=1)
def _results() -> list:
    """[rc, stderr] of every registered command line, from one child process."""
    fit = str(_fit_json())
    specs = [([fit if a == FIT else str(a) for a in argv], env) for argv, env in _SPECS]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])}
    proc = subprocess.run([sys.executable, "-c", _DRIVER], input=json.dumps(specs),
                          capture_output=True, text=True, timeout=40 * TIMEOUT_S, cwd=ROOT,
                          env=env)
    assert proc.returncode == 0, f"the driver died: {proc.stderr[-300:]!r}"
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _refused(args: list, field: str, fresh: list[Path] = (), cache: Path | None = None,
             env: dict | None = None):
    index = len(_SPECS)
    _SPECS.append((list(args), dict(env or {})))

    def case():
        rc, err = _results()[index]
        expect_exit2(subprocess.CompletedProcess(args, rc, "", err), field)
        for p in fresh:
            assert not p.exists(), f"{p} was created before the refusal"
        if cache is not None and cache.exists():
            assert not any(cache.iterdir()), "a truth was computed before the refusal"
    return case


def _own_process(args: list, field: str, fresh: list[Path] = ()):
    """The same check through ``python -m prbdm_pin.cli`` in a process of its own."""
    def case():
        proc = run_cli(*[str(_fit_json()) if a == FIT else a for a in args], timeout=TIMEOUT_S)
        expect_exit2(proc, field)
        for p in fresh:
            assert not p.exists(), f"{p} was created before the refusal"
    return case


def _bad_dirs() -> list[tuple[str, str]]:
    s = _scratch()
    return [("a file", str(s / "afile")), ("under a file", str(s / "afile" / "x")),
            ("/proc", "/proc/prbdm-probe"), ("/sys", "/sys/prbdm-probe"),
            ("/dev", "/dev/prbdm-probe"), ("empty", "")]


def _path_cases() -> list:
    cat = "2 out/cache-dir paths"
    out = []
    s = _scratch()
    for label, bad in _bad_dirs():
        cache = _fresh(f"cache-{label}")
        for cmd in ("fit", "pareto"):
            out.append((cat, f"{cmd} --out {label}", _refused(
                [cmd, BEAM, "--joints", "2", "--truth-model", "beam", "--cache-dir", cache,
                 "--out", bad, "-q"], "--out", cache=cache)))
        out.append((cat, f"truth --out {label}", _refused(
            ["truth", BEAM, "--model", "beam", "--out", bad, "-q"], "--out")))
        out.append((cat, f"batch --out {label}", _refused(
            ["batch", "--beams", "1", "--joints", "2", "--truth-model", "beam", "--out", bad,
             "-q"], "--out")))
        out.append((cat, f"bench --out {label}", _refused(
            ["bench", "--quick", "--out", bad, "-q"], "--out")))
        out.append((cat, f"batch-report --out {label}", _refused(
            ["batch-report", str(s), "--out", bad, "-q"], "--out")))
        out.append((cat, f"simulate --out {label}", _refused(
            ["simulate", FIT, "--duration", "0.01", "--out", bad, "-q"], "--out")))
    for label, bad in _bad_dirs()[:4]:
        fresh = _fresh(f"out-cache-{label}")
        for cmd in ("fit", "pareto"):
            out.append((cat, f"{cmd} --cache-dir {label}", _refused(
                [cmd, BEAM, "--joints", "2", "--truth-model", "beam", "--cache-dir", bad,
                 "--out", fresh, "-q"], "--cache-dir", [fresh])))
        out.append((cat, f"batch --cache-dir {label}", _refused(
            ["batch", "--beams", "1", "--joints", "2", "--truth-model", "beam",
             "--cache-dir", bad, "--out", fresh, "-q"], "--cache-dir", [fresh])))
        out.append((cat, f"bench --cache-dir {label}", _refused(
            ["bench", "--quick", "--cache-dir", bad, "--out", fresh, "-q"], "--cache-dir",
            [fresh])))
        out.append((cat, f"simulate --compare-truth --cache-dir {label}", _refused(
            ["simulate", FIT, "--duration", "0.01", "--compare-truth", "--truth-model", "beam",
             "--cache-dir", bad, "--out", fresh, "-q"], "--cache-dir", [fresh])))
    fresh = _fresh("env-cache")
    out.append((cat, "fit with PRBDM_CACHE a file", _refused(
        ["fit", BEAM, "--joints", "2", "--truth-model", "beam", "--out", fresh, "-q"],
        "PRBDM_CACHE", [fresh], env={"PRBDM_CACHE": str(s / "afile")})))
    for label, bad in [("a folder", str(s)), ("trailing slash", str(s / "new") + "/"),
                       ("under a file", str(s / "afile" / "m.urdf")),
                       ("/proc", "/proc/m.urdf"), ("/sys", "/sys/m.urdf"),
                       ("/dev/null", "/dev/null")]:
        out.append((cat, f"export --out {label}", _refused(
            ["export", FIT, "--format", "urdf", "--out", bad, "-q"], "--out")))
    out.append((cat, "export --out MODEL itself", _refused(
        ["export", FIT, "--format", "json", "--out", FIT, "-q"], "--out")))
    fresh = _fresh("beams-dir")
    out.append((cat, "batch --beams-dir missing: --out not created", _refused(
        ["batch", "--beams-dir", str(s / "none"), "--joints", "2", "--out", fresh, "-q"],
        "--beams-dir", [fresh])))
    out.append((cat, "batch-report DIR missing", _refused(
        ["batch-report", str(s / "none")], "DIR")))
    # end to end, in processes of their own
    out.append((cat, "own process: fit --out a file", _own_process(
        ["fit", BEAM, "--joints", "2", "--truth-model", "beam", "--out", str(s / "afile")],
        "--out")))
    out.append((cat, "own process: export --out a folder", _own_process(
        ["export", FIT, "--format", "mjcf", "--out", str(s)], "--out")))
    return out


FIT_NUMBERS = [
    ("--joints", "0"), ("--joints", "-1"), ("--frequencies", "0"), ("--frequencies", "3"),
    ("--mesh-level", "7"), ("--xi", "nan"), ("--xi", "-0.1"), ("--xi", "1"), ("--eps", "0"),
    ("--eps", "nan"), ("--seed", "-1"), ("--seed", str(2**64)), ("--extra-loads", "0"),
    ("--extra-loads", "2,inf"),
]


def _number_cases() -> list:
    cat = "5 silent wrong answers"
    out = []
    for cmd in ("fit", "pareto"):
        for opt, value in FIT_NUMBERS:
            cache, fresh = _fresh(f"c-{cmd}{opt}{value}"), _fresh(f"o-{cmd}{opt}{value}")
            argv = [cmd, BEAM, "--truth-model", "beam", "--cache-dir", cache, "--out", fresh,
                    "-q", opt, value] + ([] if opt == "--joints" else ["--joints", "2"])
            out.append((cat, f"{cmd} {opt} {value}", _refused(argv, opt, [fresh], cache)))
    for cmd, opt, value in [("fit", "--loss-tol", "nan"), ("fit", "--loss-tol", "-1"),
                            ("fit", "--loss-tol", "inf"), ("fit", "--starts", "0"),
                            ("fit", "--workers", "0"), ("pareto", "--pop", "1"),
                            ("pareto", "--pop", "3"), ("pareto", "--generations", "0"),
                            ("pareto", "--workers", "-1")]:
        cache, fresh = _fresh(f"c-{cmd}{opt}{value}"), _fresh(f"o-{cmd}{opt}{value}")
        out.append((cat, f"{cmd} {opt} {value}", _refused(
            [cmd, BEAM, "--joints", "2", "--truth-model", "beam", "--cache-dir", cache,
             "--out", fresh, "-q", opt, value], opt, [fresh], cache)))
    for opt, value in [("--damping", "1.5"), ("--damping", "1"), ("--damping", "-0.1"),
                       ("--damping", "nan"), ("--dt", "-1"), ("--dt", "1"),
                       ("--output-dt", "0"), ("--output-dt", "1"), ("--initial-angle", "inf"),
                       ("--initial-angle", "100"), ("--method", "euler")]:
        fresh = _fresh(f"sim{opt}{value}")
        out.append((cat, f"simulate {opt} {value}", _refused(
            ["simulate", FIT, "--duration", "0.05", "--out", fresh, "-q", opt, value], opt,
            [fresh])))
    for value in ("1.5", "-0.1", "nan"):
        m = _fresh(f"m{value}.urdf")
        out.append((cat, f"export --damping {value}", _refused(
            ["export", FIT, "--format", "urdf", "--damping", value, "--out", m, "-q"],
            "--damping", [m])))
    for opt, value in [("--modes", "0"), ("--mesh", "9"), ("--mesh", "-1"),
                       ("--error-tol", "0"), ("--error-tol", "nan")]:
        fresh = _fresh(f"truth{opt}{value}")
        out.append((cat, f"truth {opt} {value}", _refused(
            ["truth", BEAM, "--model", "beam", "--out", fresh, "-q", opt, value], opt,
            [fresh])))
    for opt, value in [("--beams", "0"), ("--joints", "0"), ("--frequencies", "3"),
                       ("--seed", "-1"), ("--workers", "0"), ("--shard", "3/2"),
                       ("--shard", "x"), ("--starts", "0")]:
        fresh = _fresh(f"batch{opt}{value}")
        argv = ["batch", "--truth-model", "beam", "--out", fresh, "-q", opt, value]
        argv += [] if opt == "--beams" else ["--beams", "2"]
        argv += [] if opt == "--joints" else ["--joints", "2"]
        out.append((cat, f"batch {opt} {value}", _refused(argv, opt, [fresh])))
    # argparse's own errors: one line as well
    for name, argv, field in [
        ("fit --joints abc", ["fit", BEAM, "--joints", "abc", "--out", "o"], "--joints"),
        ("fit without --joints", ["fit", BEAM, "--out", "o"], "--joints"),
        ("pareto unknown option", ["pareto", BEAM, "--joints", "2", "--out", "o", "--bogus"],
         "--bogus"),
        ("export --format pdf", ["export", "m.json", "--format", "pdf", "--out", "o"],
         "--format"),
        ("simulate --damping-form x", ["simulate", "m.json", "--duration", "1", "--out", "o",
                                       "--damping-form", "x"], "--damping-form"),
    ]:
        out.append((cat, f"argparse: {name}", _refused(argv, field)))
    out.append((cat, "own process: pareto --pop 1", _own_process(
        ["pareto", BEAM, "--joints", "2", "--truth-model", "beam", "--pop", "1", "--out",
         str(_fresh("own-pop"))], "--pop", [_fresh("own-pop")])))
    out.append((cat, "own process: argparse error", _own_process(
        ["truth", BEAM, "--modes", "x", "--out", "o"], "--modes")))
    return out


def _unbounded_cases() -> list:
    cat = "4 unbounded work"
    out = []
    for value in ("1e-12", "1e-8"):
        fresh = _fresh(f"sim{value}")
        out.append((cat, f"simulate --output-dt {value}", _refused(
            ["simulate", FIT, "--duration", "0.05", "--out", fresh, "-q", "--output-dt", value],
            "max_output_samples", [fresh])))
    for cmd, opt, value in [("fit", "--joints", "1000"), ("pareto", "--joints", "1000"),
                            ("fit", "--joints", "65"), ("fit", "--eps", "1e-9"),
                            ("pareto", "--eps", "1e-7"), ("fit", "--starts", "1000000000"),
                            ("pareto", "--pop", "1000000000"),
                            ("pareto", "--generations", "1000000000000")]:
        cache, fresh = _fresh(f"c-{cmd}{opt}{value}"), _fresh(f"o-{cmd}{opt}{value}")
        argv = [cmd, BEAM, "--truth-model", "beam", "--cache-dir", cache, "--out", fresh,
                "-q", opt, value] + ([] if opt == "--joints" else ["--joints", "2"])
        out.append((cat, f"{cmd} {opt} {value}", _refused(argv, opt, [fresh], cache)))
    fresh = _fresh("batch-joints")
    out.append((cat, "batch --joints 1000", _refused(
        ["batch", "--beams", "1", "--joints", "1000", "--out", fresh, "-q"], "--joints",
        [fresh])))
    out.append((cat, "batch --beams 10**12 in one shard", _refused(
        ["batch", "--beams", str(10**12), "--joints", "2", "--out", fresh, "-q"], "--beams",
        [fresh])))
    out.append((cat, "truth --modes 1000", _refused(
        ["truth", BEAM, "--model", "beam", "--modes", "1000", "--out", fresh, "-q"],
        "--modes", [fresh])))
    out.append((cat, "own process: simulate --output-dt 1e-12", _own_process(
        ["simulate", FIT, "--duration", "0.05", "--output-dt", "1e-12", "--out",
         str(_fresh("own-sim"))], "max_output_samples", [_fresh("own-sim")])))
    return out


def cases() -> list:
    """(category, name, fn) of every option case."""
    _SPECS.clear()
    _results.cache_clear()
    return _path_cases() + _unbounded_cases() + _number_cases()
