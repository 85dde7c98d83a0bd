"""Probe cases for batch folders, batch-report, signals and worker processes, CSV and modes.

Broken or edited batch.json / results.jsonl (exit 2 naming the file and field), reports over
some shards of a study, resumes that lost batch.json, Ctrl-C / SIGTERM / SIGKILL on drivers with
worker pools, results.csv stability across resumes and the mode of every batch output file.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import warnings
from functools import cache
from pathlib import Path

from probe_cases._common import BEAMS, ROOT, expect_exit2, run_cli

RESULTS = "3 model and result files"
SILENT = "5 silent wrong answers"
SIGNALS = "7 signals and processes"
CSV_MODES = "8 CSV and file modes"

BEAM = BEAMS / "tapered.json"
# the cheapest real batch: 1D truth, 2-joint joint-stiffness fit of 2 starts
BATCH = ["--seed", "5", "--joints", "2", "--stiffness", "joint", "--starts", "2",
         "--truth-model", "beam", "--workers", "1"]
RUN_DEPENDENT = {"wall_s", "truth_s", "fit_s", "attempts", "worker_pid", "worker_peak_rss_mb"}


@cache
def _scratch() -> Path:
    return Path(tempfile.mkdtemp(prefix="probe-batch-"))


def _batch(out: Path, beams: int = 3, *extra: str) -> subprocess.CompletedProcess:
    return run_cli("batch", "--beams", beams, *BATCH, *extra, "--out", out, "-q")


def _main(*args) -> subprocess.CompletedProcess:
    """The CLI in this process (the cases that fail before any work: no interpreter start)."""
    from prbdm_pin.cli import main

    err = io.StringIO()
    with contextlib.redirect_stderr(err), warnings.catch_warnings():
        warnings.simplefilter("default")
        code = main([str(a) for a in args])
    return subprocess.CompletedProcess(args, code, "", err.getvalue())


@cache
def _base() -> Path:
    out = _scratch() / "base"
    p = _batch(out)
    assert p.returncode == 0, p.stderr[-300:]
    return out


@cache
def _shards() -> tuple[Path, ...]:
    dirs = []
    for i in range(3):
        d = _scratch() / f"shard-{i}"
        p = _batch(d, 9, "--shard", f"{i}/3")
        assert p.returncode == 0, p.stderr[-300:]
        dirs.append(d)
    return tuple(dirs)


_counter = [0]


def _copy(src: Path) -> Path:
    _counter[0] += 1
    return Path(shutil.copytree(src, _scratch() / f"case-{_counter[0]}"))


def _report(*dirs: Path | str) -> subprocess.CompletedProcess:
    return _main("batch-report", *dirs, "--no-plots", "-q")


def _run(d: Path, command: str) -> subprocess.CompletedProcess:
    if command == "report":
        return _report(d)
    return _main("batch", "--beams", 3, *BATCH, "--out", d, "-q")


# --- 3: batch.json and results.jsonl ---------------------------------------------------------
_MANIFESTS = {
    "empty": b"", "list": b"[]", "list of objects": b'[{"seed": 5}]', "string": b'"batch"',
    "null": b"null", "number": b"5", "seed string": b'{"seed": "five"}',
    "seed negative": b'{"seed": -1}', "settings list": b'{"settings": [2]}',
    "settings joints string": b'{"settings": {"joints": "two"}}',
    "shard short": b'{"shard": [0]}', "shard out of range": b'{"shard": [3, 3]}',
    "shard strings": b'{"shard": ["0", "1"]}', "n_beams string": b'{"n_beams": "3"}',
    "beams not pairs": b'{"beams": [1, 2]}', "not utf-8": b'{"seed": 5, "source": "\xff"}',
    "NaN": b'{"seed": NaN}', "deep": b"[" * 10000, "huge int": b'{"seed": 1' + b"0" * 500 + b"}",
}


def _manifest_case(content: bytes, command: str):
    def fn():
        d = _copy(_base())
        (d / "batch.json").write_bytes(content)
        expect_exit2(_run(d, command), "batch.json")
    return fn


def _truncated_manifest(frac: float, command: str):
    def fn():
        d = _copy(_base())
        text = (d / "batch.json").read_bytes()
        (d / "batch.json").write_bytes(text[:int(len(text) * frac)])
        expect_exit2(_run(d, command), "batch.json")
    return fn


def _edit_line(edit, field: str, command: str):
    def fn():
        d = _copy(_base())
        path = d / "results.jsonl"
        lines = path.read_bytes().splitlines()
        lines[1] = edit(lines[1])
        path.write_bytes(b"\n".join(lines) + b"\n")
        p = _run(d, command)
        expect_exit2(p, field)
        assert "line 2" in p.stderr, f"the line is not named: {p.stderr.strip()!r}"
    return fn


def _set(field: str, value):
    def edit(raw: bytes) -> bytes:
        rec = json.loads(raw)
        rec[field] = value
        return json.dumps(rec).encode()
    return edit


_STRING_FIELDS = ["eigen_loss_pct", "worst_mode_error_pct", "worst_export_error_pct",
                  "taper_ratio", "mean_width_m", "scf_mean", "gamma_1", "mass_kg", "length_m",
                  "fit_seed", "nfev"]
_BAD_LINES = {
    "not utf-8": (lambda raw: raw[:-1] + b', "x": "\xff\xfe"}', "results.jsonl"),
    "NaN": (lambda raw: raw[:-1] + b', "mass_kg": NaN}', "results.jsonl"),
    "Infinity": (lambda raw: raw[:-1] + b', "mass_kg": Infinity}', "results.jsonl"),
    "deep": (lambda raw: b"[" * 5000, "results.jsonl"),
    "huge int": (lambda raw: raw[:-1] + b', "nfev": 1' + b"0" * 400 + b"}", "results.jsonl"),
    "not an object": (lambda raw: b"[1, 2]", "results.jsonl"),
    "no beam_index": (lambda raw: b'{"status": "ok"}', "beam_index"),
    "beam_index string": (_set("beam_index", "1"), "beam_index"),
    "beam_index negative": (_set("beam_index", -1), "beam_index"),
    "beam_index bool": (_set("beam_index", True), "beam_index"),
    "gamma strings": (_set("gamma", ["a", "b", "c"]), "gamma"),
    "gamma scalar": (_set("gamma", 0.5), "gamma"),
    "lengths_m nested": (_set("lengths_m", [[0.1], [0.2]]), "lengths_m"),
    "status number": (_set("status", 1), "status"),
    "error list": (_set("error", ["x"]), "error"),
    "seed string": (_set("seed", "5"), "seed"),
}


def _result_cases() -> list:
    out = [(RESULTS, f"batch-report: batch.json {name}", _manifest_case(content, "report"))
           for name, content in _MANIFESTS.items()]
    out += [(RESULTS, f"batch resume: batch.json {name}",
             _manifest_case(_MANIFESTS[name], "resume"))
            for name in ("list", "string", "settings list", "not utf-8", "NaN")]
    out += [(RESULTS, f"batch-report: batch.json cut at {frac:.0%}",
             _truncated_manifest(frac, "report")) for frac in (0.1, 0.3, 0.5, 0.7, 0.9, 0.99)]
    out.append((RESULTS, "batch resume: batch.json cut at 50%",
                _truncated_manifest(0.5, "resume")))
    out += [(RESULTS, f"batch-report: results.jsonl {field} a string",
             _edit_line(_set(field, "0.5"), field, "report")) for field in _STRING_FIELDS]
    out += [(RESULTS, f"batch-report: results.jsonl line {name}",
             _edit_line(edit, field, "report")) for name, (edit, field) in _BAD_LINES.items()]
    for name in ("not utf-8", "NaN", "gamma strings", "beam_index string"):
        edit, field = _BAD_LINES[name]
        out.append((RESULTS, f"batch resume: results.jsonl line {name}",
                    _edit_line(edit, field, "resume")))
    return out


# --- 5: shards, resumes without batch.json, fingerprints ---------------------------------------
def _missing_shards(given: tuple[int, ...]):
    def fn():
        dirs = _shards()
        rep = _scratch() / f"report-{'-'.join(map(str, given))}"
        p = _main("batch-report", *(dirs[i] for i in given), "--no-plots", "-q", "--out", rep)
        assert p.returncode == 0, p.stderr[-300:]
        missing = [i for i in range(3) if i not in given]
        err = [ln for ln in p.stderr.splitlines() if ln.strip()]
        md = (rep / "report.md").read_text()
        if not missing:
            assert not err, f"a warning over every shard: {err}"
            assert "not given" not in md
            return
        assert len(err) == 1, f"expected one warning line, got {err}"
        for i in missing:
            assert f"{i}/3" in err[0], f"shard {i}/3 not named: {err[0]!r}"
            assert f"{i}/3" in md, "the report does not say which shards are missing"
        assert "9" in err[0], f"the study's size is not given: {err[0]!r}"
    return fn


def _different_counts():
    d = _scratch() / "half-0"
    if not d.exists():
        assert _batch(d, 9, "--shard", "0/2").returncode == 0
    expect_exit2(_report(_shards()[0], d), "shard")


def _resume_without_manifest(option: list[str], named: str, old_records: bool = False):
    def fn():
        d = _copy(_base())
        (d / "batch.json").unlink()
        if old_records:  # records written before they carried their arguments
            path = d / "results.jsonl"
            recs = [json.loads(x) for x in path.read_text().splitlines()]
            for r in recs:
                for k in ("joints", "objective", "stiffness", "starts", "truth_model",
                          "min_fraction"):
                    r.pop(k, None)
            path.write_text("".join(json.dumps(r) + "\n" for r in recs))
        args = list(BATCH)
        for i in range(0, len(option), 2):
            if option[i] in args:
                args[args.index(option[i]) + 1] = option[i + 1]
            else:
                args += option[i:i + 2]
        p = _main("batch", "--beams", 3, *args, "--out", d, "-q")
        if not named:
            assert p.returncode == 0, f"same arguments refused: {p.stderr[-300:]!r}"
            return
        expect_exit2(p, named)
        assert not (d / "batch.json").exists(), "a batch.json contradicting the records"
    return fn


def _edited_fit_beam():
    out = _scratch() / "fit-edited"
    p = run_cli("fit", BEAM, "--joints", 2, "--stiffness", "joint", "--starts", 2,
                "--truth-model", "beam", "--out", out, "-q")
    assert p.returncode == 0, p.stderr[-300:]
    d = json.loads((out / "fit.json").read_text())
    d["beam"]["thickness"] *= 1.5
    (out / "fit.json").write_text(json.dumps(d))
    p = run_cli("simulate", out / "fit.json", "--duration", 0.01, "--out", out / "sim", "-q")
    expect_exit2(p, "beam_fingerprint")
    assert "None" not in p.stderr, p.stderr


def _silent_cases() -> list:
    out = [(SILENT, f"batch-report over shards {given} of 3", _missing_shards(given))
           for given in ((0, 1), (0, 2), (1, 2), (0,), (2,), (0, 1, 2))]
    out.append((SILENT, "batch-report over shards of different counts", _different_counts))
    for option, named in ((["--joints", "3"], "--joints"), (["--starts", "3"], "--starts"),
                          (["--stiffness", "paper"], "--stiffness"),
                          (["--eigen-norm", "paper"], "--eigen-norm"),
                          (["--truth-model", "plate"], "--truth-model"),
                          (["--min-link", "0.05"], "--min-link"), (["--seed", "6"], "--seed"),
                          (["--frequencies", "1"], "--frequencies"),
                          (["--joints", "3", "--frequencies", "2"], "--joints")):
        out.append((SILENT, f"resume without batch.json, {' '.join(option)}",
                    _resume_without_manifest(option, named)))
    out.append((SILENT, "resume without batch.json, old records, --joints 3",
                _resume_without_manifest(["--joints", "3", "--frequencies", "2"], "--joints",
                                         old_records=True)))
    out.append((SILENT, "resume without batch.json, same arguments (resumes)",
                _resume_without_manifest([], "")))
    out.append((SILENT, "simulate: fit.json with an edited beam", _edited_fit_beam))
    return out


# --- 7: signals and processes -----------------------------------------------------------------
def _popen(args: list) -> subprocess.Popen:
    env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
    # a session of its own: a signal to the group is Ctrl-C in a terminal
    return subprocess.Popen([sys.executable, "-m", "prbdm_pin.cli", *map(str, args), "-q"],
                            cwd=ROOT, env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)


def _stat(pid: int) -> list[str]:
    return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()


def _children(pid: int) -> list[int]:
    # every descendant, from /proc (no psutil needed)
    kids: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                kids.setdefault(int(_stat(int(entry.name))[1]), []).append(int(entry.name))
            except (OSError, IndexError, ValueError):
                continue
    out, todo = [], [pid]
    while todo:
        for k in kids.get(todo.pop(), []):
            out.append(k)
            todo.append(k)
    return out


def _running(pids: list[int]) -> list[int]:
    alive = []
    for pid in pids:
        try:
            if _stat(pid)[0] != "Z":
                alive.append(pid)
        except (OSError, IndexError):
            continue
    return alive


def _cpu_s(pids: list[int]) -> float:
    total = 0.0
    for pid in pids:
        try:
            f = _stat(pid)
            total += (int(f[11]) + int(f[12])) / os.sysconf("SC_CLK_TCK")
        except (OSError, IndexError, ValueError):
            pass
    return total


def _wait_busy(proc: subprocess.Popen, n: int, until=None) -> list[int]:
    t0 = time.monotonic()
    while time.monotonic() - t0 < 90:
        assert proc.poll() is None, f"ended early: {proc.stderr.read()[-300:]!r}"
        kids = _children(proc.pid)
        if len(kids) >= n and _cpu_s(kids) > 1.0 and (until is None or until()):
            return kids
        time.sleep(0.1)
    raise AssertionError("the workers never started")


def _reap(proc: subprocess.Popen, kids: list[int], limit_s: float) -> tuple[str, list[int]]:
    """Wait for the driver, then up to 5 s for its descendants; returns stderr and the
    descendants still alive (killed now); ``proc.exit_s`` is when the driver ended."""
    try:
        proc.wait(limit_s + 60)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    proc.exit_s = time.monotonic()
    deadline = time.monotonic() + 5
    while _running(kids) and time.monotonic() < deadline:
        time.sleep(0.05)
    left = _running(kids)
    for pid in left:  # leave nothing behind for the next case
        os.kill(pid, signal.SIGKILL)
    err = proc.stderr.read()
    proc.stderr.close()
    return err, left


def _pool_args(command: str, out: Path, beams: int = 8) -> list:
    if command == "fit":
        return ["fit", BEAM, "--joints", 2, "--truth-model", "beam", "--workers", 2,
                "--starts", 800, "--out", out]
    if command == "pareto":
        return ["pareto", BEAM, "--joints", 2, "--truth-model", "beam", "--workers", 2,
                "--pop", 40, "--generations", 100000, "--out", out]
    return ["batch", "--beams", beams, "--seed", 5, "--joints", 2, "--stiffness", "joint",
            "--starts", 16, "--truth-model", "beam", "--workers", 2, "--out", out]


def _interrupt(command: str, sig: int, group: bool):
    def fn():
        out = _scratch() / f"sig-{command}-{int(sig)}-{group}"
        args = _pool_args(command, out)
        proc = _popen(args)
        jsonl = out / "results.jsonl"
        kids = _wait_busy(proc, 2, (lambda: jsonl.exists() and jsonl.stat().st_size > 0)
                          if command == "batch" else None)
        t0 = time.monotonic()
        (os.killpg if group else os.kill)(proc.pid, sig)
        err, left = _reap(proc, kids, 3.0)
        elapsed = proc.exit_s - t0
        assert proc.returncode == 130, f"exit {proc.returncode}: {err[-300:]!r}"
        assert elapsed < 3.0, f"exited {elapsed:.1f} s after the signal"
        assert "Traceback" not in err, f"traceback: {err[-300:]!r}"
        assert not left, f"{len(left)} processes outlived the driver"
        if command == "fit":
            assert not (out / "fit.json").exists(), "a fit.json after Ctrl-C"
        if command == "batch":
            kept = [json.loads(x)["beam_index"] for x in jsonl.read_text().splitlines()]
            assert kept, "the finished records were lost"
            p = run_cli(*map(str, args), "-q")
            assert p.returncode == 0, f"resume failed: {p.stderr[-300:]!r}"
            final = [json.loads(x)["beam_index"] for x in jsonl.read_text().splitlines()]
            assert final[:len(kept)] == kept and sorted(final) == list(range(8)), final
    return fn


def _killed_driver(command: str):
    def fn():
        proc = _popen(_pool_args(command, _scratch() / f"kill-{command}", beams=200))
        kids = _wait_busy(proc, 2)
        os.kill(proc.pid, signal.SIGKILL)
        _, left = _reap(proc, kids, 10.0)
        assert not left, f"{len(left)} of {len(kids)} processes outlived the killed driver"
    return fn


def _signal_cases() -> list:
    if not sys.platform.startswith("linux"):
        return []
    return [
        (SIGNALS, "fit --workers 2: Ctrl-C (process group)",
         _interrupt("fit", signal.SIGINT, True)),
        (SIGNALS, "fit --workers 2: SIGINT to the driver only",
         _interrupt("fit", signal.SIGINT, False)),
        (SIGNALS, "pareto --workers 2: Ctrl-C", _interrupt("pareto", signal.SIGINT, True)),
        (SIGNALS, "batch --workers 2: Ctrl-C, then resume",
         _interrupt("batch", signal.SIGINT, True)),
        (SIGNALS, "batch --workers 2: SIGTERM, then resume",
         _interrupt("batch", signal.SIGTERM, False)),
        (SIGNALS, "batch driver SIGKILLed: workers and tracker end", _killed_driver("batch")),
        (SIGNALS, "fit driver SIGKILLed: workers end", _killed_driver("fit")),
    ]


# --- 8: CSV and file modes ----------------------------------------------------------------------
def _csv_resume_nothing():
    d = _copy(_base())
    before = (d / "results.csv").read_bytes()
    assert _batch(d).returncode == 0
    assert (d / "results.csv").read_bytes() == before, \
        "results.csv rewritten differently by a resume with nothing to do"


def _csv_no_nan():
    text = (_base() / "results.csv").read_text()
    cells = [c.lower() for row in csv.reader(io.StringIO(text)) for c in row]
    assert "nan" not in cells, "NaN written as 'nan' (blank once loaded on resume)"


def _stable_part(text: str) -> list[list[str]]:
    rows = list(csv.reader(io.StringIO(text)))
    keep = [i for i, h in enumerate(rows[0]) if h not in RUN_DEPENDENT]
    return [[r[i] for i in keep] for r in rows]


def _csv_half_resume():
    d = _copy(_base())
    path = d / "results.jsonl"
    lines = path.read_bytes().splitlines(keepends=True)
    path.write_bytes(lines[0] + lines[1][:20])  # the second line torn mid-write
    assert _batch(d).returncode == 0
    a = _stable_part((d / "results.csv").read_text())
    b = _stable_part((_base() / "results.csv").read_text())
    assert a == b, "a resume that did half the work wrote other cells than a whole run"


def _modes(umask: int):
    def fn():
        out = _scratch() / f"umask-{umask:o}"
        cmd = [sys.executable, "-m", "prbdm_pin.cli"]
        for args in (["batch", "--beams", "2", *BATCH, "--out", str(out), "-q"],
                     ["batch-report", str(out), "--no-plots", "-q"]):
            p = subprocess.run([*cmd, *args], cwd=ROOT, capture_output=True, text=True,
                               preexec_fn=lambda: os.umask(umask))
            assert p.returncode == 0, p.stderr[-300:]
        want = oct(0o666 & ~umask)
        files = ["batch.json", "results.jsonl", "results.csv", "report/report.md"]
        got = {f: oct((out / f).stat().st_mode & 0o777) for f in files}
        bad = {f: m for f, m in got.items() if m != want}
        assert not bad, f"modes {bad}, expected {want} for every file"
    return fn


def _csv_cases() -> list:
    return [
        (CSV_MODES, "results.csv byte-identical after a resume with nothing to do",
         _csv_resume_nothing),
        (CSV_MODES, "results.csv has no 'nan' cells", _csv_no_nan),
        (CSV_MODES, "results.csv of a half-done resume equals a whole run (stable columns)",
         _csv_half_resume),
        *[(CSV_MODES, f"batch output modes under umask {m:03o}", _modes(m))
          for m in (0o022, 0o077, 0o002)],
    ]


def cases() -> list:
    """Every batch, report, signal and CSV case: ``(category, name, fn)``."""
    return _result_cases() + _silent_cases() + _signal_cases() + _csv_cases()
