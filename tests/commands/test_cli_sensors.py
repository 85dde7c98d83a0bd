"""Sensor outputs on the command line: ``prbdm simulate --outputs`` writes them as CSV columns,
``prbdm linearize --outputs`` into its matrices, and a station off the member exits 2 with one
line naming the output.

References: the strain at a joint is the joint's spring moment k q over E I times half the
thickness (the definition, with q read from the same CSV row); the linear model written by the
command against the API's (the wiring)."""

from __future__ import annotations

import csv

import numpy as np
import pytest
from paths import ROOT
from tolerances import EPS

from prbdm_pin import build_model, linearize
from prbdm_pin.cli import main
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.files.fit_file import load_fit

BEAM = ROOT / "examples/beams/uniform-narrow.json"


@pytest.fixture(scope="module")
def fit_json(strip_fit):
    return strip_fit(2) / "fit" / "fit.json"


def _model(fit_json):
    from prbdm_pin.io.record_checks import LINK_FLOOR_FRACTION

    fit = load_fit(fit_json, beam=load_beam(BEAM))
    return build_model(load_beam(BEAM), fit.lengths_m, fit.stiffness_Nm_per_rad,
                       min_fraction=LINK_FLOOR_FRACTION)


def test_simulate_writes_sensor_columns(fit_json, tmp_path):
    model = _model(fit_json)
    x1 = float(model.lengths_m[0])  # the first joint
    names = [f"strain@{x1!r}", "root_force_z", "point_z@1:0.02", "slope@0.5"]
    out = tmp_path / "sim"
    rc = main(["simulate", str(fit_json), "--duration", "0.02", "--tip-force", "0,0,5",
               "--outputs", ",".join(names), "--out", str(out), "-q"])
    assert rc == 0
    with open(out / "trajectory.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) > 2
    beam = model.beam
    scale = -1e6 * beam.thickness_m / (2.0 * beam.material.E_Pa * beam.area_moment_at(x1))
    k = model.stiffness_Nm_per_rad[0]
    eps = np.array([float(r[f"y:{names[0]}"]) for r in rows])
    ref = np.array([scale * k * float(r["q1_rad"]) for r in rows])
    # the same product of three numbers read back exactly (repr): a few roundings
    assert np.abs(eps - ref).max() <= 8 * EPS * np.abs(ref).max()
    assert np.abs(ref).max() > 1.0  # microstrain: the load bends the member
    for name in names[1:]:
        assert f"y:{name}" in rows[0]


def test_linearize_writes_sensor_rows(fit_json, tmp_path):
    outs = "root_force_z,root_moment_y,strain@0.1,twist@0.9,point_x@0.5:-0.01"
    out = tmp_path / "plant"
    rc = main(["linearize", str(fit_json), "--inputs", "tip_force_z", "--outputs", outs,
               "--out", str(out), "-q"])
    assert rc == 0
    mats = np.load(out / "linear_model.npz")
    ref = linearize(_model(fit_json), inputs=("tip_force_z",), outputs=tuple(outs.split(",")))
    # the command runs the same linearisation: equal to the last bit
    for key in ("A", "B", "C", "D"):
        assert np.array_equal(mats[key], getattr(ref, key)), key
    assert abs(ref.D[0, 0]) > 0.0  # the acceleration path reached the file


@pytest.mark.parametrize("command", ["linearize", "simulate"])
def test_a_station_off_the_member_exits_2_with_one_line(fit_json, tmp_path, capsys, command):
    out = tmp_path / "never"
    extra = ["--duration", "0.01"] if command == "simulate" else []
    rc = main([command, str(fit_json), "--outputs", "tip_z,strain@1.5", "--out", str(out),
               "-q", *extra])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.count("\n") == 1 and err.startswith(f"prbdm {command}: error: "), err
    assert "outputs[1] = 'strain@1.5': station x = 1.5 m is off the member" in err
    assert not out.exists()
