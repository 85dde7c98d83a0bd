"""Exports: URDF reloads as the same model; MJCF in MuJoCo has the same M, frequencies, response."""

import json

import numpy as np
import pytest
import scipy.linalg as sla

from prbdm_pin.errors import BeamInputError
from prbdm_pin.export import export_model, mjcf_text, read_model_json
from prbdm_pin.geometry import load_beam
from prbdm_pin.model import build_model, load_urdf
from prbdm_pin.simulation import simulate
from prbdm_pin.stiffness import finite_segment_stiffness

mujoco = pytest.importorskip("mujoco")


@pytest.fixture(scope="module")
def model():
    beam = load_beam("examples/beams/reference-random.json")
    lengths = np.array([0.1, 0.2, 0.2, 0.2, 0.15, 0.15])
    return build_model(beam, lengths, finite_segment_stiffness(beam, lengths))


def _mj(model, damping_ratio=0.0, timestep_s=None):
    m = mujoco.MjModel.from_xml_string(mjcf_text(model, damping_ratio, timestep_s))
    return m, mujoco.MjData(m)


@pytest.mark.parametrize("pose", [0.0, 0.2, -0.35])
def test_mjcf_mass_matrix_matches_pinocchio(model, pose):
    m, d = _mj(model)
    q = pose * np.array([1.0, -0.5, 0.8, 0.3, 1.0])
    d.qpos[:] = q
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    Mp = model.mass_matrix(q)
    assert np.abs(M - Mp).max() <= 1e-9 * np.abs(Mp).max()
    np.testing.assert_allclose(d.site_xpos[0], model.tip_position(q), atol=1e-12)


def test_mjcf_frequencies_and_springs(model):
    m, d = _mj(model, damping_ratio=0.02)
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    K = np.diag(m.jnt_stiffness)
    omega = np.sqrt(sla.eigh(K, M, eigvals_only=True))
    np.testing.assert_allclose(omega, model.natural_frequencies(), rtol=1e-6)
    np.testing.assert_allclose(m.qpos_spring, 0.0)
    assert tuple(m.opt.gravity) == (0.0, 0.0, 0.0)
    assert np.all(m.dof_damping > 0)


def test_mujoco_step_load_matches_pinocchio(model):
    """A step tip load in MuJoCo (semi-implicit Euler, tiny step) and in simulate() agree."""
    force = np.array([0.0, 0.0, -500.0])
    omega = model.natural_frequencies()
    duration = 1.5 * 2 * np.pi / omega[0]
    h = 1e-5
    m, d = _mj(model, damping_ratio=0.0, timestep_s=h)
    body = m.nbody - 1
    steps = int(round(duration / h))
    every = 100
    mujoco.mj_forward(m, d)
    tip_mj = [d.site_xpos[0].copy()]
    for i in range(1, steps + 1):
        mujoco.mj_step1(m, d)
        arm = d.site_xpos[0] - d.xipos[body]
        d.xfrc_applied[body, :3] = force
        d.xfrc_applied[body, 3:] = np.cross(arm, force)
        mujoco.mj_step2(m, d)
        if i % every == 0:
            mujoco.mj_kinematics(m, d)
            tip_mj.append(d.site_xpos[0].copy())
    tip_mj = np.array(tip_mj)
    ours = simulate(model, steps * h, tip_force=force, damping_ratio=0.0,
                    output_dt=every * h, dt=every * h / 10)
    assert ours.tip_position_m.shape == tip_mj.shape
    rest = model.tip_position()
    peak = np.abs(ours.tip_position_m[:, 2] - rest[2]).max()
    err = np.abs(ours.tip_position_m[:, 2] - tip_mj[:, 2]).max() / peak
    print(f'MuJoCo vs simulate: max tip z difference {err:.2e} of the peak')
    assert err <= 0.01
    assert abs(np.abs(tip_mj[:, 2] - rest[2]).max() - peak) <= 0.01 * peak


