"""``prbdm calibrate``: a ring-down CSV of the scaled 1D beam truth in, calibration.json and a
calibrated model JSON out whose frequencies are the scaled truth's; bad data exits 2 with one
line and writes nothing."""

import json

import numpy as np
import pytest
import scipy.linalg as sla
from ring_down_truth import truth_ring_down

import prbdm_pin as pp
from prbdm_pin.cli import main
from prbdm_pin.truth.plant import clamped_model

S_E, S_RHO, ZETA = 0.93, 1.02, np.array([0.01, 0.004])


@pytest.fixture(scope="module")
def fit_json(strip_fit):
    return strip_fit(5) / "fit" / "fit.json"


@pytest.fixture(scope="module")
def plant(narrow, truth_of):
    return clamped_model(truth_of(narrow, model="beam", modes=4, static=False,
                                  error_tol_pct=None), narrow, damping_ratio=0.0)


def _csv(path, t, cols, names):
    rows = [",".join(["t_s", *names])]
    rows += [",".join(repr(float(v)) for v in r) for r in np.column_stack([t, cols])]
    path.write_text("\n".join(rows) + "\n")
    return path


def test_calibrated_model_rings_at_the_scaled_truth_s_frequencies(fit_json, plant, narrow,
                                                                   tmp_path):
    t = np.arange(750) / 250.0
    y = truth_ring_down(plant, S_E, S_RHO, ZETA, t, [0.04, -0.01, 0.2, 0.5], rates=True)
    y = y + 0.01 * np.abs(y).max(axis=0) * np.random.default_rng(3).standard_normal(y.shape)
    data = _csv(tmp_path / "ring.csv", t, y, ["tip_z_m", "tip_z_rate_m_s"])
    out = tmp_path / "cal"
    assert main(["calibrate", str(fit_json), "--data", str(data), "--parameters",
                 "E,damping[0],damping[1]", "--out", str(out), "-q"]) == 0
    rec = json.loads((out / "calibration.json").read_text())
    p = rec["parameters"]
    assert set(p) == {"E", "damping[0]", "damping[1]"}
    assert set(rec["residual_rms"]) == {"tip_z", "tip_z_rate"}
    assert (out / "calibration.png").stat().st_size > 0
    # the written model, read back: omega = the truth's sqrt(s_E / s_rho) (ring_down_truth)
    model = pp.read_model_json(out / "model.json")
    lin = pp.linearize(model, damping_ratio=0.0)
    w = np.sqrt(sla.eigh(lin.stiffness_Nm_per_rad, lin.mass_kg_m2, eigvals_only=True))[:2]
    want = plant.frequencies_rad_s[:2] * np.sqrt(S_E / S_RHO)
    # omega ~ sqrt(E): its relative standard error is half E's; 3 sigma for one seed (0.3 %)
    rel = 0.5 * p["E"]["std_error"] / p["E"]["value"]
    np.testing.assert_array_less(np.abs(w / want - 1), 3 * rel)
    for k in range(2):
        assert abs(p[f"damping[{k}]"]["value"] - ZETA[k]) <= 3 * p[f"damping[{k}]"]["std_error"]
    ratios = json.loads((out / "model.json").read_text())["damping"]
    assert ratios["form"] == "modal" and ratios["ratio"][2:] == [0.02] * 3


@pytest.mark.parametrize("text, argv_params, needle", [
    ("t_s,tip_z_m\n0,1\n0.01,nan\n" + "".join(f"{0.01 * i},0.5\n" for i in range(2, 12)),
     "E", "tip_z_m: not finite at row 1"),
    ("t_s,tip_z_m\n" + "".join(f"{0.01 * (i % 6)},{np.cos(i)}\n" for i in range(12)),
     "E", "t_s: not increasing at row 6"),
    ("t_s,tip_z_m\n0,1\n0.01,0.5\n", "E", "t_s: 2 samples; need at least 8"),
    ("t_s,tip_z_m\n" + "".join(f"{0.004 * i},{np.exp(-0.1 * i) * np.cos(0.2 * i)}\n"
                               for i in range(200)),
     "E,rho", "E, rho not determined"),
])
def test_bad_data_exits_2_with_one_line_and_writes_nothing(fit_json, tmp_path, capsys, text,
                                                           argv_params, needle):
    data = tmp_path / "bad.csv"
    data.write_text(text)
    out = tmp_path / "never"
    assert main(["calibrate", str(fit_json), "--data", str(data), "--parameters", argv_params,
                 "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("prbdm calibrate: error: "), err
    assert needle in err
    assert not out.exists()


@pytest.mark.parametrize("column, extra, needle", [
    ("tip_z_m", ["--parameters", "E", "--modes", "0"], "--modes = 0"),
    ("tip_z_m", ["--parameters", "E,nu"], "parameters[1] = 'nu'"),
    ("tip_z_m", ["--parameters", "E,offset[tip_x_m]"], "no channel 'tip_x'"),
    ("foo_m", ["--parameters", "E"], "data: the channels (foo) are outputs: outputs[0] = 'foo': "
                                     "unknown"),
])
def test_bad_options_exit_2_with_one_line_and_write_nothing(fit_json, tmp_path, capsys, column,
                                                            extra, needle):
    t = np.arange(100) / 250.0
    data = _csv(tmp_path / "ring.csv", t, np.exp(-t) * np.cos(52 * t), [column])
    out = tmp_path / "never"
    assert main(["calibrate", str(fit_json), "--data", str(data), *extra, "--out",
                 str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err, err
    assert not out.exists()
