"""Whole-folder outputs: a rerun killed at any moment leaves the old set or the new one, never a
mix; the user's files and the truth cache survive; no temporary file survives a successful run."""

import json
import os
import shutil
import signal
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from paths import ROOT

from prbdm_pin.io import output_folder as of
from prbdm_pin.io.output_folder import output_folder

BEAMS = ROOT / "examples" / "beams"
BEAM = BEAMS / "uniform-narrow.json"
LENGTH_M = {"uniform-narrow": 1.0, "tapered-linear": 0.6}

# runs the CLI and reports every rename that lands under WATCH; sleeps after the KILL_AT-th one
# so that the test can SIGKILL it exactly there
HOOK = """
import os, sys, time
watch, kill_at, count = os.environ["WATCH"], int(os.environ["KILL_AT"]), [0]
def hooked(real):
    def f(src, dst, *a, **kw):
        real(src, dst, *a, **kw)
        if os.path.abspath(os.fspath(dst)).startswith(watch):
            count[0] += 1
            print("EVENT", count[0], os.path.basename(os.fspath(dst)), flush=True)
            if count[0] == kill_at:
                time.sleep(600)
    return f
os.replace, os.rename = hooked(os.replace), hooked(os.rename)
from prbdm_pin.cli import main
sys.exit(main(sys.argv[1:]))
"""


def leftovers(out: Path) -> list[str]:
    """Staging / aside folders beside ``out`` and temporary files in it."""
    side = [p.name for p in out.parent.iterdir() if p.name.startswith(f".{out.name}.")]
    inner = [p.name for p in out.iterdir() if p.name.endswith(".tmp")] if out.exists() else []
    return side + inner


