"""``prbdm simulate`` with a hub, strain actuators and input signals, end to end on a fit made
here, checked against physics the command does not compute (the angular momentum a hub torque
pulse leaves), the signals' own definitions, and its refusals (exit 2, one line)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from prbdm_pin import Hub, build_model
from prbdm_pin.cli import main
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.files.fit_file import load_fit
from prbdm_pin.io.record_checks import LINK_FLOOR_FRACTION

BEAM = "examples/beams/uniform-narrow.json"


@pytest.fixture(scope="module")
def fit_json(strip_fit):
    return strip_fit(3) / "fit" / "fit.json"


def _csv(path):
    head = path.read_text().splitlines()[0].split(",")
    return head, np.loadtxt(path, delimiter=",", skiprows=1)


def test_a_hub_torque_pulse_leaves_its_impulse_as_angular_momentum(fit_json, tmp_path):
    out = tmp_path / "slew"
    A, T1 = 2.0, 0.3
    rc = main(["simulate", str(fit_json), "--duration", "0.8", "--hub", "5:0.1",
               "--actuator", "0:0.3", "--input", f"hub_torque=pulse:{A}:{T1}",
               "--input", "strain[0]=sine:50:4", "--outputs", "hub_angle,tip_z",
               "--output-dt", "0.001", "--out", str(out), "-q"])
    assert rc == 0
    head, rows = _csv(out / "trajectory.csv")
    assert head[:2] == ["t_s", "hub_angle_rad"]
    assert head[-4:] == ["u:hub_torque", "u:strain[0]", "y:hub_angle", "y:tip_z"]
    t = rows[:, 0]
    u = rows[:, head.index("u:hub_torque")]
    assert np.array_equal(u, np.where(t < T1, A, 0.0))
    assert np.allclose(rows[:, head.index("u:strain[0]")], 50 * np.sin(2 * np.pi * 4 * t))
    fit = load_fit(fit_json, beam=load_beam(BEAM))
    model = build_model(load_beam(BEAM), fit.lengths_m, fit.stiffness_Nm_per_rad,
                        min_fraction=LINK_FLOOR_FRACTION, hub=Hub(5.0, 0.1))
    q, v = rows[:, 1:5], rows[:, 5:9]
    # the strain moment is internal: after the pulse the angular momentum about the hub axis
    # is the pulse's impulse A T1, while the panel keeps vibrating under the patch
    after = t > T1 + 0.01
    p_hub = np.array([(model.mass_matrix(qi) @ vi)[0] for qi, vi in zip(q[after], v[after],
                                                                         strict=True)])
    assert np.abs(p_hub - A * T1).max() < 1e-3 * A * T1
    assert np.array_equal(rows[:, head.index("y:hub_angle")], q[:, 0])
    assert (out / "response.png").stat().st_size > 1000


def test_compare_truth_of_the_plant_writes_per_pair_and_per_mode(fit_json, tmp_path):
    out = tmp_path / "cmp"
    rc = main(["simulate", str(fit_json), "--duration", "0.2", "--hub", "5:0.1",
               "--actuator", "0:0.5", "--input", "hub_torque=1", "--input", "strain[0]=0",
               "--outputs", "hub_angle,tip_z,q[0]", "--compare-truth",
               "--cache-dir", str(fit_json.parent.parent / "cache"), "--out", str(out), "-q"])
    assert rc == 0
    d = json.loads((out / "comparison.json").read_text())
    pairs = {(p["input"], p["output"]) for p in d["pairs"]}
    assert pairs == {(i, o) for i in ("hub_torque", "strain[0]") for o in ("hub_angle", "tip_z")}
    assert "q[0]" in json.dumps(d["not_compared"])
    assert len(d["modes"]) == 3
    assert (out / "comparison.png").stat().st_size > 1000


@pytest.mark.parametrize("args, text", [
    (["--input", "hub_torque=1"], "hub_torque"),
    (["--input", "torque"], "--input"),
    (["--input", "strain[0]=sine:1:0", "--actuator", "0:0.5"], "F > 0"),
    (["--input", "strain[0]=pulse:x:1", "--actuator", "0:0.5"], "--input"),
    (["--input", "strain[0]=1"], "strain[0]"),
    (["--hub=-1:0.1"], "--hub"),
    (["--actuator", "0.5:0.2"], "--actuator"),
    (["--actuator", "0.5:2"], "--actuator"),
    (["--outputs", "tip_w"], "tip_w"),
    (["--hub", "1:0.1", "--compare-truth"], "--input"),
    (["--hub", "1:0.1", "--input", "hub_torque=1", "--method", "gauss"], "gauss"),
    (["--input", "joint_torque[0]=1", "--input", "joint_torque[0]=2"], "twice"),
])
def test_bad_plant_options_exit_2_with_one_line(fit_json, tmp_path, capsys, args, text):
    out = tmp_path / "bad"
    rc = main(["simulate", str(fit_json), "--duration", "0.1", *args, "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and text in err[0], err
    assert not out.exists()


def test_a_model_json_brings_its_hub_and_actuators(fit_json, tmp_path):
    # an exported plant is simulated and linearised as exported: the hub and the patch it
    # records act without --hub or --actuator (a strain moment alone keeps the hub's angular
    # momentum at zero and turns the joints inside the patch)
    plant = tmp_path / "plant.json"
    assert main(["export", str(fit_json), "--format", "json", "--hub", "5:0.1",
                 "--actuator", "0:0.5", "--out", str(plant), "-q"]) == 0
    out = tmp_path / "sim"
    assert main(["simulate", str(plant), "--duration", "0.3", "--input", "strain[0]=40",
                 "--output-dt", "0.01", "--out", str(out), "-q"]) == 0
    head, rows = _csv(out / "trajectory.csv")
    assert head[1] == "hub_angle_rad" and "u:strain[0]" in head
    from prbdm_pin.files.export import read_plant_json

    model, acts = read_plant_json(plant)
    assert model.hub == Hub(5.0, 0.1) and len(acts) == 1
    q, v = rows[:, 1:5], rows[:, 5:9]
    p_hub = [(model.mass_matrix(qi) @ vi)[0] for qi, vi in zip(q, v, strict=True)]
    recoil = np.abs(model.mass_matrix()[0, 0] * v[:, 0]).max()  # the hub's own momentum
    assert np.abs(q[:, 1:]).max() > 0.005 and recoil > 0.0
    # the exponential integrator's step control (3e-4 of the motion per step) bounds the drift
    assert np.abs(p_hub).max() < 1e-3 * recoil
    lin_out = tmp_path / "lin"
    assert main(["linearize", str(plant), "--inputs", "strain[0]", "--outputs", "tip_z",
                 "--out", str(lin_out), "-q"]) == 0
    d = json.loads((lin_out / "linear_model.json").read_text())
    assert d["actuators_m"] == [[0.0, 0.5]]
