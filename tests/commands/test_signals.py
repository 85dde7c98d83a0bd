"""Ctrl-C and a killed driver, on real CLI processes with worker pools.

Ctrl-C (SIGINT to the process group, as a terminal sends it) must cancel the queued work at
once: exit 130 within a few seconds, no traceback, no fit written, no process left behind; a
batch keeps the records written so far and resumes. A SIGKILLed driver must take its workers
(and the resource tracker) down with it.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from paths import ROOT
from terminal_signals import sigint_default

psutil = pytest.importorskip("psutil")

BEAM = ROOT / "examples" / "beams" / "tapered.json"
pytestmark = pytest.mark.skipif(os.name != "posix", reason="POSIX signals and process groups")


def _start(args: list[str], tmp_path: Path) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OMP_NUM_THREADS": "1",
           "OPENBLAS_NUM_THREADS": "1", "PRBDM_CACHE": str(tmp_path / "cache")}
    # a session of its own: SIGINT goes to the whole group, like Ctrl-C in a terminal
    return subprocess.Popen([sys.executable, "-m", "prbdm_pin.cli", *args, "-q"], cwd=ROOT,
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, preexec_fn=sigint_default)


def _busy_children(proc: subprocess.Popen, n: int, timeout_s: float = 60.0) -> list:
    """Wait until ``proc`` has ``n`` pool workers and they have computed for a while."""
    parent = psutil.Process(proc.pid)
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout_s:
        assert proc.poll() is None, f"exited early ({proc.returncode}): {proc.stderr.read()}"
        kids = parent.children(recursive=True)
        workers = [k for k in kids if "spawn_main" in " ".join(_cmdline(k))
                   or _cmdline(k) == _cmdline(parent)]
        if len(workers) >= n and sum(_cpu_s(k) for k in workers) > 1.0:
            return kids
        time.sleep(0.1)
    raise AssertionError(f"no {n} busy workers after {timeout_s} s")


def _cmdline(p) -> list[str]:
    try:
        return p.cmdline()
    except psutil.Error:
        return []


def _cpu_s(p) -> float:
    try:
        t = p.cpu_times()
    except psutil.Error:
        return 0.0
    return t.user + t.system


def _alive(procs: list) -> list[int]:
    out = []
    for p in procs:
        try:
            if p.is_running() and p.status() != psutil.STATUS_ZOMBIE:
                out.append(p.pid)
        except psutil.NoSuchProcess:
            pass
    return out


def _wait_gone(procs: list, timeout_s: float) -> list[int]:
    t0 = time.monotonic()
    while _alive(procs) and time.monotonic() - t0 < timeout_s:
        time.sleep(0.05)
    left = _alive(procs)
    for pid in left:  # do not leave them to the next test
        os.kill(pid, signal.SIGKILL)
    return left


def _interrupt(proc: subprocess.Popen, kids: list, limit_s: float) -> tuple[float, str]:
    t0 = time.monotonic()
    os.killpg(proc.pid, signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=limit_s + 60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    elapsed = time.monotonic() - t0
    assert not _wait_gone(kids, 3.0), "worker processes outlived the interrupted driver"
    return elapsed, err


def _batch_args(out: Path, beams: int = 8, starts: int = 16) -> list[str]:
    return ["batch", "--beams", str(beams), "--seed", "3", "--joints", "2", "--stiffness",
            "joint", "--starts", str(starts), "--truth-model", "beam", "--workers", "2",
            "--out", str(out)]


def test_ctrl_c_on_fit_cancels_queued_starts(tmp_path):
    out = tmp_path / "fit"
    proc = _start(["fit", str(BEAM), "--joints", "2", "--truth-model", "beam", "--workers", "2",
                   "--starts", "800", "--out", str(out)], tmp_path)
    kids = _busy_children(proc, 2)
    elapsed, err = _interrupt(proc, kids, 3.0)
    assert proc.returncode == 130, err
    assert elapsed < 3.0, f"exited {elapsed:.1f} s after Ctrl-C"
    assert "Traceback" not in err, err
    assert not (out / "fit.json").exists()


def test_ctrl_c_on_pareto_stops_the_pool(tmp_path):
    out = tmp_path / "pareto"
    proc = _start(["pareto", str(BEAM), "--joints", "2", "--truth-model", "beam", "--workers", "2",
                   "--pop", "40", "--generations", "100000", "--out", str(out)], tmp_path)
    kids = _busy_children(proc, 2)
    elapsed, err = _interrupt(proc, kids, 3.0)
    assert proc.returncode == 130, err
    assert elapsed < 3.0, f"exited {elapsed:.1f} s after Ctrl-C"
    assert "Traceback" not in err, err


def test_ctrl_c_on_batch_keeps_records_and_resumes(tmp_path):
    out = tmp_path / "batch"
    proc = _start(_batch_args(out), tmp_path)
    kids = _busy_children(proc, 2)
    jsonl = out / "results.jsonl"
    t0 = time.monotonic()
    while not (jsonl.exists() and jsonl.read_bytes().count(b"\n") >= 1):
        assert time.monotonic() - t0 < 60, "no record written"
        time.sleep(0.05)
    elapsed, err = _interrupt(proc, kids, 3.0)
    assert proc.returncode == 130, err
    assert elapsed < 3.0, f"exited {elapsed:.1f} s after Ctrl-C"
    assert "Traceback" not in err, err
    kept = [json.loads(line)["beam_index"] for line in jsonl.read_text().splitlines()]
    assert 1 <= len(kept) < 8
    resumed = _start(_batch_args(out), tmp_path)
    _, err = resumed.communicate(timeout=120)
    assert resumed.returncode == 0, err
    final = [json.loads(line)["beam_index"] for line in jsonl.read_text().splitlines()]
    assert final[:len(kept)] == kept  # the kept records are not rewritten
    assert sorted(final) == list(range(8))


@pytest.mark.parametrize("command", ["batch", "fit"])
def test_killed_driver_takes_its_workers_down(command, tmp_path):
    if command == "batch":
        proc = _start(_batch_args(tmp_path / "b", beams=200), tmp_path)
    else:
        proc = _start(["fit", str(BEAM), "--joints", "2", "--truth-model", "beam",
                       "--workers", "2", "--starts", "800", "--out", str(tmp_path / "f")],
                      tmp_path)
    kids = _busy_children(proc, 2)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait(10)  # not communicate(): orphaned workers would hold its pipes open
    left = _wait_gone(kids, 5.0)
    proc.stdout.close()
    proc.stderr.close()
    assert not left, f"{len(left)} of {len(kids)} processes outlived the killed driver"


_FORK_SERVER_DRIVER = """
import time
from prbdm_pin.batch import LocalPool
if __name__ == "__main__":
    ex = LocalPool(2, mp_context="forkserver").executor()
    futures = [ex.submit(time.sleep, 120) for _ in range(4)]
    time.sleep(120)
"""

_NO_KERNEL_GUARD_DRIVER = """
import os, time
from prbdm_pin import workers
if os.fork() == 0:
    workers._die_with_parent = lambda: False  # as on a platform without prctl
    workers.init_worker(os.getppid(), poll_s=0.05)
    time.sleep(120)
    os._exit(0)
time.sleep(120)
"""


@pytest.mark.parametrize("script", [_FORK_SERVER_DRIVER, _NO_KERNEL_GUARD_DRIVER],
                         ids=["forkserver", "watch-thread"])
def test_killed_driver_takes_its_workers_down_without_spawn(script, tmp_path):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, "-c", script], cwd=ROOT, env=env,
                            start_new_session=True)
    parent = psutil.Process(proc.pid)
    t0 = time.monotonic()
    while len(kids := parent.children(recursive=True)) < (4 if "forkserver" in script else 1):
        assert time.monotonic() - t0 < 30, "the driver started no workers"
        time.sleep(0.05)
    time.sleep(0.5)
    kids = parent.children(recursive=True)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait(10)
    left = _wait_gone(kids, 5.0)
    assert not left, f"{len(left)} of {len(kids)} processes outlived the killed driver"
