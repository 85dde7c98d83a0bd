"""``--json`` on every command: stdout is one JSON object whose numbers are the files' own, and
every JSON the package writes says which versions and which seed made it."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from paths import BEAMS

from prbdm_pin.cli import build_parser
from prbdm_pin.version import __version__

BEAM = str(BEAMS / "uniform-narrow.json")


def _run(*argv: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "prbdm_pin", *argv], capture_output=True,
                          text=True, timeout=300)


@pytest.fixture(scope="module")
def fit_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("json") / "fit"
    done = _run("fit", BEAM, "--joints", "3", "--truth-model", "beam", "--stiffness", "joint",
                "--objective", "combined", "--starts", "2", "--seed", "5", "--out", str(out),
                "--json")
    assert done.returncode == 0, done.stderr
    return out, json.loads(done.stdout)  # stdout is the object and nothing else


def test_every_command_takes_json():
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    for name, parser in sub.choices.items():
        assert any("--json" in a.option_strings for a in parser._actions), name


def test_fit_json_summary_is_the_files_own(fit_dir):
    out, doc = fit_dir
    fit = json.loads((out / "fit.json").read_text())
    assert doc["command"] == "fit" and doc["exit_code"] == 0
    assert doc["versions"]["prbdm_pin"] == __version__
    assert "fit.json" in doc["files"] and doc["seed"] == fit["seed"] == 5
    for key in ("worst_mode_error_pct", "eigen_loss_pct", "combined_loss_pct", "lengths_m",
                "stiffness_Nm_per_rad", "omega_truth_rad_s"):
        assert doc["summary"][key] == fit[key], key


def test_json_files_record_versions_and_seed(fit_dir, tmp_path):
    out, _ = fit_dir
    fit = str(out / "fit.json")
    for argv, name in ((["statics", fit, "--tip-force", "0,0,-10"], "statics.json"),
                       (["linearize", fit], "linear_model.json"),
                       (["truth", BEAM, "--model", "beam", "--modes", "2"], "truth.json")):
        d = tmp_path / name.split(".")[0]
        done = _run(*argv, "--out", str(d), "--json")
        assert done.returncode == 0, done.stderr
        rec = json.loads((d / name).read_text())
        assert rec["versions"]["prbdm_pin"] == __version__, name
        # the fit's seed travels with the model; a truth draws nothing
        assert rec["seed"] == (None if name == "truth.json" else 5), name
        summary = json.loads(done.stdout)["summary"]
        assert summary and all(summary[k] == rec[k] for k in summary), name
    model = tmp_path / "model.json"
    assert _run("export", fit, "--format", "json", "--out", str(model)).returncode == 0
    rec = json.loads(model.read_text())
    assert rec["versions"]["prbdm_pin"] == __version__ and rec["seed"] == 5


def test_export_json_of_a_urdf_reads_its_record(fit_dir, tmp_path):
    out, _ = fit_dir
    done = _run("export", str(out / "fit.json"), "--format", "urdf", "--out",
                str(tmp_path / "m.urdf"), "--json")
    assert done.returncode == 0, done.stderr
    doc = json.loads(done.stdout)
    fit = json.loads((out / "fit.json").read_text())
    assert doc["files"] == ["m.urdf"]
    assert doc["summary"]["worst_mode_error_pct"] == pytest.approx(
        fit["worst_export_error_pct"], rel=1e-9)  # the record is written with repr's digits


def test_refused_command_prints_the_object_with_the_error(tmp_path):
    done = _run("statics", str(tmp_path / "missing.json"), "--out", str(tmp_path / "o"),
                "--json")
    assert done.returncode == 2
    doc = json.loads(done.stdout)
    assert doc["exit_code"] == 2 and "missing.json" in doc["error"]
    assert doc["files"] == [] and not (tmp_path / "o").exists()
    assert len(done.stderr.strip().splitlines()) == 1
