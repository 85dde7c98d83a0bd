"""``prbdm linearize`` end to end on a fit made here (a 2-joint eigen fit to the 1D beam truth),
and its refusals: exit 2 with one line naming the option."""

from __future__ import annotations

import json

import numpy as np
import pytest
from tolerances import EPS

from prbdm_pin import Hub, StrainActuator, build_model, linearize
from prbdm_pin.cli import main
from prbdm_pin.files.fit_file import load_fit

BEAM = "examples/beams/uniform-narrow.json"


@pytest.fixture(scope="module")
def fit_json(strip_fit):
    return strip_fit(2) / "fit" / "fit.json"


def _model(fit_json, hub=None):
    from prbdm_pin.files.beam_file import load_beam
    from prbdm_pin.io.record_checks import LINK_FLOOR_FRACTION

    fit = load_fit(fit_json, beam=load_beam(BEAM))
    return build_model(load_beam(BEAM), fit.lengths_m, fit.stiffness_Nm_per_rad,
                       min_fraction=LINK_FLOOR_FRACTION, hub=hub)


def test_writes_matrices_names_modes_and_bode(fit_json, tmp_path):
    out = tmp_path / "plant"
    rc = main(["linearize", str(fit_json), "--inputs", "tip_force_z,strain[0]",
               "--outputs", "tip_z,q[0]", "--actuator", "0.1:0.6", "--load", "0,0,-10",
               "--damping-ratio", "0.03", "--out", str(out), "-q"])
    assert rc == 0
    mats = np.load(out / "linear_model.npz")
    ref = linearize(_model(fit_json), inputs=("tip_force_z", "strain[0]"),
                    outputs=("tip_z", "q[0]"), actuators=[StrainActuator(0.1, 0.6)],
                    load_N=[0.0, 0.0, -10.0], damping_ratio=0.03)
    # exact by construction: the command runs this linearize on the model of this fit file, and
    # npz and JSON keep every bit; slack 5000 EPS (the test's 1e-12)
    for name in "ABCD":
        np.testing.assert_allclose(mats[name], getattr(ref, name), rtol=5000 * EPS,
                                   atol=1e-300)
    d = json.loads((out / "linear_model.json").read_text())
    assert d["input_names"] == ["tip_force_z", "strain[0]"]
    assert d["output_units"] == ["m", "rad"] and d["input_units"] == ["N", "N m"]
    assert d["state_names"] == ["q[0]", "q[1]", "q_rate[0]", "q_rate[1]"]
    np.testing.assert_allclose(d["q_eq_rad"], ref.q_eq, rtol=5000 * EPS)
    assert len(d["modes"]) == 2 and d["hub"] is None
    assert d["modes"][0]["omega_rad_s"] == pytest.approx(ref.modal().omega_rad_s[0],
                                                         rel=5000 * EPS)
    assert (out / "bode.png").stat().st_size > 1000
    assert not list(tmp_path.glob(".*staging*"))


def test_hub_option(fit_json, tmp_path):
    out = tmp_path / "hub"
    rc = main(["linearize", str(fit_json), "--inputs", "hub_torque", "--outputs",
               "hub_angle,tip_z", "--hub", "0.5:0.05", "--out", str(out), "-q"])
    assert rc == 0
    d = json.loads((out / "linear_model.json").read_text())
    assert d["hub"] == {"inertia_kg_m2": 0.5, "radius_m": 0.05, "axis": "y"}
    assert d["spin_rad_s"] == 0.0
    assert d["modes"][0]["omega_rad_s"] == 0.0
    ref = _model(fit_json, Hub(0.5, 0.05)).natural_frequencies()
    # two solves of the hub model's modes (the plant's on the hub's Schur complement, the
    # model's scaled one): EPS (w_max / w_min)^2 each, 1e-14 here; kept: the test's 1e-12
    np.testing.assert_allclose([m["omega_rad_s"] for m in d["modes"]], ref, rtol=5000 * EPS)


@pytest.mark.parametrize("argv,needle", [
    (["--inputs", "tip_force_q"], "inputs[0] = 'tip_force_q'"),
    (["--inputs", "strain[0]"], "inputs[0] = 'strain[0]'"),
    (["--outputs", "tip_z,q[5]"], "outputs[1] = 'q[5]'"),
    (["--outputs", "q(0)"], "--outputs = 'q(0)'"),
    (["--actuator", "0.6:0.1"], "--actuator = '0.6:0.1'"),
    (["--actuator", "0.1:5", "--inputs", "strain[0]"], "--actuator = '0.1:5': x_end_m = 5.0"),
    (["--actuator", "a:b"], "--actuator = 'a:b'"),
    (["--hub=-1:0.1"], "--hub = '-1:0.1': Hub inertia_kg_m2 = -1.0"),
    (["--hub", "1"], "--hub = '1'"),
    (["--load", "0,0"], "--load = '0,0'"),
    (["--damping-ratio", "1.5"], "--damping-ratio = 1.5"),
    (["--out", "/proc/x"], "--out = '/proc/x'"),
])
def test_bad_input_exits_2_with_one_line(fit_json, tmp_path, capsys, argv, needle):
    out = tmp_path / "never"
    full = ["linearize", str(fit_json), "--out", str(out), "-q", *argv]
    rc = main(full)
    err = capsys.readouterr().err
    assert rc == 2
    assert err.count("\n") == 1 and err.startswith("prbdm linearize: error: "), err
    assert needle in err
    assert not out.exists()


def test_missing_model_exits_2(tmp_path, capsys):
    rc = main(["linearize", str(tmp_path / "nope.json"), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "not found" in err
