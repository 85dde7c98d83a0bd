"""``prbdm simulate --base-motion FILE.csv``: a run on a moving clamp, and bad files refused.

Reference: samples of a constant base acceleration a equal gravity g = -a on the fixed clamp
(the API's gravity path); the world tip is the base-frame tip plus the base's position (a pure
translation). Bad files: one line on stderr naming the option, the file and the column or
row, exit 2, no output folder.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from paths import ROOT
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.cli import main
from prbdm_pin.files.beam_file import load_beam

BEAM = load_beam(ROOT / "examples/beams/reference-random.json")
LENGTHS = np.array([0.15, 0.3, 0.2, 0.35]) * BEAM.length_m
SPRINGS = np.array([400.0, 150.0, 60.0])
ACCEL = np.array([0.5, 0.0, -2.0])  # m/s^2
DURATION = 0.4  # s


@pytest.fixture(scope="module")
def model_file(tmp_path_factory):
    d = tmp_path_factory.mktemp("base_motion")
    src = d / "model.json"
    pp.export_model(pp.build_model(BEAM, LENGTHS, SPRINGS), src, "json")
    return src


def _write(path, header, rows):
    path.write_text(",".join(header) + "\n"
                    + "".join(",".join(repr(float(v)) for v in r) + "\n" for r in rows))
    return path


def _read(path):
    head = path.read_text().splitlines()[0].split(",")
    return head, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def test_a_sampled_acceleration_equals_gravity_and_the_world_tip_moves(model_file, tmp_path):
    t = np.linspace(0.0, DURATION, 9)
    pos = 0.5 * np.outer(t * t, ACCEL)
    csv = _write(tmp_path / "motion.csv", ["t_s", "x_m", "y_m", "z_m", "roll_rad", "pitch_rad",
                                           "yaw_rad"], np.column_stack([t, pos, 0 * pos]))
    out = tmp_path / "sim"
    assert main(["simulate", str(model_file), "--duration", str(DURATION), "--base-motion",
                 str(csv), "--output-dt", "0.05", "--outputs", "tip_z", "--out", str(out),
                 "-q"]) == 0
    head, rows = _read(out / "trajectory.csv")
    assert "tip_z_m" in head and head[-3:] == ["tip_world_x_m", "tip_world_y_m",
                                               "tip_world_z_m"]
    col = {name: i for i, name in enumerate(head)}
    model = pp.read_model_json(model_file)
    # the exponential integrator, which the default picks for a base motion (an input the
    # compiled kernel does not take), named here: under gravity alone it would pick compiled
    ref = pp.simulate(model, DURATION, gravity_m_s2=-ACCEL, output_dt_s=0.05,
                      damping_ratio=0.02, method="exponential")
    assert json.loads((out / "simulation.json").read_text())["method"] == "exponential"
    q = rows[:, [col["q1_rad"], col["q2_rad"], col["q3_rad"]]]
    swing = np.abs(ref.q_rad).max()
    assert swing > 1e-3
    # the same exponential steps on both sides, the forces equal up to roundings (1e-12 of the
    # swing measured); the file's repr round-trips exactly
    assert np.abs(q - ref.q_rad).max() <= 1e-10 * swing
    np.testing.assert_array_equal(rows[:, col["y:tip_z"]], rows[:, col["tip_z_m"]])
    base = 0.5 * np.outer(rows[:, 0] ** 2, ACCEL)
    tip = rows[:, [col["tip_x_m"], col["tip_y_m"], col["tip_z_m"]]]
    world = rows[:, [col["tip_world_x_m"], col["tip_world_y_m"], col["tip_world_z_m"]]]
    # the spline reproduces the quadratic: roundings of ~1 m positions and of the spline's
    # solve (kept: 1e-12)
    np.testing.assert_allclose(world, tip + base, rtol=0, atol=5000 * EPS)


def test_a_sampled_spin_about_y_equals_a_hub_held_at_that_rate(model_file, tmp_path):
    omega, T = 3.0, 0.5  # rad/s, s
    t = np.linspace(0.0, T, 6)
    zero = 0.0 * t
    # pitch = omega t (a line: the spline is exact), the other columns zero
    csv = _write(tmp_path / "spin.csv", ["t_s", "yaw_rad", "x_m", "pitch_rad", "y_m", "z_m",
                                         "roll_rad"],
                 np.column_stack([t, zero, zero, omega * t, zero, zero, zero]))
    out = tmp_path / "sim"
    assert main(["simulate", str(model_file), "--duration", str(T), "--base-motion", str(csv),
                 "--initial-angle", "0.03", "--damping", "0", "--method", "DOP853",
                 "--output-dt", "0.05", "--out", str(out), "-q"]) == 0
    head, rows = _read(out / "trajectory.csv")
    q = rows[:, [head.index(f"q{j}_rad") for j in (1, 2, 3)]]
    hub = pp.build_model(BEAM, LENGTHS, SPRINGS, hub=pp.Hub(1e10, 0.0))
    ref = pp.simulate(hub, T, q0=np.r_[0.0, 0.03, 0.03, 0.03], v0=np.r_[omega, 0.0, 0.0, 0.0],
                      damping_ratio=0.0, method="DOP853", output_dt_s=0.05)
    swing = np.abs(ref.q_rad[:, 1:]).max()
    # DOP853 at its default rtol 1e-9 on both sides, and the hub's finite inertia (1e-10):
    # 1.2e-9 of the swing measured; the spin itself changes the response by 36 %
    assert np.abs(q - ref.q_rad[:, 1:]).max() <= 1e-7 * swing


GOOD = ["t_s", "x_m", "y_m", "z_m"]


@pytest.mark.parametrize("header,rows,needles", [
    (["t_s", "x_m", "z_m"], [[0, 0, 0], [1, 0, 0]], ["motion.csv", "'y_m'", "missing column"]),
    (GOOD + ["roll_rad"], [[0, 0, 0, 0, 0], [1, 0, 0, 0, 0]], ["'pitch_rad'"]),
    (GOOD + ["speed"], [[0, 0, 0, 0, 0], [1, 0, 0, 0, 0]], ["unknown column", "'speed'"]),
    (GOOD, [[0, 0, 0, 0], [0.5, 0, 0, 0], [0.5, 0, 0, 0]], ["row 4", "'t_s'", "increase"]),
    (GOOD, [[0, 0, 0, 0], [1, 0, float("nan"), 0]], ["row 3", "'y_m'", "finite"]),
    (GOOD, [[0, 0, 0, 0]], ["two rows"]),
    (GOOD, [[0, 0, 0, 0], [0.1, 0, 0, 0]], ["cover the run"]),
])
def test_bad_base_motion_files_are_one_line_exit_2(model_file, tmp_path, capsys, header, rows,
                                                    needles):
    csv = _write(tmp_path / "motion.csv", header, rows)
    out = tmp_path / "sim"
    assert main(["simulate", str(model_file), "--duration", str(DURATION), "--base-motion",
                 str(csv), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "--base-motion" in err[0] or "base_motion" in err[0]
    for text in needles:
        assert text in err[0], err
    assert not out.exists()


def test_base_motion_file_missing_or_with_a_hub_is_refused(model_file, tmp_path, capsys):
    out = tmp_path / "sim"
    assert main(["simulate", str(model_file), "--duration", "0.1", "--base-motion",
                 str(tmp_path / "none.csv"), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--base-motion" in err[0] and "none.csv" in err[0], err
    t = np.linspace(0.0, 0.1, 3)
    csv = _write(tmp_path / "ok.csv", GOOD, np.column_stack([t, 0 * t, 0 * t, 0 * t]))
    assert main(["simulate", str(model_file), "--duration", "0.1", "--base-motion", str(csv),
                 "--hub", "500:0.1", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--base-motion" in err[0] and "hub" in err[0], err
    assert not out.exists()
