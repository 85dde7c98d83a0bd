"""Batch folders that were truncated, edited, split or resumed with other arguments.

Every defect of batch.json or results.jsonl is a one-line error (exit 2) naming the file and
the field; a report over some of a study's shards says so; a resume without batch.json checks
the records' own arguments; results.csv is byte-stable across resumes; every output file has
one mode (0o666 less the umask).
"""

from __future__ import annotations

import json
import os
import shutil
import stat
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from paths import ROOT

from prbdm_pin import batch
from prbdm_pin.batch import BatchSpec, FitSettings, LocalPool, run_batch
from prbdm_pin.cli import main
from prbdm_pin.errors import BeamInputError
from prbdm_pin.options.objects import FitOptions

REAL = FitSettings(joints=2, options=FitOptions(frequencies=2, objective="eigen",
                                                stiffness="joint", starts=2),
                   truth_model="beam")


def nan_work(task: batch.BeamTask) -> dict:
    """Deterministic, cheap work whose record holds a NaN (as an unused loss does)."""
    beam = batch.beam_of(task)
    return {"beam_index": task.index, "beam_name": task.name, "seed": task.seed,
            "status": "ok", "mass_kg": beam.mass_kg, "taper_ratio": 0.5 + task.index / 10,
            "mean_width_m": 0.01, "eigen_loss_pct": float("nan"),
            "gamma": [0.25, float("nan"), 0.75], "gamma_1": 0.25}


def _spec(n: int = 6, settings: FitSettings = REAL, **kw) -> BatchSpec:
    return BatchSpec(seed=11, settings=settings, n_beams=n, **kw)


@pytest.fixture(scope="module")
def real_dir(tmp_path_factory) -> Path:
    """Three beams through the real pipeline (1D truth, 2-start joint fit)."""
    out = tmp_path_factory.mktemp("real")
    assert run_batch(_spec(3, REAL), out, progress=False, backend=LocalPool(1)).n_ok == 3
    return out


@pytest.fixture(scope="module")
def shards(tmp_path_factory) -> list[Path]:
    base = tmp_path_factory.mktemp("shards")
    dirs = []
    for i in range(3):
        d = base / f"s{i}"
        run_batch(_spec(30, shard=(i, 3)), d, work=nan_work, backend=LocalPool(1),
                  progress=False)
        dirs.append(d)
    return dirs


def _exit2(capsys, argv: list[str], *fields: str) -> str:
    code = main(argv)
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    for f in fields:
        assert f in err, f"{f!r} not named in {err!r}"
    return err


def _copy(src: Path, tmp_path: Path) -> Path:
    return Path(shutil.copytree(src, tmp_path / "copy"))


# --- batch-report on broken files ------------------------------------------------------------
@pytest.mark.parametrize("content", [b'{"seed": 11, "settings": {"joi', b"[1, 2, 3]",
                                     b'{"seed": "eleven"}', b'{"shard": [0]}',
                                     b'{"settings": []}'],
                         ids=["truncated", "list", "string-seed", "bad-shard", "list-settings"])
def test_report_on_broken_manifest_names_it(real_dir, tmp_path, capsys, content):
    d = _copy(real_dir, tmp_path)
    (d / "batch.json").write_bytes(content)
    _exit2(capsys, ["batch-report", str(d), "--no-plots", "-q"], "batch.json")


@pytest.mark.parametrize("edit, field", [
    (lambda r: {**r, "eigen_loss_pct": "0.1"}, "eigen_loss_pct"),
    (lambda r: {**r, "taper_ratio": "wide"}, "taper_ratio"),
    (lambda r: {**r, "gamma": ["a", "b", "c"]}, "gamma"),
    (lambda r: {**r, "gamma": 0.3}, "gamma"),
    (lambda r: {**r, "status": 1}, "status"),
    (lambda r: {**r, "beam_index": "0"}, "beam_index"),
])
def test_report_on_string_fields_names_the_field(real_dir, tmp_path, capsys, edit, field):
    d = _copy(real_dir, tmp_path)
    path = d / "results.jsonl"
    lines = path.read_text().splitlines()
    lines[1] = json.dumps(edit(json.loads(lines[1])))
    path.write_text("\n".join(lines) + "\n")
    err = _exit2(capsys, ["batch-report", str(d), "--no-plots", "-q"], field, "line 2")
    assert "results.jsonl" in err


@pytest.mark.parametrize("line", [b'{"beam_index": 1, "beam_name": "b\xff\xfe"}',
                                  b'{"beam_index": 1, "mass_kg": NaN}', b"[" * 5000,
                                  b'{"beam_index": 1, "mass_kg": 1' + b"0" * 400 + b"}"],
                         ids=["not-utf8", "nan", "deep", "huge-int"])
