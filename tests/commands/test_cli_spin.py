"""``prbdm linearize --hub-axis --spin`` end to end on a model JSON written here, against the
spinning chain's frequencies by another solver, and its refusals: exit 2, one line naming the
option, nothing written."""

from __future__ import annotations

import json

import numpy as np
import pytest
from paths import BEAMS
from tolerances import EPS

from prbdm_pin import Hub, build_model, spinning_frequencies
from prbdm_pin.cli import main
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.files.model_json import model_dict

BEAM = load_beam(BEAMS / "uniform-narrow.json")
LENGTHS = np.array([0.1, 0.2, 0.2, 0.2, 0.2, 0.1])  # 5 joints at the centres of equal segments
SPRINGS = np.full(5, 205e9 * 0.05 * 0.01**3 / 12.0 / 0.2)  # E I / l, N m/rad


@pytest.fixture(scope="module")
def model_json(tmp_path_factory):
    path = tmp_path_factory.mktemp("spin") / "strip.json"
    path.write_text(json.dumps(model_dict(build_model(BEAM, LENGTHS, SPRINGS))))
    return path


@pytest.mark.parametrize("axis", ["y", "z"])
def test_spin_writes_the_spinning_plant(model_json, tmp_path, axis):
    out = tmp_path / "plant"
    spin = 40.0
    rc = main(["linearize", str(model_json), "--inputs", "hub_torque", "--outputs",
               "hub_angle,tip_z", "--hub", "50:0.1", "--hub-axis", axis, "--spin", str(spin),
               "--damping-ratio", "0.01", "--out", str(out), "-q"])
    assert rc == 0
    d = json.loads((out / "linear_model.json").read_text())
    assert d["hub"] == {"inertia_kg_m2": 50.0, "radius_m": 0.1, "axis": axis}
    assert d["spin_rad_s"] == spin
    ref = spinning_frequencies(build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(50.0, 0.1, axis)),
                               spin)
    omega = [m["omega_rad_s"] for m in d["modes"]]
    assert omega[0] == 0.0  # the free hub's rigid mode
    # two solves of one pencil (the plant's modal view, scipy's eigvalsh of the Schur
    # complement): EPS (w_max / w_min)^2 each, ~1e-12 here
    np.testing.assert_allclose(omega[1:], ref, rtol=50 * EPS * (ref[-1] / ref[0]) ** 2)
    # straight: no gyroscopic coupling, the record's spinning frequencies are the modal ones
    np.testing.assert_allclose(d["spin_frequencies_rad_s"], ref,
                               rtol=50 * EPS * (ref[-1] / ref[0]) ** 2)
    # the state matrix's undamped part has the same frequencies: the spin is in A
    A = np.load(out / "linear_model.npz")["A"]
    ev = np.linalg.eigvals(A)
    ev = np.sort(np.abs(ev[np.abs(ev) > 1e-9 * np.abs(ev).max()]))[::2]
    # |lambda| of a pair with damping ratio 0.01 is its undamped frequency (modal damping);
    # the nonsymmetric eigensolver on A: EPS times A's spread, ~1e-9 here
    np.testing.assert_allclose(ev, ref, rtol=1e-8)


@pytest.mark.parametrize("argv,needle", [
    (["--hub-axis", "z"], "--hub-axis = 'z': needs --hub"),
    (["--hub", "50:0.1", "--hub-axis", "w"], "--hub-axis = 'w': must be x, y or z"),
    (["--spin", "10"], "--spin = 10.0: needs --hub"),
    (["--hub", "50:0.1", "--spin", "nan"], "--spin = nan"),
    (["--hub", "50:0.1", "--spin", "10", "--load", "0,0,-1"], "--spin = 10.0: a spinning hub"),
    (["--hub", "50:0.1", "--spin", "10", "--gravity", "0,0,-9.81"],
     "off its axis (y"),
    (["--hub", "50:0.1", "--hub-axis", "z", "--spin", "10", "--gravity", "0,-9.81,0"],
     "off its axis (z"),
])
def test_spin_refusals_exit_2_with_one_line(model_json, tmp_path, capsys, argv, needle):
    out = tmp_path / "never"
    rc = main(["linearize", str(model_json), "--out", str(out), "-q", *argv])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.count("\n") == 1 and err.startswith("prbdm linearize: error: "), err
    assert needle in err
    assert not out.exists()


def test_export_carries_the_hub_axis(model_json, tmp_path):
    from prbdm_pin import load_urdf

    out = tmp_path / "hub.urdf"
    rc = main(["export", str(model_json), "--format", "urdf", "--hub", "50:0.1",
               "--hub-axis", "x", "--out", str(out), "-q"])
    assert rc == 0
    assert load_urdf(out).hub == Hub(50.0, 0.1, "x")


def test_simulate_spin_keeps_the_free_hub_spinning(model_json, tmp_path):
    out = tmp_path / "sim"
    spin, T = 20.0, 0.2
    rc = main(["simulate", str(model_json), "--duration", str(T), "--hub", "50:0.1",
               "--hub-axis", "z", "--spin", str(spin), "--outputs", "hub_angle,hub_rate",
               "--out", str(out), "-q"])
    assert rc == 0
    rows = (out / "trajectory.csv").read_text().splitlines()
    head = rows[0].split(",")
    data = np.array([[float(v) for v in r.split(",")] for r in rows[1:]])
    t = data[:, head.index("t_s")]
    # the straight pose is the spinning chain's relative equilibrium: the hub turns at the
    # constant rate (the default method picks the compiled DOP853: its rounding over the run)
    np.testing.assert_allclose(data[:, head.index("hub_angle_rad")], spin * t, rtol=0.0,
                               atol=1000 * EPS * spin * T)
    np.testing.assert_allclose(data[:, head.index("hub_rate_rad_s")], spin, rtol=1000 * EPS)
    # the tip runs round the circle of radius r + L = 1.1 m in the xy-plane
    x, y = data[:, head.index("tip_x_m")], data[:, head.index("tip_y_m")]
    np.testing.assert_allclose(np.hypot(x, y), 1.1, rtol=1000 * EPS)
    np.testing.assert_allclose(np.arctan2(y, x), np.arctan2(np.sin(spin * t), np.cos(spin * t)),
                               atol=1000 * EPS * spin * T)


@pytest.mark.parametrize("argv,needle", [
    (["--spin", "10"], "--spin = 10.0: needs --hub"),
    (["--hub", "50:0.1", "--spin", "10", "--compare-truth"], "--spin = 10.0: --compare-truth"),
    (["--hub", "50:0.1", "--spin", "inf"], "--spin = inf"),
    (["--hub", "50:0.1", "--spin", "10", "--method", "exponential"],
     "spin_rad_s = 10.0: the exponential integrator"),
])
def test_simulate_spin_refusals(model_json, tmp_path, capsys, argv, needle):
    out = tmp_path / "never"
    rc = main(["simulate", str(model_json), "--duration", "0.1", "--out", str(out), "-q",
               *argv])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.count("\n") == 1 and err.startswith("prbdm simulate: error: "), err
    assert needle in err
    assert not out.exists()
