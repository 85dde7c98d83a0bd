"""Probe cases: statics that never answer wrongly in silence, whole-folder outputs, file modes.

- "5 silent wrong answers": the planar statics (scalar and the fit's batched solver) over load
  indices 1e-2 ... 1e300 in three directions: an equilibrium whose moments balance (checked with
  the tip geometry, not the solver's Jacobian) or a SolveError naming the load; never the straight
  pose in silence. Non-finite loads: BeamInputError naming tip_force.
- "6 folder atomicity": ``prbdm fit`` (2R paper -> 3R joint), ``prbdm truth`` (another beam) and
  ``prbdm simulate`` reruns SIGKILLed right after each rename into the output tree: the folder
  holds one whole set; the next run keeps the user's files and the truth cache and leaves no
  temporary or staging file.
- "8 CSV and file modes": every output file of truth, fit and simulate under umask 022 and
  077 has mode 0666 & ~umask, as results.jsonl (opened with open()) has.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
BEAMS = ROOT / "examples" / "beams"
BEAM = BEAMS / "uniform-narrow.json"
LENGTH_M = {"uniform-narrow": 1.0, "tapered-linear": 0.6}

S5, S6, S8 = "5 silent wrong answers", "6 folder atomicity", "8 CSV and file modes"

# the CLI, reporting every rename under WATCH and sleeping after the KILL_AT-th one
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


def prbdm(args, watch: Path, kill_at: int = 0) -> list[str]:
    """Run ``prbdm ARGS``, SIGKILLed right after the kill_at-th rename (0: never); the renames."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), WATCH=str(watch), KILL_AT=str(kill_at))
    proc = subprocess.Popen([sys.executable, "-c", HOOK, *map(str, args)], env=env, cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    events = []
    for line in proc.stdout:
        if line.startswith("EVENT"):
            events.append(line.split()[2])
            if len(events) == kill_at:
                proc.send_signal(signal.SIGKILL)
                break
    proc.wait(timeout=300)
    err = proc.stderr.read()
    if kill_at == 0 or len(events) < kill_at:
        assert proc.returncode == 0, f"exit {proc.returncode}: {err[-300:]!r}"
    return events


def _tmpdir(prefix: str) -> Path:
    # inside the probe's scratch folder (it sets PRBDM_CACHE there), removed with it
    cache = os.environ.get("PRBDM_CACHE")
    return Path(tempfile.mkdtemp(prefix=prefix, dir=Path(cache).parent if cache else None))


# --- 5: statics --------------------------------------------------------------------------------

def _torques(lengths, q, F):
    """Moments (N m) of the tip force about each joint, from the tip geometry alone."""
    phi = np.cumsum(q)
    pts = [np.array([lengths[0], 0.0])]
    for Li, p in zip(lengths[1:], phi, strict=True):
        pts.append(pts[-1] + Li * np.array([math.cos(p), -math.sin(p)]))
    tip = pts[-1]
    return np.array([F[0] * (tip - j)[1] - F[2] * (tip - j)[0] for j in pts[:-1]])


def _balanced(lengths, k, q, F) -> None:
    kq, tau = k * q, _torques(lengths, q, F)
    scale = max(float(np.abs(kq).max()), float(np.abs(tau).max()), 1e-300)
    assert np.all(np.isfinite(q)), f"q = {q.tolist()} not finite"
    assert float(np.abs(kq - tau).max()) <= 1e-6 * scale, (
        f"F = {F.tolist()}: returned q = {q.tolist()} is not an equilibrium "
        f"(K q = {kq.tolist()}, moments {tau.tolist()})")


def _statics_case(n: int, exp: float, angle_deg: float):
    def fn():
        from prbdm_pin.chain import statics
        from prbdm_pin.errors import SolveError

        rng = np.random.default_rng(int(1000 * n + 10 * exp + angle_deg))
        L = rng.uniform(0.05, 0.4, n + 1)
        k = rng.uniform(0.5, 5.0, n)
        a = math.radians(angle_deg)
        F = 10.0**exp * k.max() / L[1:].sum() * np.array([math.cos(a), 0.0, math.sin(a)])
        try:
            q = statics.static_deflection_planar(L, k, F)
        except SolveError as exc:
            assert "tip_force" in str(exc), f"SolveError does not name the load: {exc}"
            # a load index the residual test resolves must be answered, not refused
            assert exp > 5, f"load index 1e{exp:g} refused: {exc}"
        else:
            _balanced(L, k, q, F)
        qb, ok = statics.static_deflection_planar_batch(L, k[None], F)
        if ok[0]:
            _balanced(L, k, qb[0], F)
        else:
            assert np.isnan(qb[0]).all(), f"batch row not converged but q = {qb[0].tolist()}"
            assert exp > 5, f"batch: load index 1e{exp:g} not solved"
    return fn


def _nonfinite_case(bad: float, where: int):
    def fn():
        from prbdm_pin.chain import statics
        from prbdm_pin.errors import BeamInputError

        F = [0.0, 0.0, -1.0]
        F[where] = bad
        for solve in (lambda: statics.static_deflection_planar([0.1, 0.4], [2.0], F),
                      lambda: statics.static_deflection_planar_batch([0.1, 0.4], [[2.0]], F)):
            try:
                solve()
            except BeamInputError as exc:
                assert "tip_force" in str(exc), f"does not name tip_force: {exc}"
            else:
                raise AssertionError(f"tip_force = {F} accepted")
    return fn


def _model_case(force_N: float):
    def fn():
        from prbdm_pin.errors import SolveError
        from prbdm_pin.files.beam_file import load_beam
        from prbdm_pin.model.prbdm_model import build_model

        m = build_model(load_beam(BEAM), [0.1, 0.3, 0.3, 0.3], [50.0, 30.0, 10.0])
        try:
            q, _ = m.static_deflection(np.array([0.0, 0.0, -force_N]))
        except SolveError as exc:
            assert "tip_force" in str(exc), str(exc)
        else:
            _balanced(m.lengths_m, m.stiffness_Nm_per_rad, q, np.array([0.0, 0.0, -force_N]))
    return fn


def statics_cases() -> list:
    out = []
    for n in (1, 3, 8):
        for exp in list(range(-2, 8)) + list(range(8, 303, 6)):
            for angle in (-90.0, -30.0, 180.0):
                out.append((S5, f"statics {n}R load index 1e{exp} at {angle:g} deg",
                            _statics_case(n, exp, angle)))
    for bad in (math.nan, math.inf, -math.inf):
        for where in (0, 2):
            out.append((S5, f"statics tip_force[{where}] = {bad}", _nonfinite_case(bad, where)))
    for f in (1.0, 1e5, 1e155, 1e160, 1e200, 1e300):
        out.append((S5, f"PrbdmModel.static_deflection |F| = {f:g} N", _model_case(f)))
    return out


# --- 6: folders --------------------------------------------------------------------------------

class _Scratch:
    """A scratch folder with a beam truth and a 2R paper fit, made once for all folder cases."""

    _dir: Path | None = None

    @classmethod
    def get(cls) -> Path:
        if cls._dir is None:
            d = _tmpdir("folders-")
            prbdm(["truth", BEAM, "--model", "beam", "--modes", "3", "--out", d / "truth",
                   "--quiet"], d)
            prbdm(_fit_args(d, d / "fit2r", 2), d)
            cls._dir = d
        return cls._dir


def _fit_args(d: Path, out: Path, joints: int) -> list:
    return ["fit", BEAM, "--joints", joints, "--stiffness", "paper" if joints == 2 else "joint",
            "--truth", d / "truth" / "truth.json", "--starts", "1", "--out", out, "--quiet"]


def _leftovers(out: Path) -> list[str]:
    side = [p.name for p in out.parent.iterdir() if p.name.startswith(f".{out.name}.")]
    return side + ([p.name for p in out.iterdir() if p.name.endswith(".tmp")]
                   if out.exists() else [])


def _user_files(out: Path) -> None:
    (out / "notes.txt").write_text("the user's own file\n")
    (out / "truth-cache").mkdir(exist_ok=True)
    (out / "truth-cache" / "entry.json").write_text("{}\n")
    (out / ".planform.png.k1ll3d.tmp").write_bytes(b"")


def _kept(out: Path) -> None:
    assert (out / "notes.txt").exists(), "the user's notes.txt is gone"
    assert (out / "truth-cache" / "entry.json").exists(), "OUT/truth-cache is gone"
    assert _leftovers(out) == [], f"left behind: {_leftovers(out)}"


def _one_fit(out: Path) -> int:
    fit = json.loads((out / "fit.json").read_text())
    joints = sum(1 for j in ET.parse(out / "model.urdf").getroot().iter("joint")
                 if j.get("type") == "revolute")
    assert joints == fit["joints"], f"model.urdf has {joints} joints, fit.json {fit['joints']}"
    assert (out / "scf.png").exists() == (fit["stiffness"] == "paper"), "scf.png of another fit"
    return fit["joints"]


def _fit_kill_case(k: int):
    def fn():
        d = _Scratch.get()
        work = Path(tempfile.mkdtemp(dir=d))
        out = work / "fit"
        shutil.copytree(d / "fit2r", out)
        _user_files(out)
        events = prbdm(_fit_args(d, out, 3), work, kill_at=k)
        if len(events) < k:
            return  # fewer renames than k: the run finished
        if out.exists():
            _one_fit(out)
        else:
            assert [p for p in work.iterdir() if ".old-" in p.name], "OUT gone, nothing aside"
        prbdm(_fit_args(d, out, 3), work)
        assert _one_fit(out) == 3
        _kept(out)
    return fn


def _one_truth(out: Path) -> str:
    import meshio

    name = json.loads((out / "truth.json").read_text())["beam"]
    x = float(meshio.read(out / "modes.vtu").points[:, 0].max())
    assert abs(x - LENGTH_M[name]) < 1e-9, f"modes.vtu spans {x} m, truth.json is {name}"
    return name


def _truth_args(beam: str, out: Path) -> list:
    return ["truth", BEAMS / f"{beam}.json", "--model", "beam", "--modes", "3", "--out", out,
            "--quiet"]


def _truth_kill_case(k: int):
    def fn():
        work = Path(tempfile.mkdtemp(dir=_Scratch.get()))
        out = work / "truth"
        prbdm(_truth_args("uniform-narrow", out), work)
        _user_files(out)
        events = prbdm(_truth_args("tapered-linear", out), work, kill_at=k)
        if len(events) >= k and out.exists():
            _one_truth(out)
        prbdm(_truth_args("tapered-linear", out), work)
        assert _one_truth(out) == "tapered-linear"
        _kept(out)
    return fn


def _simulate_kill_case(k: int):
    def fn():
        d = _Scratch.get()
        work = Path(tempfile.mkdtemp(dir=d))
        out = work / "sim"

        def sim(duration: str, kill_at: int = 0):
            return prbdm(["simulate", d / "fit2r" / "fit.json", "--duration", duration,
                          "--out", out, "--quiet"], work, kill_at=kill_at)

        def duration_of(folder: Path) -> float:
            rows = (folder / "trajectory.csv").read_text().splitlines()
            return float(rows[-1].split(",")[0])

        sim("0.05")
        _user_files(out)
        png_old = (out / "response.png").read_bytes()
        events = sim("0.1", kill_at=k)
        if len(events) >= k and out.exists():
            # the old pair (0.05 s and its plot) or the new pair (0.1 s and another plot)
            old = abs(duration_of(out) - 0.05) < 1e-9
            same_png = (out / "response.png").read_bytes() == png_old
            assert old == same_png, (f"trajectory.csv of the {'old' if old else 'new'} run "
                                     "beside the other run's response.png")
        sim("0.1")
        assert abs(duration_of(out) - 0.1) < 1e-9
        _kept(out)
    return fn


def _exception_case():
    def fn():
        from prbdm_pin.io.output_folder import output_folder

        work = Path(tempfile.mkdtemp(dir=_Scratch.get()))
        out = work / "fit"
        shutil.copytree(_Scratch.get() / "fit2r", out)
        before = sorted(os.listdir(out))
        for exc in (RuntimeError, KeyboardInterrupt):
            try:
                with output_folder(out, ["fit.json", "model.urdf"]) as stage:
                    (stage / "fit.json").write_text("{}")
                    raise exc()
            except exc:
                pass
            assert sorted(os.listdir(out)) == before, "a failed run changed OUT"
            assert _leftovers(out) == [], f"left behind: {_leftovers(out)}"
            _one_fit(out)
    return fn


def folder_cases() -> list:
    out = [(S6, f"fit 2R -> 3R rerun SIGKILLed after rename {k}", _fit_kill_case(k))
           for k in range(1, 6)]
    out += [(S6, f"truth rerun (another beam) SIGKILLed after rename {k}", _truth_kill_case(k))
            for k in (1, 3)]
    out += [(S6, f"simulate rerun SIGKILLed after rename {k}", _simulate_kill_case(k))
            for k in (1,)]
    out.append((S6, "exception / KeyboardInterrupt inside the folder leaves OUT as it was",
                _exception_case()))
    return out


# --- 8: file modes -----------------------------------------------------------------------------

class _Modes:
    """Outputs of truth, fit and simulate written under a given umask (made once per umask)."""

    _done: dict[int, Path] = {}

    @classmethod
    def get(cls, mask: int) -> Path:
        if mask not in cls._done:
            d = _tmpdir("modes-")
            old = os.umask(mask)
            try:
                prbdm(["truth", BEAM, "--model", "beam", "--modes", "3", "--out", d / "truth",
                       "--quiet"], d)
                prbdm(["fit", BEAM, "--joints", "2", "--truth", d / "truth" / "truth.json",
                       "--starts", "1", "--out", d / "fit", "--quiet"], d)
                prbdm(["simulate", d / "fit" / "fit.json", "--duration", "0.05", "--out",
                       d / "sim", "--quiet"], d)
            finally:
                os.umask(old)
            cls._done[mask] = d
        return cls._done[mask]


OUTPUTS = [("truth", "truth.json"), ("truth", "modes.vtu"), ("fit", "fit.json"),
           ("fit", "model.urdf"), ("fit", "planform.png"), ("fit", "scf.png"),
           ("sim", "trajectory.csv"), ("sim", "response.png")]


def _mode_case(mask: int, folder: str, name: str):
    def fn():
        p = _Modes.get(mask) / folder / name
        got = p.stat().st_mode & 0o777
        assert got == 0o666 & ~mask, f"{folder}/{name}: mode {got:o}, want {0o666 & ~mask:o}"
        dmode = p.parent.stat().st_mode & 0o777
        assert dmode == 0o777 & ~mask, f"{folder}/: mode {dmode:o}, want {0o777 & ~mask:o}"
    return fn


def mode_cases() -> list:
    return [(S8, f"umask {mask:03o}: {folder}/{name}", _mode_case(mask, folder, name))
            for mask in (0o022, 0o077) for folder, name in OUTPUTS]


def cases() -> list:
    """Every case of this module: (category, name, fn)."""
    return statics_cases() + folder_cases() + mode_cases()