def run_cli(args, tmp_path: Path, kill_at: int = 0) -> list[str]:
    """Run ``prbdm ARGS`` (SIGKILLed right after the kill_at-th rename, 0: never); its events."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), WATCH=str(tmp_path), KILL_AT=str(kill_at),
               OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    proc = subprocess.Popen([sys.executable, "-c", HOOK, *map(str, args)], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    events = []
    for line in proc.stdout:
        if line.startswith("EVENT"):
            events.append(line.split()[2])
            if len(events) == kill_at:
                proc.send_signal(signal.SIGKILL)
                break
    proc.wait(timeout=300)
    if kill_at == 0 or len(events) < kill_at:
        assert proc.returncode == 0, proc.stderr.read()
    return events


def urdf_joints(path: Path) -> int:
    """Revolute joints of a URDF, counted by an XML parser."""
    return sum(1 for j in ET.parse(path).getroot().iter("joint") if j.get("type") == "revolute")


def assert_one_fit(out: Path) -> int:
    """fit.json, model.urdf and the plots belong to one fit; returns its joint count."""
    fit = json.loads((out / "fit.json").read_text())
    assert urdf_joints(out / "model.urdf") == fit["joints"]
    # the 2R fit is a paper-stiffness fit (with scf.png), the 3R one a joint fit (without)
    assert (out / "scf.png").exists() == (fit["stiffness"] == "paper")
    return fit["joints"]


@pytest.fixture(scope="module")
def truth_file(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("truth")
    run_cli(["truth", BEAM, "--model", "beam", "--modes", "3", "--out", d / "t"], d)
    return d / "t" / "truth.json"


def fit_args(truth: Path, out: Path, joints: int) -> list:
    stiffness = "paper" if joints == 2 else "joint"
    return ["fit", BEAM, "--joints", joints, "--stiffness", stiffness, "--truth", truth,
            "--starts", "1", "--out", out, "--quiet"]


@pytest.fixture(scope="module")
def two_r_fit(truth_file, tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("fit2r")
    run_cli(fit_args(truth_file, d / "fit", 2), d)
    return d / "fit"


def two_r_folder(fit2r: Path, tmp_path: Path) -> Path:
    out = tmp_path / "fit"
    shutil.copytree(fit2r, out)
    (out / "notes.txt").write_text("the user's own file\n")
    (out / "truth-cache").mkdir()
    (out / "truth-cache" / "entry.json").write_text("{}\n")
    (out / ".planform.png.k1ll3d.tmp").write_bytes(b"")  # a killed run's leftover
    return out


def check_killed_rerun(truth: Path, fit2r: Path, tmp_path: Path, kill_at: int) -> None:
    out = two_r_folder(fit2r, tmp_path)
    events = run_cli(fit_args(truth, out, 3), tmp_path, kill_at=kill_at)
    assert len(events) == kill_at, events
    if out.exists():
        assert assert_one_fit(out) in (2, 3)
    # the user's files are in OUT or in a killed run's aside folder, which the next run empties
    run_cli(fit_args(truth, out, 3), tmp_path)
    assert assert_one_fit(out) == 3
    assert (out / "notes.txt").read_text() == "the user's own file\n"
    assert (out / "truth-cache" / "entry.json").exists()
    assert leftovers(out) == []


def test_fit_rerun_killed_leaves_one_whole_fit(truth_file, two_r_fit, tmp_path):
    # model.urdf (3R) is the first file renamed: it used to land in OUT beside the 2R fit.json
    check_killed_rerun(truth_file, two_r_fit, tmp_path, 1)


@pytest.mark.slow
def test_fit_rerun_killed_after_every_rename_leaves_one_whole_fit(truth_file, two_r_fit,
                                                                   tmp_path):
    # the files into the staging folder, then (after the exchange) the user's entries carried
    # over: every moment of the commit
    probe = tmp_path / "probe"
    probe.mkdir()
    events = run_cli(fit_args(truth_file, two_r_folder(two_r_fit, probe), 3), probe)
    for k in range(1, len(events) + 1):
        (tmp_path / f"k{k}").mkdir()
        check_killed_rerun(truth_file, two_r_fit, tmp_path / f"k{k}", k)


def truth_args(beam: str, out: Path) -> list:
    return ["truth", BEAMS / f"{beam}.json", "--model", "beam", "--modes", "3", "--out", out,
            "--quiet"]


def assert_one_truth(out: Path) -> str:
    """truth.json and modes.vtu describe the same beam (the mesh spans the named beam's
    length); returns the beam name."""
    import meshio

    name = json.loads((out / "truth.json").read_text())["beam"]
    points = meshio.read(out / "modes.vtu").points
    assert points[:, 0].max() == pytest.approx(LENGTH_M[name], rel=1e-9)
    return name


def test_truth_rerun_killed_keeps_truth_json_and_modes_vtu_together(tmp_path):
    out = tmp_path / "truth"
    run_cli(truth_args("uniform-narrow", out), tmp_path)
    assert assert_one_truth(out) == "uniform-narrow"
    run_cli(truth_args("tapered-linear", out), tmp_path, kill_at=1)
    assert assert_one_truth(out) == "uniform-narrow"
    run_cli(truth_args("tapered-linear", out), tmp_path)
    assert assert_one_truth(out) == "tapered-linear"
    assert leftovers(out) == []


# --- the context manager itself ----------------------------------------------------------------

def old_folder(tmp_path: Path) -> Path:
    out = tmp_path / "out"
    out.mkdir()
    for name, text in [("fit.json", "old"), ("scf.png", "old"), ("notes.txt", "mine"),
                       (".fit.json.x1.tmp", "")]:
        (out / name).write_text(text)
    (out / "truth-cache").mkdir()
    (out / "truth-cache" / "k.json").write_text("{}")
    return out


def write_new(stage: Path) -> None:
    (stage / "fit.json").write_text("new")
    (stage / "model.urdf").write_text("new")


def assert_new_set(out: Path) -> None:
    assert sorted(os.listdir(out)) == ["fit.json", "model.urdf", "notes.txt", "truth-cache"]
    assert (out / "fit.json").read_text() == "new"
    assert (out / "truth-cache" / "k.json").read_text() == "{}"
    assert leftovers(out) == []


OWNED = ("fit.json", "model.urdf", "scf.png")


@pytest.mark.parametrize("exchange", [True, False])
def test_success_replaces_the_owned_set_and_carries_the_rest(tmp_path, monkeypatch, exchange):
    out = old_folder(tmp_path)
    if not exchange:  # a filesystem without renameat2(RENAME_EXCHANGE)
        monkeypatch.setattr(of, "_exchange", lambda a, b: False)
    with output_folder(out, OWNED, marker="fit.json") as stage:
        assert stage.parent == out.parent and stage != out
        write_new(stage)
        assert (out / "fit.json").read_text() == "old"  # nothing visible before the end
    assert_new_set(out)


@pytest.mark.parametrize("exc", [RuntimeError, KeyboardInterrupt])
def test_failure_leaves_the_old_folder_untouched(tmp_path, exc):
    out = old_folder(tmp_path)
    before = {p.name: p.read_text() for p in out.iterdir() if p.is_file()}
    with pytest.raises(exc), output_folder(out, OWNED) as stage:
        write_new(stage)
        raise exc()
    assert {p.name: p.read_text() for p in out.iterdir() if p.is_file()} == before
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_leftovers_of_killed_runs_are_emptied_into_the_next_one(tmp_path):
    out = old_folder(tmp_path)
    (out / "notes.txt").unlink()
    aside = tmp_path / ".out.old-dead"  # killed while carrying over: still holds a user file
    aside.mkdir()
    (aside / "notes.txt").write_text("mine")
    (aside / "fit.json").write_text("older")
    staged = tmp_path / ".out.staging-dead"  # killed while writing
    staged.mkdir()
    (staged / "model.urdf").write_text("half")
    with output_folder(out, OWNED) as stage:
        write_new(stage)
    assert_new_set(out)
    assert (out / "model.urdf").read_text() == "new"


def test_a_live_runs_staging_folder_is_left_alone(tmp_path):
    out = old_folder(tmp_path)
    live = tmp_path / ".out.staging-live"
    live.mkdir()
    fd = of._lock(live)
    try:
        with output_folder(out, OWNED) as stage:
            write_new(stage)
        assert live.exists()
    finally:
        os.close(fd)


def test_new_folder_and_working_directory_fallback(tmp_path, monkeypatch):
    fresh = tmp_path / "a" / "b"
    with output_folder(fresh, OWNED) as stage:
        write_new(stage)
    assert sorted(os.listdir(fresh)) == ["fit.json", "model.urdf"]
    # OUT is the working directory: cannot be renamed under the shell; files moved in one by one
    out = old_folder(tmp_path)
    inode = out.stat().st_ino
    monkeypatch.chdir(out)
    with output_folder(".", OWNED, marker="fit.json") as stage:
        assert stage.parent == out
        write_new(stage)
    assert out.stat().st_ino == inode
    assert_new_set(out)
