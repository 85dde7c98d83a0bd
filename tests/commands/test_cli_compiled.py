"""``prbdm simulate --method compiled``: the command's trajectory is the API's "compiled" run
(the same equations and tolerances, written with repr), which follows scipy's DOP853 on
Pinocchio within the tolerances; a plant input with it is one line, exit 2."""

from __future__ import annotations

import numpy as np
from cli_strip_runs import strip_model_json, tip_z

import prbdm_pin as pp
from prbdm_pin.cli import main


def test_simulate_with_the_compiled_method(tmp_path):
    path = strip_model_json(tmp_path)
    args = ["simulate", str(path), "--duration", "0.1", "--initial-angle", "0.01",
            "--output-dt", "0.001", "--out"]
    assert main([*args, str(tmp_path / "c"), "--method", "compiled", "-q"]) == 0
    assert main([*args, str(tmp_path / "d"), "--method", "DOP853", "-q"]) == 0
    z, ref = tip_z(tmp_path / "c"), tip_z(tmp_path / "d")
    model = pp.load_model(str(path)).model
    api = pp.simulate(model, 0.1, q0=np.full(2, 0.01), output_dt_s=0.001, method="compiled")
    np.testing.assert_array_equal(z, api.tip_position_m[:, 2])
    # both at the command's rtol 1e-9 against each other: the tolerance times the growth over
    # the run's periods of the fastest mode (tests/simulation/test_compiled_integrator.py)
    w2 = np.linalg.eigvals(np.linalg.solve(model.mass_matrix(), model.stiffness_matrix())).real
    periods = max(1.0, float(np.sqrt(w2.max())) * 0.1 / (2 * np.pi))
    swing = np.abs(ref - ref[0]).max()
    assert np.abs(z - ref).max() <= 10 * periods * 2e-9 * swing


def test_a_plant_input_with_the_compiled_method_is_one_line(tmp_path, capsys):
    path = strip_model_json(tmp_path)
    code = main(["simulate", str(path), "--duration", "0.01", "--method", "compiled",
                 "--input", "tip_force_z=1", "--out", str(tmp_path / "x"), "-q"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "compiled" in err and "\n" not in err
    assert not (tmp_path / "x" / "trajectory.csv").exists()
