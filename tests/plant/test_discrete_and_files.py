"""The discrete-time plant (zero-order hold), the MATLAB file of ``prbdm linearize`` and input
signals read from CSV files by ``prbdm simulate``.

References: exp(A dt) by the eigen-decomposition of A (not the block exponential
python-control uses) and B_d = A^-1 (A_d - I) B; the continuous linear model's exact step
response at the sample times; numpy's interpolation for the sampled signal; scipy.io reading
the .mat back.
"""

import json

import numpy as np
import pytest
import scipy.io
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.cli import main
from prbdm_pin.commands.input_signals import SampledSignal, read_samples
from prbdm_pin.errors import BeamInputError


@pytest.fixture(scope="module")
def plant(tapered):
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * tapered.length_m
    model = pp.build_model(tapered, lengths, spatial_stiffness(tapered, lengths, "y"))
    return model, pp.linearize(model, inputs=("tip_force_z", "joint_torque[0]"),
                               outputs=("tip_z", "q[1]"))


def test_the_zero_order_hold_is_the_exponential_of_a(plant):
    _, lin = plant
    dt = 2e-4
    Ad, Bd = lin.discretize(dt)
    lam, V = np.linalg.eig(lin.A)
    E = (V * np.exp(lam * dt)) @ np.linalg.inv(V)
    # two algorithms for exp(A dt): eig carries cond(V) EPS (V of a damped oscillator pencil)
    np.testing.assert_allclose(Ad, E.real, rtol=0.0, atol=1e-10 * np.abs(Ad).max())
    Bref = np.linalg.solve(lin.A, (Ad - np.eye(Ad.shape[0])) @ lin.B)
    np.testing.assert_allclose(Bd, Bref, rtol=0.0, atol=1e-9 * np.abs(Bd).max())
    # a held unit step: the discrete samples are the continuous step response, exactly
    x, y = np.zeros(Ad.shape[0]), []
    for _ in range(50):
        x = Ad @ x + Bd[:, 0]
        y.append(lin.C @ x)
    t = dt * np.arange(1, 51)
    ref = np.array([lin.C @ np.linalg.solve(lin.A, ((V * np.exp(lam * tk)) @ np.linalg.inv(V)
                                                    ).real - np.eye(Ad.shape[0])) @ lin.B[:, 0]
                    for tk in t])
    np.testing.assert_allclose(y, ref, rtol=0.0, atol=1e-8 * np.abs(ref).max())
    with pytest.raises(BeamInputError, match="dt_s = 0"):
        lin.discretize(0.0)


def test_the_command_writes_the_discrete_plant_and_the_mat_file(plant, tmp_path):
    model, lin = plant
    src = tmp_path / "model.json"
    pp.export_model(model, src, "json")
    out = tmp_path / "lin"
    assert main(["linearize", str(src), "--inputs", "tip_force_z,joint_torque[0]",
                 "--outputs", "tip_z,q[1]", "--dt", "0.0002", "--out", str(out), "-q"]) == 0
    m = scipy.io.loadmat(out / "linear_model.mat")
    z = np.load(out / "linear_model.npz")
    for key in ("A", "B", "C", "D", "Ad", "Bd"):
        np.testing.assert_array_equal(m[key], z[key])
    Ad, _ = lin.discretize(2e-4)
    # the model read back from its JSON has the same numbers: the same matrix exponential,
    # to a few roundings of its largest entry
    np.testing.assert_allclose(z["Ad"], Ad, rtol=0.0, atol=50 * EPS * np.abs(Ad).max())
    assert [str(c[0]) for c in m["input_names"].ravel()] == ["tip_force_z", "joint_torque[0]"]
    assert [str(c[0]) for c in m["output_names"].ravel()] == ["tip_z", "q[1]"]
    assert json.loads((out / "linear_model.json").read_text())["dt_s"] == 2e-4


def test_a_sampled_signal_is_linear_between_samples_and_held_outside(tmp_path):
    f = tmp_path / "u.csv"
    f.write_text("t_s,torque_Nm\n0,0\n0.1,2\n0.3,-1\n")
    s = SampledSignal("hub_torque", *read_samples(str(f), "--input"))
    t = np.array([-1.0, 0.0, 0.05, 0.1, 0.2, 0.3, 5.0])
    # two interpolation formulas: a rounding or two of the values
    np.testing.assert_allclose([s.value(v) for v in t],
                               np.interp(t, [0.0, 0.1, 0.3], [0.0, 2.0, -1.0]), rtol=0.0,
                               atol=4 * EPS * 2.0)


@pytest.mark.parametrize("text, needle", [("0,0\n0.1,1\n0.1,2\n", "does not increase"),
                                          ("0,0\n0.1,nan\n", "two finite numbers"),
                                          ("0,0\n", "at least two rows"),
                                          ("0,0,1\n1,2,3\n", "two finite numbers")])
def test_bad_signal_files_exit_2_naming_the_option(plant, tmp_path, capsys, text, needle):
    model, _ = plant
    src = tmp_path / "model.json"
    pp.export_model(model, src, "json")
    f = tmp_path / "u.csv"
    f.write_text(text)
    out = tmp_path / "sim"
    assert main(["simulate", str(src), "--duration", "0.01", "--input",
                 f"tip_force_z={f}", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--input" in err[0] and needle in err[0], err
    assert not out.exists()


def test_a_file_signal_drives_the_simulation(plant, tmp_path):
    model, _ = plant
    src = tmp_path / "model.json"
    pp.export_model(model, src, "json")
    f = tmp_path / "u.csv"
    f.write_text("0,0\n0.005,1.5\n0.01,1.5\n")
    out = tmp_path / "sim"
    assert main(["simulate", str(src), "--duration", "0.02", "--output-dt", "0.001",
                 "--input", f"tip_force_z={f}", "--out", str(out), "-q"]) == 0
    lines = (out / "trajectory.csv").read_text().splitlines()
    head = lines[0].split(",")
    data = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    t, u = data[:, head.index("t_s")], data[:, head.index("u:tip_force_z")]
    # the samples' interpolation (two formulas: a few roundings of 1.5), written with 17 digits
    np.testing.assert_allclose(u, np.interp(t, [0.0, 0.005, 0.01], [0.0, 1.5, 1.5]),
                               rtol=0.0, atol=8 * EPS * 1.5)
