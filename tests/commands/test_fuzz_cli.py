"""Fuzz of the CLI argument surface: every subcommand with valid and invalid values for each of
its options (numbers at and beyond their ranges, non-finite and non-numeric text, paths that are
files, lie under files or in /proc, unknown options, control characters).

The work each command does after its checks is replaced by a sentinel (the truth, the fit, the
model load, the batch driver, the report and the benchmark), so the property is about the
checks alone: either the sentinel is reached (every option passed) or the command exits 2 with
one line ``prbdm CMD: error: ...`` naming an option or argument, having created nothing; never
another exception, never a traceback, never a warning.
"""

from __future__ import annotations

import functools
import os
import shutil
import tempfile
import warnings
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from prbdm_pin.cli import build_parser, main

BEAM = "examples/beams/uniform-narrow.json"


class Reached(Exception):
    """The command's work started: every option passed its checks."""


def _reached(*args, **kwargs):
    raise Reached


NUMBERS = st.one_of(
    st.sampled_from(["0", "-1", "1", "2", "3", "4", "5", "64", "65", "1000", "nan", "inf",
                     "-inf", "1e-12", "1e-300", "1e300", "0.5", "0.02", "0.999", "1.0", "abc",
                     "", " 7", "1e3", "0x10", "1_000", "9" * 30, "-0", "0.0", "1.5"]),
    st.integers(-10**6, 10**6).map(str),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.text(max_size=6),
)
TEXT = st.one_of(st.text(max_size=12), st.sampled_from(["0,0,-10", "1,2", "2,5", "x", "3/2",
                                                        "0/1", "1/4", "tcp://h:1", "a\nb"]))
# design specifications: valid ones, unknown names, vertices that do not exist or are not
# design variables (the root, the tip station), a name twice, empty lists
DESIGNS = st.one_of(st.sampled_from(["thickness", "half_width[1]", "thickness,E,rho,nu",
                                     "half_width[0],half_width[1]", "x[0]", "x[1]",
                                     "half_width[9]", "thickness,thickness", ",", "",
                                     "half_width[-1]", "E ,rho"]), TEXT)
# "fresh": a path that does not exist yet (must still not exist after a refusal)
PATH_KINDS = st.sampled_from(["fresh", "fresh", "dir", "file", "under-file", "/proc/x",
                              "/sys/x", "/dev/x", "", "trailing/"])

OPTIONS = {
    "truth": {"--model": ["plate", "beam"], "--modes": NUMBERS, "--mesh": NUMBERS,
              "--selection": ["paper", "shape", "other"], "--no-static": None,
              "--large-deflection": ["elastica", "none", "x"], "--error-tol": NUMBERS,
              "--accept-coarse": None, "--out": "dir"},
    "fit": {"--joints": NUMBERS, "--frequencies": NUMBERS, "--stiffness": ["paper", "joint"],
            "--truth-model": ["beam", "plate", "fem"], "--mesh-level": NUMBERS,
            "--accept-coarse": None, "--cache-dir": "dir", "--extra-loads": TEXT,
            "--xi": NUMBERS, "--squared": None, "--min-link": NUMBERS, "--seed": NUMBERS,
            "--out": "dir", "--objective": ["eigen", "combined", "x"], "--starts": NUMBERS,
            "--eps": NUMBERS, "--workers": NUMBERS, "--loss-tol": NUMBERS,
            "--eigen-norm": ["paper", "relative", "l3"]},
    "pareto": {"--joints": NUMBERS, "--frequencies": NUMBERS, "--stiffness": ["paper", "joint"],
               "--cache-dir": "dir", "--xi": NUMBERS, "--min-link": NUMBERS, "--seed": NUMBERS,
               "--out": "dir", "--pop": NUMBERS, "--generations": NUMBERS, "--eps": NUMBERS,
               "--workers": NUMBERS, "--deflection-norm": ["position", "displacement", "x"]},
    "simulate": {"--duration": NUMBERS, "--tip-force": TEXT, "--initial-angle": NUMBERS,
                 "--damping": NUMBERS, "--damping-form": ["modal", "eq5c", "stiffness", "x"],
                 "--method": ["exponential", "gauss", "DOP853", "Euler", ""], "--dt": NUMBERS,
                 "--output-dt": NUMBERS, "--compare-truth": None,
                 "--truth-model": ["plate", "beam", "solid"], "--cache-dir": "dir",
                 "--out": "dir"},
    "export": {"--format": ["urdf", "mjcf", "json", "pdf"], "--damping": NUMBERS,
               "--damping-form": ["stiffness", "modal", "x"], "--out": "file"},
    "batch": {"--beams": NUMBERS, "--seed": NUMBERS, "--joints": NUMBERS,
              "--frequencies": NUMBERS, "--starts": NUMBERS, "--min-link": NUMBERS,
              "--truth-model": ["beam", "plate", "x"], "--out": "dir", "--cache-dir": "dir",
              "--workers": NUMBERS, "--shard": TEXT, "--retry-failed": None},
    "batch-report": {"--out": "dir", "--no-plots": None},
    "bench": {"--quick": None, "--out": "dir", "--cache-dir": "dir", "--no-mujoco": None},
    "sensitivity": {"--design": DESIGNS, "--model": ["plate", "beam", "solid"],
                    "--modes": NUMBERS, "--mesh": NUMBERS,
                    "--selection": ["paper", "shape", "other"], "--out": "dir"},
}