def test_report_on_undecodable_line_names_it(real_dir, tmp_path, capsys, line):
    d = _copy(real_dir, tmp_path)
    path = d / "results.jsonl"
    lines = path.read_bytes().splitlines()
    lines[1] = line
    path.write_bytes(b"\n".join(lines) + b"\n")
    err = _exit2(capsys, ["batch-report", str(d), "--no-plots", "-q"], "line 2")
    assert "results.jsonl" in err


def test_report_warns_on_missing_shards(shards, tmp_path, capsys):
    out = tmp_path / "rep"
    assert main(["batch-report", str(shards[0]), str(shards[2]), "--no-plots", "-q",
                 "--out", str(out)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "1/3" in err[0] and "20" in err[0] and "30" in err[0], err
    md = (out / "report.md").read_text()
    assert "1/3" in md and "Beams with a record: 20" in md
    # every shard given: no warning
    assert main(["batch-report", *map(str, shards), "--no-plots", "-q", "--out",
                 str(tmp_path / "all")]) == 0
    assert capsys.readouterr().err == ""
    assert "not given" not in (tmp_path / "all" / "report.md").read_text()


def test_report_refuses_shards_of_different_counts(shards, tmp_path, capsys):
    other = tmp_path / "half"
    run_batch(_spec(30, shard=(0, 2)), other, work=nan_work, backend=LocalPool(1),
              progress=False)
    _exit2(capsys, ["batch-report", str(shards[0]), str(other), "--no-plots", "-q"], "shard")


# --- resume -----------------------------------------------------------------------------------
def test_resume_on_list_manifest_names_it(real_dir, tmp_path):
    d = _copy(real_dir, tmp_path)
    (d / "batch.json").write_text("[]\n")
    with pytest.raises(BeamInputError, match="batch.json"):
        run_batch(_spec(3, REAL), d, progress=False, backend=LocalPool(1))


@pytest.mark.parametrize("change, option", [
    ({"joints": 3, "frequencies": 3}, "--joints"), ({"starts": 3}, "--starts"),
    ({"stiffness": "paper"}, "--stiffness"), ({"eigen_norm": "paper"}, "--eigen-norm"),
    ({"truth_model": "plate"}, "--truth-model"), ({"min_fraction": 0.05}, "--min-link"),
])
def test_resume_without_manifest_checks_the_records(real_dir, tmp_path, change, option):
    d = _copy(real_dir, tmp_path)
    (d / "batch.json").unlink()
    before = (d / "results.jsonl").read_bytes()
    other = REAL.replace(**change)
    with pytest.raises(BeamInputError, match=option):
        run_batch(_spec(3, other), d, progress=False, backend=LocalPool(1))
    assert (d / "results.jsonl").read_bytes() == before
    assert not (d / "batch.json").exists()  # no manifest that contradicts the records


def test_resume_without_manifest_other_seed_refused(real_dir, tmp_path):
    d = _copy(real_dir, tmp_path)
    (d / "batch.json").unlink()
    with pytest.raises(BeamInputError, match="--seed"):
        run_batch(BatchSpec(seed=12, settings=REAL, n_beams=3), d, progress=False)


def test_resume_without_manifest_same_arguments_resumes(real_dir, tmp_path):
    d = _copy(real_dir, tmp_path)
    (d / "batch.json").unlink()
    s = run_batch(_spec(3, REAL), d, progress=False, backend=LocalPool(1))
    assert (s.n_skipped, s.n_ok) == (3, 0)
    assert json.loads((d / "batch.json").read_text())["settings"]["joints"] == 2


def test_resume_without_manifest_checks_records_of_older_versions(real_dir, tmp_path):
    # records written before they carried their arguments: the fit still shows the joints
    d = _copy(real_dir, tmp_path)
    (d / "batch.json").unlink()
    path = d / "results.jsonl"
    recs = [json.loads(line) for line in path.read_text().splitlines()]
    for r in recs:
        for k in ("joints", "objective", "stiffness", "starts", "truth_model", "min_fraction"):
            r.pop(k)
    path.write_text("".join(json.dumps(r) + "\n" for r in recs))
    other = REAL.replace(joints=3, frequencies=2)
    with pytest.raises(BeamInputError, match="--joints = 3.*--joints = 2"):
        run_batch(_spec(3, other), d, progress=False, backend=LocalPool(1))


def test_beams_dir_error_leaves_no_out_folder(tmp_path):
    bad = tmp_path / "beams"
    bad.mkdir()
    (bad / "a.json").write_text("{")
    out = tmp_path / "out"
    with pytest.raises(BeamInputError, match="a.json"):
        run_batch(BatchSpec(seed=0, settings=REAL, beams_dir=str(bad)), out, progress=False)
    assert not out.exists()


# --- CSV and file modes ----------------------------------------------------------------------
def test_csv_byte_identical_across_resumes(tmp_path):
    out = tmp_path / "b"
    run_batch(_spec(6), out, work=nan_work, backend=LocalPool(1), progress=False)
    csv = out / "results.csv"
    first = csv.read_bytes()
    assert b"nan" not in first.lower()  # NaN is blank, as it reads back from the JSON line
    run_batch(_spec(6), out, work=nan_work, backend=LocalPool(1), progress=False)
    assert csv.read_bytes() == first
    # a resume that does half the work writes what an uninterrupted run writes
    half = tmp_path / "half"
    half.mkdir()
    shutil.copy(out / "batch.json", half)
    lines = (out / "results.jsonl").read_bytes().splitlines(keepends=True)
    (half / "results.jsonl").write_bytes(b"".join(lines[:3]))
    s = run_batch(_spec(6), half, work=nan_work, backend=LocalPool(1), progress=False)
    assert (s.n_skipped, s.n_ok) == (3, 3)
    assert (half / "results.csv").read_bytes() == first


def test_csv_of_real_fits_unchanged_by_empty_resume(real_dir, tmp_path):
    d = _copy(real_dir, tmp_path)
    before = (d / "results.csv").read_bytes()
    run_batch(_spec(3, REAL), d, progress=False, backend=LocalPool(1))
    assert (d / "results.csv").read_bytes() == before


def test_every_output_file_has_one_mode(shards, tmp_path):
    old = os.umask(0o022)
    try:
        out = tmp_path / "b"
        run_batch(_spec(4), out, work=nan_work, backend=LocalPool(1), progress=False)
        assert main(["batch-report", str(out), "--no-plots", "-q"]) == 0
        files = ["batch.json", "results.jsonl", "results.csv", "report/report.md"]
        modes = {f: stat.S_IMODE((out / f).stat().st_mode) for f in files}
        assert modes == dict.fromkeys(files, 0o644)
        os.umask(0o027)
        other = tmp_path / "c"
        run_batch(_spec(4), other, work=nan_work, backend=LocalPool(1), progress=False)
        modes = {f: stat.S_IMODE((other / f).stat().st_mode) for f in files[:3]}
        assert modes == dict.fromkeys(files[:3], 0o640)
    finally:
        os.umask(old)


# --- fit.json whose stored beam was edited ---------------------------------------------------
def test_edited_fit_beam_names_the_fingerprint(tmp_path, capsys):
    out = tmp_path / "fit"
    assert main(["fit", str(ROOT / "examples" / "beams" / "tapered.json"), "--joints", "2",
                 "--stiffness", "joint", "--starts", "2", "--truth-model", "beam",
                 "--cache-dir", str(tmp_path / "cache"), "--out", str(out), "-q"]) == 0
    d = json.loads((out / "fit.json").read_text())
    d["beam"]["thickness"] *= 1.5
    (out / "fit.json").write_text(json.dumps(d))
    err = _exit2(capsys, ["simulate", str(out / "fit.json"), "--duration", "0.01", "--out",
                          str(tmp_path / "sim"), "-q"], "beam_fingerprint")
    assert "None" not in err


# --- fuzz: a results.jsonl line is a record that passes the checks or a BeamInputError --------
_scalar = st.one_of(st.none(), st.booleans(), st.integers(-10**40, 10**40),
                    st.floats(allow_nan=False), st.text(max_size=5))
_value = st.recursive(_scalar, lambda c: st.lists(c, max_size=3)
                      | st.dictionaries(st.text(max_size=3), c, max_size=3), max_leaves=6)
_keys = st.sampled_from(["beam_index", "status", "seed", "eigen_loss_pct", "gamma", "mass_kg",
                         "taper_ratio", "error", "joints", "lengths_m", "other"])


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.one_of(st.dictionaries(_keys, _value, max_size=6).map(
    lambda d: json.dumps(d).encode()), st.binary(max_size=40)))
def test_fuzz_results_line(tmp_path, line):
    path = tmp_path / "results.jsonl"
    path.write_bytes(line.replace(b"\n", b" ") + b"\n")
    try:
        recs = batch.read_records(path)
    except BeamInputError as exc:
        assert "line 1" in str(exc)
        return
    from prbdm_pin.batch import summarise

    for r in recs:
        assert isinstance(r["beam_index"], int) and r["beam_index"] >= 0
    summarise(recs)  # the report reads every accepted record without another exception