def test_urdf_export_reloads_as_the_same_model(model, tmp_path):
    path = export_model(model, tmp_path / "beam.urdf", "urdf")
    back = load_urdf(path)
    a, b = model.pin_model, back.pin_model
    assert a.nv == b.nv == 5
    for i in range(a.njoints):
        ia, ib = a.inertias[i], b.inertias[i]
        assert ib.mass == pytest.approx(ia.mass, rel=1e-12, abs=1e-15)
        np.testing.assert_allclose(ib.lever, ia.lever, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(ib.inertia, ia.inertia, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(b.jointPlacements[i].homogeneous,
                                   a.jointPlacements[i].homogeneous, atol=1e-15)
    np.testing.assert_allclose(back.stiffness_Nm_per_rad, model.stiffness_Nm_per_rad, rtol=1e-15)
    np.testing.assert_allclose(back.lengths_m, model.lengths_m, rtol=1e-14)
    np.testing.assert_allclose(back.tip_position(np.full(5, 0.1)),
                               model.tip_position(np.full(5, 0.1)), atol=1e-14)
    np.testing.assert_allclose(back.natural_frequencies(), model.natural_frequencies(),
                               rtol=1e-12)


def test_json_export_round_trip(model, tmp_path):
    path = export_model(model, tmp_path / "model.json", "json")
    d = json.loads(path.read_text())
    assert d["n_joints"] == 5 and len(d["links"]) == 6
    assert sum(link["mass_kg"] for link in d["links"]) == pytest.approx(model.beam.mass_kg,
                                                                         rel=1e-12)
    back = read_model_json(path)
    np.testing.assert_allclose(back.natural_frequencies(), d["natural_frequencies_rad_s"],
                               rtol=1e-12)
    np.testing.assert_allclose(back.stiffness_Nm_per_rad, model.stiffness_Nm_per_rad)


def test_export_is_atomic_and_checks_format(model, tmp_path):
    with pytest.raises(BeamInputError, match="format"):
        export_model(model, tmp_path / "x.sdf", "sdf")
    export_model(model, tmp_path / "m.xml", "mjcf")
    assert [p.name for p in tmp_path.iterdir()] == ["m.xml"]


def test_export_cli_and_simulate_cli(model, tmp_path, capsys):
    from prbdm_pin.cli import main

    src = export_model(model, tmp_path / "model.json", "json")
    assert main(["export", str(src), "--format", "urdf", "--out", str(tmp_path / "m.urdf"),
                 "--quiet"]) == 0
    assert main(["export", str(tmp_path / "m.urdf"), "--format", "mjcf",
                 "--out", str(tmp_path / "m.xml"), "-q"]) == 0
    m = mujoco.MjModel.from_xml_path(str(tmp_path / "m.xml"))
    np.testing.assert_allclose(m.jnt_stiffness, model.stiffness_Nm_per_rad, rtol=1e-15)
    out = tmp_path / "sim"
    assert main(["simulate", str(tmp_path / "m.urdf"), "--duration", "0.05",
                 "--tip-force", "0,0,-100", "--out", str(out), "-q"]) == 0
    data = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    assert data.shape == (2001, 1 + 5 + 5 + 3)
    assert (out / "response.png").stat().st_size > 0
    # the 1D beam truth (milliseconds; the plate comparison is tests/test_cli_simulate.py's)
    assert main(["simulate", str(src), "--duration", "0.05", "--compare-truth",
                 "--truth-model", "beam", "--cache-dir", str(tmp_path / "cache"),
                 "--out", str(out), "-q"]) == 0
    summary = json.loads((out / "truth_comparison.json").read_text())
    assert 0.0 < summary["frf_error"] and 0.0 < summary["step_error"]


@pytest.mark.parametrize("argv, match", [
    (["simulate", "missing.urdf", "--duration", "1", "--out", "x"], "not found"),
    (["simulate", "{model}", "--duration", "1", "--tip-force", "1,2", "--out", "x"],
     "--tip-force"),
    (["simulate", "{model}", "--duration", "-1", "--out", "x"], "--duration"),
    (["export", "{model}", "--format", "mjcf", "--damping", "-1", "--out", "x.xml"],
     "damping_ratio"),
])
def test_cli_bad_input_is_one_line_exit_2(model, tmp_path, capsys, argv, match):
    from prbdm_pin.cli import main

    src = export_model(model, tmp_path / "model.json", "json")
    argv = [a.replace("{model}", str(src)) for a in argv]
    argv = [str(tmp_path / a) if a in ("x", "x.xml") else a for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and match in err
