"""``prbdm simulate``'s default method "auto": the integrator the rule picked is the one the
command ran (its trajectory is the API's run with that integrator, bit for bit) and
``simulation.json`` records it; within the default's tolerance of scipy's DOP853; a bad
``--method`` is one line, exit 2, nothing written."""

from __future__ import annotations

import json

import numpy as np
from cli_strip_runs import strip_model_json, tip_z

import prbdm_pin as pp
from prbdm_pin.cli import main


def test_the_default_records_the_integrator_it_ran(tmp_path):
    path = strip_model_json(tmp_path)
    args = ["simulate", str(path), "--duration", "0.1", "--initial-angle", "0.01",
            "--output-dt", "0.001", "-q", "--out"]
    assert main([*args, str(tmp_path / "a")]) == 0
    assert main([*args, str(tmp_path / "d"), "--method", "DOP853"]) == 0
    rec = json.loads((tmp_path / "a" / "simulation.json").read_text())
    # a 2R release, undamped-or-lightly damped: the rule's compiled DOP853 at 1e-4 / 100
    assert rec["method_asked"] == "auto" and rec["method"] == "compiled"
    assert rec["integrator"] == {"type": "Compiled", "rtol": 1e-6, "atol": None}
    model = pp.load_model(str(path)).model
    api = pp.simulate(model, 0.1, q0=np.full(2, 0.01), output_dt_s=0.001,
                      integrator=pp.Compiled(rtol=rec["integrator"]["rtol"]))
    z = tip_z(tmp_path / "a")
    # the command wrote the API's run with the recorded integrator (repr round trip: exact)
    np.testing.assert_array_equal(z, api.tip_position_m[:, 2])
    assert rec["steps"] == api.steps
    ref = tip_z(tmp_path / "d")
    # Auto's tolerance: 1e-4 of the peak tip motion (against DOP853 at the command's 1e-9)
    assert np.abs(z - ref).max() <= 1e-4 * np.abs(ref - ref[0]).max()
    named = json.loads((tmp_path / "d" / "simulation.json").read_text())
    assert named["method_asked"] == named["method"] == "DOP853"
    assert named["integrator"]["type"] == "ScipyIVP" and named["integrator"]["rtol"] == 1e-9


def test_a_bad_method_is_one_line(tmp_path, capsys):
    path = strip_model_json(tmp_path)
    code = main(["simulate", str(path), "--duration", "0.01", "--method", "automatic",
                 "--out", str(tmp_path / "x"), "-q"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "--method" in err and "auto" in err and "\n" not in err
    assert not (tmp_path / "x").exists()
