"""``prbdm fit`` and ``prbdm pareto`` end to end, with an independent truth file (Euler-Bernoulli
frequencies and the elastica tip of uniform-narrow.json at P L^2/EI = 1)."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest
from reference import ELASTICA

from prbdm_pin.cli import main
from prbdm_pin.files.urdf_file import load_urdf

BEAM = "examples/beams/uniform-narrow.json"


@pytest.fixture(scope="module")
def truth_file(strip_truth):
    return strip_truth


def test_fit_writes_fit_json_urdf_and_plots(truth_file, tmp_path):
    path, omega, tip = truth_file
    out = tmp_path / "fit"
    rc = main(["fit", BEAM, "--joints", "2", "--objective", "eigen", "--stiffness", "joint",
               "--starts", "3", "--seed", "1", "--truth", str(path), "--out", str(out), "-q"])
    assert rc == 0
    d = json.loads((out / "fit.json").read_text())
    for key in ("joints", "lengths_m", "stiffness_Nm_per_rad", "scf_mean", "omega_truth_rad_s",
                "omega_model_rad_s", "eigen_loss_pct", "deflection_loss_pct",
                "displacement_loss_pct", "combined_loss_pct", "seed", "wall_time_s",
                "versions", "mac"):
        assert key in d, key
    assert d["joints"] == 2 and d["seed"] == 1
    assert d["eigen_loss_pct"] <= 1e-6
    # the exported URDF (springs read back from it) reproduces the Euler-Bernoulli frequencies
    model = load_urdf(out / "model.urdf")
    assert model.natural_frequencies() == pytest.approx(omega[:2], rel=1e-8)
    # the reported tip error is the distance to the elastica tip
    p = np.array(d["tip_position_model_m"][0])
    assert d["deflection_loss_pct"] == pytest.approx(
        100 * np.linalg.norm(p - tip) / np.linalg.norm(tip), rel=1e-9)
    assert (out / "planform.png").stat().st_size > 1000
    assert not list(out.glob(".*tmp"))


def test_fit_paper_writes_scf_plot(truth_file, tmp_path):
    path, _, _ = truth_file
    out = tmp_path / "paper"
    rc = main(["fit", BEAM, "--joints", "2", "--stiffness", "paper", "--starts", "2",
               "--truth", str(path), "--out", str(out), "-q"])
    assert rc == 0
    d = json.loads((out / "fit.json").read_text())
    assert len(d["factors"]) == len(d["poses_rad"]) == len(d["stiffness_per_pose_Nm_per_rad"])
    assert d["scf_mean"] == pytest.approx(np.mean(d["factors"]))
    assert (out / "scf.png").is_file()


def test_pareto_writes_front_and_knee(truth_file, tmp_path, capsys):
    path, omega, _ = truth_file
    out = tmp_path / "pareto"
    rc = main(["pareto", BEAM, "--joints", "2", "--stiffness", "joint", "--pop", "12",
               "--generations", "3", "--truth", str(path), "--out", str(out),
               "--eigen-norm", "relative"])
    assert rc == 0
    text = capsys.readouterr().out
    # the worst mode beside the loss: the knee's URDF frequencies against the truth file
    w = load_urdf(out / "model.urdf").natural_frequencies()
    e = 100 * (w / omega[:2] - 1)
    k = int(np.argmax(np.abs(e)))
    assert f"worst mode {e[k]:+.3g} % (mode {k + 1})" in text
    assert "(relative norm)" in text
    rows = list(csv.DictReader((out / "pareto.csv").open()))
    comb = [math.hypot(float(r["eigen_loss_pct"]), float(r["deflection_loss_pct"]))
            for r in rows]
    knee = [r for r in rows if r["knee"] == "1"]
    assert len(knee) == 1 and float(knee[0]["combined_loss_pct"]) == pytest.approx(min(comb))
    d = json.loads((out / "fit.json").read_text())
    assert d["combined_loss_pct"] == pytest.approx(min(comb), rel=1e-6)
    assert d["eigen_norm"] == "relative"
    assert json.loads((out / "pareto.json").read_text())["eigen_norm"] == "relative"
    assert (out / "model.urdf").is_file() and (out / "pareto.png").is_file()


@pytest.mark.parametrize("argv, msg", [
    (["--joints", "0"], "joints"),
    (["--joints", "2", "--frequencies", "3"], "frequencies"),
    (["--joints", "2", "--starts", "0"], "starts"),
])
def test_bad_input_exit_2(truth_file, tmp_path, capsys, argv, msg):
    path, _, _ = truth_file
    rc = main(["fit", BEAM, *argv, "--truth", str(path), "--out", str(tmp_path / "x"), "-q"])
    assert rc == 2
    assert msg in capsys.readouterr().err
    assert not (tmp_path / "x" / "fit.json").exists()


def test_missing_truth_file_is_an_input_error(tmp_path, capsys):
    rc = main(["fit", BEAM, "--joints", "2", "--truth", str(tmp_path / "nope.json"),
               "--out", str(tmp_path / "x"), "-q"])
    assert rc == 2 and "truth" in capsys.readouterr().err


def test_fit_json_alone_drives_export_and_simulate(truth_file, tmp_path):
    """fit.json carries its beam: export and simulate need no --beam, and the exported model has
    the Euler-Bernoulli frequencies the fit matched."""
    from prbdm_pin.files.beam_file import load_beam
    from prbdm_pin.files.fit_file import fit_beam

    path, omega, _ = truth_file
    out = tmp_path / "fit"
    assert main(["fit", BEAM, "--joints", "2", "--objective", "eigen", "--stiffness", "joint",
                 "--starts", "2", "--seed", "0", "--truth", str(path), "--out", str(out),
                 "-q"]) == 0
    d = json.loads((out / "fit.json").read_text())
    assert fit_beam(d).fingerprint() == load_beam(BEAM).fingerprint()
    urdf = tmp_path / "model.urdf"
    assert main(["export", str(out / "fit.json"), "--format", "urdf", "--out", str(urdf),
                 "-q"]) == 0
    assert load_urdf(urdf).natural_frequencies() == pytest.approx(omega[:2], rel=1e-8)
    sim = tmp_path / "sim"
    assert main(["simulate", str(out / "fit.json"), "--duration", "0.05", "--out", str(sim),
                 "-q"]) == 0
    assert (sim / "trajectory.csv").stat().st_size > 100


def test_fit_with_extra_loads_matches_the_elastica_table(tmp_path):
    # uniform-narrow.json carries P L^2/EI = 1; --extra-loads 2,5 adds the table's rows
    # alpha^2 = 2 and 5
    out = tmp_path / "fit"
    rc = main(["fit", BEAM, "--joints", "3", "--objective", "combined", "--stiffness", "joint",
               "--truth-model", "beam", "--extra-loads", "2,5", "--starts", "4", "--seed", "0",
               "--cache-dir", str(tmp_path / "cache"), "--out", str(out), "-q"])
    assert rc == 0
    d = json.loads((out / "fit.json").read_text())
    F = np.array(d["tip_force_N"])
    np.testing.assert_allclose(d["extra_tip_force_N"], [2 * F, 5 * F])
    truth = np.array(d["extra_tip_position_truth_m"])
    for row, (retreat, deflection) in zip(truth, [ELASTICA[2.0], ELASTICA[5.0]],
                                          strict=True):
        assert row == pytest.approx([1 - retreat, 0.0, -deflection], abs=2e-5)
    # the deflection loss is the mean over the three load cases of the relative tip error
    tips = [np.array(d["tip_position_model_m"][0])] + [np.array(t[0]) for t in
                                                      d["extra_tip_position_model_m"]]
    refs = [np.array(d["tip_position_truth_m"])] + list(truth)
    errs = [np.linalg.norm(p - t) / np.linalg.norm(t) for p, t in zip(tips, refs, strict=True)]
    assert d["deflection_loss_pct"] == pytest.approx(100 * np.mean(errs), rel=1e-9)
    # a 3R chain follows the elastica over P L^2/EI = 1...5 to a fraction of a percent
    assert d["deflection_loss_pct"] < 0.5


def test_extra_loads_bad_input_exit_2(tmp_path, capsys):
    rc = main(["fit", BEAM, "--joints", "2", "--truth-model", "beam", "--extra-loads", "2,x",
               "--out", str(tmp_path / "o"), "-q"])
    assert rc == 2
    assert "extra-loads" in capsys.readouterr().err