def _base(cmd: str, fresh: Path) -> list[str]:
    return {
        "truth": ["truth", BEAM, "--model", "beam", "--out", str(fresh)],
        "fit": ["fit", BEAM, "--joints", "2", "--truth-model", "beam", "--out", str(fresh)],
        "pareto": ["pareto", BEAM, "--joints", "2", "--truth-model", "beam", "--out",
                   str(fresh)],
        "simulate": ["simulate", "model.json", "--duration", "0.1", "--out", str(fresh)],
        "export": ["export", "model.json", "--format", "urdf", "--out", str(fresh / "m.urdf")],
        "batch": ["batch", "--beams", "3", "--joints", "2", "--truth-model", "beam", "--out",
                  str(fresh)],
        "batch-report": ["batch-report", str(fresh.parent)],
        "bench": ["bench", "--out", str(fresh)],
        "sensitivity": ["sensitivity", BEAM, "--design", "thickness", "--model", "beam",
                        "--out", str(fresh)],
    }[cmd]


def _path(kind: str, scratch: Path, n: int) -> str:
    afile = scratch / "afile"
    return {"fresh": str(scratch / f"new{n}" / "x"), "dir": str(scratch), "file": str(afile),
            "under-file": str(afile / "x"), "/proc/x": "/proc/prbdm-fuzz",
            "/sys/x": "/sys/prbdm-fuzz", "/dev/x": "/dev/prbdm-fuzz", "": "",
            "trailing/": str(scratch / f"new{n}") + "/"}[kind]


# every drawn command line's scratch folder lives under one root, removed after the module
# (hypothesis draws hundreds of lines a run; one folder each would pile up in the temp dir)
_SCRATCH_ROOT = Path(tempfile.mkdtemp(prefix="prbdm-fuzz-"))


@pytest.fixture(autouse=True, scope="module")
def _remove_scratch_root():
    yield
    shutil.rmtree(_SCRATCH_ROOT, ignore_errors=True)


@st.composite
def command_lines(draw, cmd: str):
    """(argv, fresh paths that must not exist after a refusal)."""
    scratch = Path(tempfile.mkdtemp(dir=_SCRATCH_ROOT))
    (scratch / "afile").write_text("a file\n")
    fresh = scratch / "out"
    argv = _base(cmd, fresh)
    must_not_exist = [fresh] if cmd != "export" else [fresh / "m.urdf"]
    options = OPTIONS[cmd]
    names = draw(st.lists(st.sampled_from(sorted(options)), max_size=4))
    for i, name in enumerate(names):
        spec = options[name]
        if spec is None:
            argv.append(name)
        elif isinstance(spec, list):
            argv += [name, draw(st.sampled_from(spec) | st.text(max_size=5))]
        elif spec in ("dir", "file"):
            kind = draw(PATH_KINDS)
            value = _path(kind, scratch, i)
            if spec == "file" and kind == "fresh":
                value = str(scratch / f"new{i}.urdf")
            argv += [name, value]
            if kind in ("fresh", "trailing/"):
                must_not_exist.append(Path(value))
        else:
            argv += [name, draw(spec)]
    if draw(st.integers(0, 9)) == 0:
        argv.append(draw(st.sampled_from(["--bogus", "extra", "-x", "--out"])))
    return argv, must_not_exist


