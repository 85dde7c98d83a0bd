"""``prbdm fit --gravity`` end to end: fit.json, model.urdf and the MJCF export carry the gravity;
bad input is one line and exit 2 with nothing written.

The fitted numbers are checked against the truth in gravity and in MuJoCo in
tests/fitting/test_gravity_fit.py; here the command's files are compared with the API's
truth in gravity (:func:`prbdm_pin.fitting.gravity_target.gravity_target`)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from prbdm_pin.cli import main
from prbdm_pin.fitting.gravity_target import gravity_target
from prbdm_pin.fitting.result import EXACT_MATCH_PCT

BEAM = "examples/beams/uniform-narrow.json"
FIT = ["fit", BEAM, "--joints", "2", "--truth-model", "beam", "--stiffness", "joint",
       "--starts", "2", "-q"]


def test_fit_in_gravity_writes_it_everywhere(narrow, tmp_path):
    out = tmp_path / "fit"
    assert main([*FIT, "--objective", "eigen", "--gravity", "0,0,-9.81",
                 "--out", str(out)]) == 0
    d = json.loads((out / "fit.json").read_text())
    assert d["gravity_m_s2"] == [0.0, 0.0, -9.81]
    assert d["truth_request"] is None  # compute_truth has no gravity: nothing to look up
    t = gravity_target(narrow, [0.0, 0.0, -9.81], modes=2)
    # the truth the command fitted is the API's in the same gravity, to the last bit (same
    # solves, written in full)
    assert d["omega_truth_rad_s"] == t.omega_truth_rad_s.tolist()
    assert d["tip_position_truth_m"] == t.tip_position_m.tolist()
    # 2 frequencies with 2 joints: matched to the fit's exact-match level
    np.testing.assert_allclose(d["omega_model_rad_s"][0], d["omega_truth_rad_s"],
                               rtol=EXACT_MATCH_PCT / 100)
    urdf = (out / "model.urdf").read_text()
    assert "fitted in gravity_m_s2: 0.0 0.0 -9.81" in urdf
    xml = tmp_path / "m.xml"
    assert main(["export", str(out / "fit.json"), "--format", "mjcf", "--out", str(xml),
                 "-q"]) == 0
    assert '<option gravity="0.0 0.0 -9.81"' in xml.read_text()
    # carried on through the model JSON and the URDF (its comment) into the MJCF
    prev = out / "fit.json"
    for name, fmt in (("m.json", "json"), ("m.urdf", "urdf"), ("again.xml", "mjcf")):
        assert main(["export", str(prev), "--format", fmt, "--out", str(tmp_path / name),
                     "-q"]) == 0
        prev = tmp_path / name
    assert '<option gravity="0.0 0.0 -9.81"' in prev.read_text()
    # a URDF whose comment was edited to an absurd gravity is refused by name
    bad = tmp_path / "bad.urdf"
    bad.write_text((tmp_path / "m.urdf").read_text().replace(
        "gravity_m_s2: 0.0 0.0 -9.81", "gravity_m_s2: 0.0 0.0 -9810.0"))
    assert main(["export", str(bad), "--format", "mjcf", "--out", str(tmp_path / "b.xml"),
                 "-q"]) == 2
    assert not (tmp_path / "b.xml").exists()


def test_a_fit_without_gravity_exports_none(tmp_path):
    out = tmp_path / "plain"
    assert main([*FIT, "--out", str(out)]) == 0
    assert "gravity_m_s2" not in json.loads((out / "fit.json").read_text())
    xml = tmp_path / "m.xml"
    assert main(["export", str(out / "fit.json"), "--format", "mjcf", "--out", str(xml),
                 "-q"]) == 0
    assert '<option gravity="0 0 0"' in xml.read_text()


@pytest.mark.parametrize("argv, msg", [
    (["--gravity", "0,0,-9810"], "above 1000 m/s^2"),          # a unit slip (mm/s^2)
    (["--gravity", "0,0,nan"], "--gravity"),
    (["--gravity", "0,-9.81"], "--gravity"),
    (["--gravity", "0,9.81,0"], "g_y must be 0"),
    (["--gravity", "0,0,-9.81", "--truth-model", "plate"], "--truth-model"),
    (["--gravity", "0,0,-9.81", "--stiffness", "paper"], "--stiffness"),
    (["--gravity", "0,0,-9.81", "--extra-loads", "2"], "--extra-loads"),
    (["--gravity", "-5000,0,0", "--truth-model", "beam"], "above"),
])
def test_bad_gravity_exit_2(tmp_path, capsys, argv, msg):
    rc = main([*FIT, *argv, "--out", str(tmp_path / "x")])
    assert rc == 2
    err = capsys.readouterr().err.strip()
    assert msg in err and len(err.splitlines()) == 1
    assert not (tmp_path / "x").exists()


def test_plant_commands_run_a_gravity_fit_in_its_gravity(tmp_path):
    """statics, linearize and simulate of a fit made in gravity default to that gravity (its
    springs hold the member about the sag): the same numbers as with --gravity given, and the
    straight member with --gravity 0,0,0."""
    out = tmp_path / "fit"
    assert main([*FIT, "--objective", "eigen", "--gravity", "0,0,-9.81",
                 "--out", str(out)]) == 0
    fit = str(out / "fit.json")

    def statics(*extra):
        d = tmp_path / f"s{len(list(tmp_path.iterdir()))}"
        assert main(["statics", fit, *extra, "--out", str(d), "-q"]) == 0
        return json.loads((d / "statics.json").read_text())

    default, given, none = statics(), statics("--gravity", "0,0,-9.81"), \
        statics("--gravity", "0,0,0")
    # the same solve either way: equal to the last bit
    assert default["q_rad"] == given["q_rad"] and default["tip_position_m"][2] < 0.0
    assert not any(none["q_rad"])

    def linearize(*extra):
        d = tmp_path / f"l{len(list(tmp_path.iterdir()))}"
        assert main(["linearize", fit, *extra, "--out", str(d), "-q"]) == 0
        return json.loads((d / "linear_model.json").read_text())

    lin_default, lin_given = linearize(), linearize("--gravity", "0,0,-9.81")
    assert lin_default["gravity_m_s2"] == lin_given["gravity_m_s2"] == [0.0, 0.0, -9.81]
    assert lin_default["q_eq_rad"] == lin_given["q_eq_rad"]
