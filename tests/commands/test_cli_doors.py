"""The command line's doors: values that argparse took for options (``--hub -1:0.1``), empty
design names, sweep angles beyond a quarter turn and strain patches between joints are refused
with one line naming the option, exit code 2, and nothing written."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from paths import ROOT

from prbdm_pin.cli import main

BEAM = str(ROOT / "examples" / "beams" / "uniform-narrow.json")


@pytest.fixture(scope="module")
def fit_json(tmp_path_factory):
    root = tmp_path_factory.mktemp("fit")
    rc = main(["fit", BEAM, "--joints", "3", "--truth-model", "beam", "--stiffness", "joint",
               "--starts", "2", "--cache-dir", str(root / "cache"), "--out", str(root / "fit"),
               "-q"])
    assert rc == 0
    return root / "fit" / "fit.json"


def _refused(capsys, argv, *needles, out: Path):
    before = sorted(out.parent.rglob("*"))
    rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.count("\n") == 1 and err.startswith(f"prbdm {argv[0]}: error: "), err
    for needle in needles:
        assert needle in err, (needle, err)
    assert "expected one argument" not in err
    assert not out.exists() and sorted(out.parent.rglob("*")) == before
    return err


@pytest.mark.parametrize("spaced", [True, False])
def test_a_negative_hub_inertia_reaches_the_hubs_own_check(fit_json, tmp_path, capsys, spaced):
    out = tmp_path / "lin"
    hub = ["--hub", "-1:0.1"] if spaced else ["--hub=-1:0.1"]
    _refused(capsys, ["linearize", str(fit_json), *hub, "--out", str(out)],
             "--hub = '-1:0.1'", "inertia_kg_m2 = -1.0", "> 0", out=out)
    _refused(capsys, ["linearize", str(fit_json), "--hub", "1:-0.1", "--out", str(out)],
             "--hub = '1:-0.1'", "radius_m = -0.1", out=out)


def test_dash_values_of_other_options_reach_their_checks(fit_json, tmp_path, capsys):
    out = tmp_path / "sim"
    # the tip force -10,0,0 is parsed; the run is refused for its duration, by name
    _refused(capsys, ["simulate", str(fit_json), "--tip-force", "-10,0,0", "--duration", "-1",
                      "--out", str(out)], "--duration = -1", out=out)
    _refused(capsys, ["simulate", str(fit_json), "--duration", "0.1", "--actuator",
                      "-0.1:0.5", "--out", str(out)], "--actuator = '-0.1:0.5'",
             "x_start_m = -0.1", out=out)


@pytest.mark.parametrize("design, position", [("thickness,,E", "variable 2 of 3"),
                                              ("thickness,E,", "variable 3 of 3"),
                                              (",E", "variable 1 of 2")])
def test_an_empty_design_name_is_refused(tmp_path, capsys, design, position):
    out = tmp_path / "sens"
    _refused(capsys, ["sensitivity", BEAM, "--design", design, "--out", str(out)],
             f"--design '{design}'", position, "empty", out=out)


@pytest.mark.parametrize("option, value", [("--eps", "1e300"), ("--eps", "2"),
                                           ("--xi", "1e300")])
def test_sweep_angles_beyond_a_quarter_turn_are_refused(tmp_path, capsys, option, value):
    out = tmp_path / "fit"
    _refused(capsys, ["fit", BEAM, "--joints", "2", "--truth-model", "beam", option, value,
                      "--out", str(out)], f"{option} = {float(value):g}", "1.5708", out=out)


@pytest.mark.parametrize("command", ["linearize", "simulate", "export"])
def test_a_patch_between_joints_is_refused_naming_the_nearest_joints(fit_json, tmp_path,
                                                                     capsys, command):
    stations = np.cumsum(json.loads(fit_json.read_text())["lengths_m"])[:-1]
    a = 0.0
    b = 0.5 * stations[0]  # from the root to half way to the first joint
    out = tmp_path / ("m.urdf" if command == "export" else "o")
    extra = {"linearize": ["--inputs", "strain[0]"],
             "simulate": ["--duration", "0.01", "--input", "strain[0]=1"],
             "export": ["--format", "urdf"]}[command]
    err = _refused(capsys, [command, str(fit_json), "--actuator", f"{a}:{b}", *extra,
                            "--out", str(out)],
                   f"--actuator = '{a}:{b}'", "holds no joint", f"{stations[0]:.6g} m",
                   out=out)
    assert "--fit-actuators" in err
