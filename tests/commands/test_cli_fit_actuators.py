"""``--fit-actuators`` of ``prbdm linearize``, ``prbdm simulate`` and ``prbdm export``, end to
end on a fit made by ``prbdm fit`` against the 1D beam truth: the written plant's residues give the
truth's modal gains, MuJoCo reads the weights the linear model used, the nonlinear simulation
follows the linear model's step response; and the refusals."""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.linalg as sla
from tolerances import EPS

from prbdm_pin.cli import main
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.files.export import read_export_record
from prbdm_pin.truth import compute_truth
from prbdm_pin.truth.plant import truth_modal_gains

BEAM = "examples/beams/uniform-narrow.json"
PATCH = (0.2, 0.3)  # between the eigen fit's joints: the virtual-work map gives it no joint


@pytest.fixture(scope="module")
def fit_json(strip_fit):
    return strip_fit(3) / "fit" / "fit.json"


def _cache(fit_json):
    return str(fit_json.parent.parent / "cache")


@pytest.fixture(scope="module")
def linearized(fit_json, tmp_path_factory):
    out = tmp_path_factory.mktemp("lin")
    rc = main(["linearize", str(fit_json), "--inputs", "tip_force_z,strain[0]", "--outputs",
               "tip_z", "--actuator", f"{PATCH[0]}:{PATCH[1]}", "--fit-actuators",
               "--damping-ratio", "0", "--cache-dir", _cache(fit_json), "--out", str(out), "-q"])
    assert rc == 0
    return out


def test_linearize_writes_the_fitted_plant_and_its_weights(fit_json, linearized):
    """The written A, B, C: strain -> tip z residues over sqrt(tip force -> tip z residues) are
    the truth's modal gains of the patch (the truth's modes with positive tip gains)."""
    rec = json.loads((linearized / "linear_model.json").read_text())
    assert rec["actuators_m"] == [list(PATCH)] and rec["actuator_maps"] == ["fitted"]
    assert len(rec["actuator_weights"][0]) == 3 and any(rec["actuator_weights"][0])
    m = np.load(linearized / "linear_model.npz")
    p, V = np.linalg.eig(m["A"])
    up = np.flatnonzero(p.imag > 0.0)
    up = up[np.argsort(p[up].imag)]
    R = np.real(2j * p[up].imag[:, None] * (m["C"][0] @ V[:, up])[:, None]
                * (np.linalg.inv(V)[up] @ m["B"]))
    beam = load_beam(BEAM)
    truth = compute_truth(beam, model="beam", modes=6, cache_dir=_cache(fit_json),
                          error_tol_pct=None)
    g = truth_modal_gains(truth, beam, (PATCH,))
    np.testing.assert_allclose(R[:, 1] / np.sqrt(R[:, 0]), g.strain_per_sqrt_kg_m[0, :3],
                               rtol=1e-9)


def test_export_mjcf_carries_the_weights_linearize_used(fit_json, linearized, tmp_path):
    mujoco = pytest.importorskip("mujoco")
    out = tmp_path / "patch.xml"
    rc = main(["export", str(fit_json), "--format", "mjcf", "--actuator",
               f"{PATCH[0]}:{PATCH[1]}", "--fit-actuators", "--cache-dir", _cache(fit_json),
               "--out", str(out), "-q"])
    assert rc == 0
    w = json.loads((linearized / "linear_model.json").read_text())["actuator_weights"][0]
    m = mujoco.MjModel.from_xml_path(str(out))
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    moment = np.zeros((m.nu, m.nv))
    mujoco.mju_sparse2dense(moment, d.actuator_moment, d.moment_rownnz, d.moment_rowadr,
                            d.moment_colind)
    # exact by construction: export fits the weights as linearize did (equal bit for bit,
    # below) and MuJoCo reads the written repr back to the same double; slack 5 EPS (the
    # test's 1e-15)
    np.testing.assert_allclose(moment[0], w, rtol=5 * EPS)
    rec = read_export_record(out.read_text())
    assert rec.actuators()[0].joint_weights == tuple(w)


def test_simulate_follows_the_fitted_linear_plant(fit_json, linearized, tmp_path):
    """A step of the patch moment (small: the linear regime) simulated on the nonlinear chain
    against the exact step response of linearize's undamped plant."""
    out = tmp_path / "sim"
    rc = main(["simulate", str(fit_json), "--duration", "0.2", "--damping", "0",
               "--actuator", f"{PATCH[0]}:{PATCH[1]}", "--fit-actuators", "--input",
               "strain[0]=1", "--outputs", "tip_z", "--output-dt", "0.001", "--method", "RK45",
               "--cache-dir", _cache(fit_json), "--out", str(out), "-q"])
    assert rc == 0
    head = (out / "trajectory.csv").read_text().splitlines()[0].split(",")
    rows = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    t, z = rows[:, 0], rows[:, head.index("y:tip_z")]
    m = np.load(linearized / "linear_model.npz")
    A, b, c = m["A"], m["B"][:, 1], m["C"][0]
    n = A.shape[0]
    # x(t) = int_0^t e^(A s) b ds from the augmented exponential
    aug = np.zeros((n + 1, n + 1))
    aug[:n, :n], aug[:n, n] = A, b
    ref = np.array([c @ sla.expm(aug * ti)[:n, n] for ti in t])
    assert np.abs(ref).max() > 1e-5
    np.testing.assert_allclose(z, ref, rtol=0.0, atol=2e-3 * np.abs(ref).max())


@pytest.mark.parametrize("argv, needle", [
    (["linearize", "--inputs", "strain[0]", "--out", "{o}"],
     "--fit-actuators: no strain actuator to fit; give --actuator XA:XB"),
    (["simulate", "--duration", "0.01", "--out", "{o}"],
     "--fit-actuators: no strain actuator to fit"),
    (["export", "--format", "mjcf", "--out", "{o}.xml"],
     "--fit-actuators: no strain actuator to fit"),
])
def test_fit_actuators_without_actuators_exit_2(fit_json, tmp_path, capsys, argv, needle):
    argv = [a.replace("{o}", str(tmp_path / "o")) for a in argv]
    assert main([argv[0], str(fit_json), *argv[1:], "--fit-actuators", "--cache-dir",
                 _cache(fit_json)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err, err


@pytest.mark.parametrize("command", ["linearize", "simulate", "export"])
def test_fit_actuators_without_a_truth_record_exit_2(fit_json, tmp_path, capsys, command):
    model = tmp_path / "model.json"
    assert main(["export", str(fit_json), "--format", "json", "--out", str(model), "-q"]) == 0
    capsys.readouterr()
    extra = {"linearize": ["--inputs", "strain[0]", "--out", str(tmp_path / "o")],
             "simulate": ["--duration", "0.01", "--out", str(tmp_path / "o")],
             "export": ["--format", "mjcf", "--out", str(tmp_path / "o.xml")]}[command]
    assert main([command, str(model), "--actuator", "0.2:0.3", "--fit-actuators",
                 "--cache-dir", _cache(fit_json), *extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert "--fit-actuators: MODEL" in err and "carries no truth record" in err, err
    assert not (tmp_path / "o").exists() and not (tmp_path / "o.xml").exists()
