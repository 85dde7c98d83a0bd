"""``prbdm simulate --bus`` and ``prbdm linearize --bus``: a member on a free-floating bus.

References: a bus of huge mass gives the clamped chain's frequencies back (error ~ 1 / mass);
a tip force changes the system's linear momentum as F t (Newton's second law; Pinocchio's
centroidal momentum of the recorded coordinates and rates). Bad options: one line on stderr
naming ``--bus``, exit 2, no output folder.
"""

from __future__ import annotations

import json

import numpy as np
import pinocchio as pin
import pytest
from paths import ROOT

import prbdm_pin as pp
from prbdm_pin.cli import main

BEAM = pp.load_beam(ROOT / "examples/beams/reference-random.json")
LENGTHS = np.array([0.15, 0.3, 0.2, 0.35]) * BEAM.length_m
SPRINGS = np.array([400.0, 150.0, 60.0])


@pytest.fixture(scope="module")
def model_file(tmp_path_factory):
    src = tmp_path_factory.mktemp("bus") / "model.json"
    pp.export_model(pp.build_model(BEAM, LENGTHS, SPRINGS), src, "json")
    return src


def test_linearize_on_a_heavy_bus_gives_the_clamped_frequencies(model_file, tmp_path):
    out = tmp_path / "lin"
    assert main(["linearize", str(model_file), "--bus", "1e9:5e7,5e7,5e7:0.2,0,0", "--inputs",
                 "tip_force_z", "--outputs", "bus_attitude_y,tip_z", "--out", str(out),
                 "-q"]) == 0
    rec = json.loads((out / "linear_model.json").read_text())
    w = np.array([m["omega_rad_s"] for m in rec["modes"]])
    assert np.all(w[:6] == 0.0)
    clamped = pp.build_model(BEAM, LENGTHS, SPRINGS).natural_frequencies()
    # the member's 37 kg and ~5 kg m^2 against the bus's 1e9 kg and 5e7 kg m^2 (2.2e-7
    # measured; the error falls as 1 / mass: tests/model/test_free_bus.py)
    np.testing.assert_allclose(w[6:], clamped, rtol=1e-6)
    assert rec["bus"]["mass_kg"] == 1e9 and rec["bus"]["root_m"] == [0.2, 0.0, 0.0]
    assert rec["state_units"][:7] == ["m", "m", "m", "rad", "rad", "rad", "rad"]
    assert rec["state_names"][:6] == ["bus_x", "bus_y", "bus_z", "bus_yaw", "bus_pitch",
                                      "bus_roll"]


def test_simulate_on_a_bus_obeys_newtons_second_law(model_file, tmp_path):
    out = tmp_path / "sim"
    F = 4.0  # N, world z, at the tip
    assert main(["simulate", str(model_file), "--duration", "0.3", "--bus",
                 "12:0.4,0.5,0.6:0.25,0,0", "--tip-force", f"0,0,{F}", "--method", "DOP853",
                 "--damping", "0", "--output-dt", "0.05", "--outputs", "bus_position_z,tip_z",
                 "--out", str(out), "-q"]) == 0
    text = (out / "trajectory.csv").read_text().splitlines()
    head = text[0].split(",")
    rows = np.array([[float(v) for v in r.split(",")] for r in text[1:]])
    nv = 9
    Q, V = rows[:, 1:1 + nv], rows[:, 1 + nv:1 + 2 * nv]
    assert head[1:4] == ["bus_x_m", "bus_y_m", "bus_z_m"] and head[7] == "q1_rad"
    model = pp.build_model(BEAM, LENGTHS, SPRINGS,
                           support=pp.FreeBus(12.0, [0.4, 0.5, 0.6], root_m=[0.25, 0, 0]))
    data = model.pin_model.createData()
    P = np.array([pin.computeCentroidalMomentum(model.pin_model, data, q, v).linear
                  for q, v in zip(Q, V, strict=True)])
    assert np.abs(Q[:, 6:]).max() > 1e-4  # the member bends
    # DOP853 at its default rtol 1e-9 (3e-15 of F T measured; the file's repr round-trips
    # exactly)
    np.testing.assert_allclose(P[:, 2], F * rows[:, 0], rtol=0, atol=1e-9 * F * 0.3)
    np.testing.assert_array_equal(rows[:, head.index("y:bus_position_z")], Q[:, 2])


@pytest.mark.parametrize("extra,needles", [
    (["--bus", "0:1,1,1"], ["--bus", "mass_kg"]),
    (["--bus", "5:1,-1,1"], ["--bus", "positive definite"]),
    (["--bus", "5:1,1"], ["--bus", "MASS:IXX,IYY,IZZ"]),
    (["--bus", "5:1,1,1:0,0"], ["--bus", "MASS:IXX,IYY,IZZ"]),
    (["--bus", "5:1,1,1", "--hub", "500:0.1"], ["--bus", "--hub"]),
])
@pytest.mark.parametrize("command", ["simulate", "linearize"])
def test_bad_bus_options_are_one_line_exit_2(model_file, tmp_path, capsys, command, extra,
                                             needles):
    out = tmp_path / "out"
    argv = [command, str(model_file), *(["--duration", "0.1"] if command == "simulate" else []),
            *extra, "--out", str(out)]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    for text in needles:
        assert text in err[0], err
    assert not out.exists()
