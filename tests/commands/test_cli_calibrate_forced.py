"""``prbdm calibrate`` on an FRF CSV and a driven-trajectory CSV of the scaled 1D beam truth
(``forced_truth``): the data's kind told by the header, calibration.json and the plot written,
the frequencies the scaled truth's; bad files exit 2 with one line and write nothing."""

import json

import numpy as np
import pytest
from forced_truth import truth_driven, truth_frf

from prbdm_pin.cli import main
from prbdm_pin.truth.plant import clamped_model

S_E, S_RHO, ZETA = 0.95, 1.03, np.array([0.01, 0.005, 0.02, 0.02])


@pytest.fixture(scope="module")
def fit_json(strip_fit):
    return strip_fit(5) / "fit" / "fit.json"


@pytest.fixture(scope="module")
def plant(narrow, truth_of):
    return clamped_model(truth_of(narrow, model="beam", modes=4, static=False,
                                  error_tol_pct=None), narrow, damping_ratio=0.0)


def _csv(path, head, cols):
    rows = [",".join(head)] + [",".join(repr(float(v)) for v in r) for r in cols]
    path.write_text("\n".join(rows) + "\n")
    return path


def _run(fit_json, data, params, out, *extra):
    return main(["calibrate", str(fit_json), "--data", str(data), "--parameters", params,
                 *extra, "--out", str(out), "-q"])


def test_an_frf_file_is_calibrated(fit_json, plant, narrow, tmp_path):
    f = np.linspace(2.0, 80.0, 300)
    H = truth_frf(plant, S_E, S_RHO, ZETA, f, ("base_accel_z",))[:, 0, 0]
    rng = np.random.default_rng(0)
    # complex noise of one size (the standard errors' model): 1 % of the RMS
    H = H + 0.01 * np.sqrt(np.mean(np.abs(H) ** 2)) * (rng.standard_normal(f.size)
                                                        + 1j * rng.standard_normal(f.size))
    data = _csv(tmp_path / "frf.csv", ["f_hz", "tip_z_m/base_accel_z_m_s2_re",
                                       "tip_z_m/base_accel_z_m_s2_im"],
                np.column_stack([f, H.real, H.imag]))
    out = tmp_path / "cal"
    assert _run(fit_json, data, "E,damping[0],damping[1]", out) == 0
    rec = json.loads((out / "calibration.json").read_text())
    assert rec["data"] == "frf" and rec["inputs"] == ["base_accel_z"]
    assert list(rec["residual_rms"]) == ["tip_z/base_accel_z"]
    assert (out / "calibration.png").stat().st_size > 0
    p = rec["parameters"]
    # a base acceleration sees E/rho; one seed: a 3-sigma miss has probability 0.3 %
    want = narrow.material.E_Pa * S_E / S_RHO
    assert abs(p["E"]["value"] - want) <= 3 * p["E"]["std_error"], (p, want)
    w = np.array(rec["omega_rad_s"][:2])
    # omega ~ sqrt(E): half E's relative standard error; 3 of them (the eigen fit's own
    # frequency error, 1e-14, is far below)
    rel = 0.5 * p["E"]["std_error"] / p["E"]["value"]
    np.testing.assert_array_less(np.abs(w / (plant.frequencies_rad_s[:2]
                                             * np.sqrt(S_E / S_RHO)) - 1), 3 * rel)


def test_a_driven_file_with_the_trajectory_csv_spelling_is_calibrated(fit_json, plant, narrow,
                                                                       tmp_path):
    t = np.arange(750) / 250.0
    u = np.random.default_rng(1).standard_normal((t.size, 1))
    y = truth_driven(plant, S_E, S_RHO, ZETA, t, u, ("base_accel_z",))[:, :1]
    y = y + 0.01 * np.abs(y).max() * np.random.default_rng(2).standard_normal(y.shape)
    data = _csv(tmp_path / "run.csv", ["t_s", "u:base_accel_z", "y:tip_z"],
                np.column_stack([t, u, y]))
    out = tmp_path / "cal"
    assert _run(fit_json, data, "E,damping[0]", out) == 0
    rec = json.loads((out / "calibration.json").read_text())
    assert rec["data"] == "driven" and rec["samples"] == 750 and rec["channels"] == ["tip_z"]
    p = rec["parameters"]["E"]
    # one seed: a 3-sigma miss has probability 0.3 %
    assert abs(p["value"] - narrow.material.E_Pa * S_E / S_RHO) <= 3 * p["std_error"]