@functools.cache
def _names(cmd: str) -> frozenset[str]:
    """Every option string and positional name of ``cmd``, and what else may be named."""
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    names = set()
    for action in sub.choices[cmd]._actions:
        names.update(action.option_strings)
        if not action.option_strings:
            names.add(action.metavar or action.dest)
    return frozenset(names) | {"PRBDM_CACHE", "cache folder", "output samples",
                               "unrecognized arguments", "the following arguments are required",
                               "tip_force"}


@pytest.fixture()
def stubs(monkeypatch, tmp_path):
    """Replace each command's work (after its checks) by a sentinel."""
    import prbdm_pin.batch
    import prbdm_pin.bench.run
    import prbdm_pin.commands.fit
    import prbdm_pin.commands.pareto
    import prbdm_pin.files.model_source
    import prbdm_pin.truth
    import prbdm_pin.truth.compute_derivatives

    monkeypatch.setenv("PRBDM_CACHE", str(tmp_path / "cache"))
    for mod, name in [(prbdm_pin.truth, "compute_truth"),
                      (prbdm_pin.truth.compute_derivatives, "truth_gradient"),
                      (prbdm_pin.commands.fit, "load_target"),
                      (prbdm_pin.commands.pareto, "load_target"),
                      (prbdm_pin.files.model_source, "load_model"),
                      (prbdm_pin.batch, "run_batch"), (prbdm_pin.batch, "LocalPool"),
                      (prbdm_pin.batch, "DaskCluster"),
                      (prbdm_pin.batch, "load_study"),
                      (prbdm_pin.bench.run, "run_benchmark")]:
        monkeypatch.setattr(mod, name, _reached)


def _check(cmd: str, argv: list[str], must_not_exist: list[Path], capsys) -> None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            rc = main(argv)
        except Reached:
            return
        except SystemExit as exc:
            rc = exc.code
    assert not caught, [str(w.message) for w in caught]
    err = capsys.readouterr().err.strip()
    assert rc == 2, (argv, rc, err)
    lines = err.splitlines()
    assert len(lines) == 1 and "Traceback" not in err, (argv, err)
    assert lines[0].startswith((f"prbdm {cmd}: error: ", "prbdm: error: ")), (argv, err)
    assert any(n in err for n in _names(cmd)), (argv, err)
    for p in must_not_exist:
        assert not p.exists(), (argv, err, f"{p} was created")


FUZZ = settings(max_examples=20, deadline=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture,
                                       HealthCheck.too_slow])
STRESS = settings(FUZZ, max_examples=600)


@pytest.mark.parametrize("cmd", sorted(OPTIONS))
def test_cli_options_fuzz(cmd, stubs, capsys):
    @FUZZ
    @given(command_lines(cmd))
    def prop(case):
        capsys.readouterr()
        _check(cmd, *case, capsys)

    prop()


@pytest.mark.stress
@pytest.mark.parametrize("cmd", sorted(OPTIONS))
def test_cli_options_fuzz_stress(cmd, stubs, capsys):
    @STRESS
    @given(command_lines(cmd))
    def prop(case):
        capsys.readouterr()
        _check(cmd, *case, capsys)

    prop()


def test_stubs_are_reached_by_valid_command_lines(stubs, capsys, tmp_path):
    # the property above is not vacuous: a valid command line of each command gets past its
    # checks to the work (here the sentinel)
    (tmp_path / "m.json").write_text("{}")
    for cmd in OPTIONS:
        fresh = tmp_path / f"out-{cmd}"  # bench creates its folder before its work
        argv = _base(cmd, fresh)
        with pytest.raises(Reached):
            main(argv)
        assert not os.path.exists(fresh) or cmd == "bench"
