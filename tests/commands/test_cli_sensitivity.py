"""``prbdm sensitivity``: gradients written against the truth and the closed-form scalings; bad
input refused in one line with exit code 2."""

from __future__ import annotations

import json

import numpy as np
import pytest
from paths import BEAMS
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.cli import main

BEAM = str(BEAMS / "tapered.json")


def test_sensitivity_writes_gradients(tmp_path):
    out = tmp_path / "sens"
    rc = main(["sensitivity", BEAM, "--design", "thickness,half_width[1],E,rho", "--model",
               "beam", "--modes", "2", "--out", str(out), "-q"])
    assert rc == 0
    doc = json.loads((out / "sensitivity.json").read_text())
    truth = pp.compute_truth(pp.load_beam(BEAM), model="beam", modes=2, error_tol_pct=None)
    # exact by construction (the command's truth is this one, written as JSON): slack 5000 EPS,
    # the test's 1e-12
    np.testing.assert_allclose(doc["omega_rad_s"], truth.omega_rad_s, rtol=5000 * EPS)
    np.testing.assert_allclose(doc["tip_z_m"], truth.static_linear.tip_displacement_m[2],
                               rtol=1e-7)
    # omega ~ t sqrt(E / rho), tip ~ 1 / (E t^3)
    rel = doc["relative_d_omega"]
    np.testing.assert_allclose(rel["thickness"], [1.0, 1.0], atol=1e-10)
    np.testing.assert_allclose(rel["E"], [0.5, 0.5], atol=1e-10)
    np.testing.assert_allclose(rel["rho"], [-0.5, -0.5], atol=1e-10)
    np.testing.assert_allclose(doc["relative_d_tip_z"]["thickness"], -3.0, atol=1e-10)
    # a unit-consistent record: d omega / dp * p / omega is the relative sensitivity (two
    # roundings on each side; kept: the test's 1e-12)
    w = doc["variables"][1]["value"]
    np.testing.assert_allclose(np.array(doc["d_omega_rad_s"]["half_width[1]"]) * w
                               / np.array(doc["omega_rad_s"]), rel["half_width[1]"],
                               rtol=5000 * EPS)
    assert [v["unit"] for v in doc["variables"]] == ["m", "m", "Pa", "kg/m^3"]
    assert (out / "sensitivity.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("design, extra, needle", [
    ("width", [], "unknown"),
    ("x[0]", [], "clamped root"),
    ("x[1]", [], "tip station"),
    ("half_width[9]", [], "does not exist"),
    ("thickness,thickness", [], "named twice"),
    ("thickness", ["--modes", "0"], "--modes"),
    ("thickness", ["--mesh", "9"], "--mesh"),
    (",", [], "at least one"),
])
def test_bad_input_is_one_line_exit_2(capsys, tmp_path, design, extra, needle):
    out = tmp_path / "sens"
    rc = main(["sensitivity", BEAM, "--design", design, "--out", str(out), "-q", *extra])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.count("\n") == 1 and needle in err and err.startswith("prbdm sensitivity: error")
    assert not out.exists()