_F = [f"{1.0 + i}" for i in range(12)]


@pytest.mark.parametrize("text, needle", [
    ("f_hz,tip_z/tip_force_z_re\n" + "".join(f"{f},0.1\n" for f in _F),
     "tip_z/tip_force_z_re: no imaginary column tip_z/tip_force_z_im"),
    ("f_hz,tip_z/tip_force_z_re,tip_z/tip_force_z_im\n"
     + "".join(f"{f},0.1,{'nan' if i == 3 else 0.2}\n" for i, f in enumerate(_F)),
     "tip_z/tip_force_z_im: not finite at row 3"),
    ("f_hz,tip_z/tip_force_z_re,tip_z/tip_force_z_im\n"
     + "".join(f"{f},0.1,0.2\n" for f in _F[:6] + _F[:6]), "f_hz: not increasing at row 6"),
    ("f_hz,tip_z/foo_re,tip_z/foo_im\n" + "".join(f"{f},0.1,0.2\n" for f in _F),
     "'foo' is not an input of linearize"),
    ("t_s,u:tip_z,tip_z_m\n" + "".join(f"{0.01 * i},1,{np.cos(i)}\n" for i in range(12)),
     "u:tip_z: not an input of linearize"),
    ("t_s,tip_force_z_N,tip_z_m\n" + "".join(f"{0.01 * i},1,{np.cos(i)}\n" for i in range(5)),
     "t_s: 5 samples; need at least 8"),
    ("t_s,tip_force_z_N\n" + "".join(f"{0.01 * i},1\n" for i in range(12)),
     "no measured output column"),
])
def test_bad_files_exit_2_with_one_line_and_write_nothing(fit_json, tmp_path, capsys, text,
                                                          needle):
    data = tmp_path / "bad.csv"
    data.write_text(text)
    out = tmp_path / "never"
    assert main(["calibrate", str(fit_json), "--data", str(data), "--parameters", "E",
                 "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("prbdm calibrate: error: "), err
    assert needle in err, err
    assert not out.exists()


@pytest.mark.parametrize("extra, needle", [
    (["--modes", "2"], "--modes = 2: the modes whose initial state is fitted"),
    (["--initial-state"], "--initial-state: an FRF has no initial state"),
])
def test_initial_state_options_on_an_frf_exit_2(fit_json, tmp_path, capsys, extra, needle):
    f = np.linspace(5.0, 12.0, 10)
    H = 1.0 / (52.0**2 - (2 * np.pi * f) ** 2 + 2j * 0.01 * 52.0 * 2 * np.pi * f)
    data = _csv(tmp_path / "frf.csv", ["f_hz", "tip_z/tip_force_z_re", "tip_z/tip_force_z_im"],
                np.column_stack([f, H.real, H.imag]))
    out = tmp_path / "never"
    assert main(["calibrate", str(fit_json), "--data", str(data), "--parameters", "E", *extra,
                 "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err, err
    assert not out.exists()


def test_too_few_samples_for_the_unknowns_exit_2(fit_json, tmp_path, capsys):
    t = np.arange(8) / 250.0
    data = _csv(tmp_path / "run.csv", ["t_s", "tip_force_z_N", "tip_z_m"],
                np.column_stack([t, np.sin(40 * t), np.cos(50 * t)]))
    out = tmp_path / "never"
    # 3 parameters and the initial state of 3 modes (6) against 8 samples
    assert main(["calibrate", str(fit_json), "--data", str(data), "--parameters",
                 "E,damping[0],damping[1]", "--initial-state", "--modes", "3", "--out",
                 str(out)]) == 2
    err = capsys.readouterr().err
    assert "t_s: 8 samples x 1 channel(s) for 9 unknowns" in err, err
    assert not out.exists()
