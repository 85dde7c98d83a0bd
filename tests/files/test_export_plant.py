"""Exports of the plant: a hub and strain actuators in MJCF (MuJoCo), URDF (Pinocchio, pybullet,
yourdfpy) and the model JSON, against independent references: Pinocchio's CRBA and ABA of the
hand-built hub model, an accurate integration of the nonlinear equations, the package's input
map and damping, and the consumers' own parsers."""

from __future__ import annotations

import json

import numpy as np
import pinocchio as pin
import pytest
import scipy.linalg as sla
from scipy.integrate import solve_ivp
from tolerances import EPS

from prbdm_pin import BeamInputError, Hub, StrainActuator, build_model, linearize, load_urdf
from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.cli import main
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.files.export import (
    export_model,
    export_record,
    mjcf_text,
    read_export_record,
    read_model_json,
    read_plant_json,
)
from prbdm_pin.model.inputs import input_map
from prbdm_pin.simulation.hub_damping import plant_damping

mujoco = pytest.importorskip("mujoco")

BEAM = load_beam("examples/beams/reference-random.json")
LENGTHS = np.array([0.15, 0.3, 0.3, 0.25]) * BEAM.length_m
SPRINGS = finite_segment_stiffness(BEAM, LENGTHS)
HUB = Hub(2.0, 0.1)
# strain[0] ends exactly on joint 2 (x = 0.45 L): coefficient 1/2 there; strain[1] spans two
ACTUATORS = (StrainActuator(0.05 * BEAM.length_m, 0.45 * BEAM.length_m),
             StrainActuator(0.2 * BEAM.length_m, 0.9 * BEAM.length_m))
# a fitted map: any real weights on every joint (negative, beyond 1)
FITTED = (StrainActuator(0.02 * BEAM.length_m, 0.08 * BEAM.length_m,
                         joint_weights=(0.43, -0.27, 1.6)),)
POSE = np.array([0.4, 0.2, -0.3, 0.5])
XI = 0.02


@pytest.fixture(scope="module")
def hub_model():
    return build_model(BEAM, LENGTHS, SPRINGS, hub=HUB)


def _mj(text):
    m = mujoco.MjModel.from_xml_string(text)
    return m, mujoco.MjData(m)


def _full_M(m, d, q):
    d.qpos[:] = q
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    return M


def _crba(model, q):
    M = pin.crba(model.pin_model, model.new_data(), q)
    return np.triu(M) + np.triu(M, 1).T


def test_mjcf_hub_mass_matrix_frequencies_and_damping(hub_model):
    """MuJoCo's M at a bent pose is Pinocchio's CRBA of the hub model; its frequencies (mj_fullM
    and jnt_stiffness, generalized eigenproblem) are the model's; its joint damping is the
    plant's stiffness form (linearize's), the hub joint undamped; the record keeps the clamped
    model's frequencies and adds the hub model's flexible ones."""
    m, d = _mj(mjcf_text(hub_model, XI))
    assert m.nv == 4 and m.joint(0).name == "hub" and m.jnt_stiffness[0] == 0.0
    M = _full_M(m, d, POSE)
    ref = _crba(hub_model, POSE)
    assert np.abs(M - ref).max() <= 1e-10 * np.abs(ref).max()
    M0 = _full_M(m, d, np.zeros(4))
    w2 = sla.eigh(np.diag(m.jnt_stiffness), M0, eigvals_only=True)
    omega = hub_model.natural_frequencies()
    assert abs(w2[0]) <= 1e-9 * w2[-1] and omega[0] == 0.0
    np.testing.assert_allclose(np.sqrt(w2[1:]), omega[1:], rtol=1e-10)
    lin = linearize(hub_model, inputs=("hub_torque",), outputs=("hub_angle",),
                    damping="stiffness", damping_ratio=XI)
    # the file's damping is this beta K written in full (exact here); kept: the test's 1e-12
    np.testing.assert_allclose(np.diag(np.array(m.dof_damping)), lin.damping_Nms_per_rad,
                               rtol=5000 * EPS, atol=0.0)
    assert m.dof_damping[0] == 0.0
    rec = read_export_record(mjcf_text(hub_model, XI))
    clamped = build_model(BEAM, LENGTHS, SPRINGS)
    np.testing.assert_allclose(rec.natural_frequencies_rad_s, clamped.natural_frequencies(),
                               rtol=1e-10)
    np.testing.assert_allclose(rec.hub_frequencies_rad_s, np.sqrt(w2[1:]), rtol=1e-10)
    # the lowest flexible mode of the hub model gets the asked ratio, the others more
    assert rec.modal_damping_ratios[0] == pytest.approx(XI, rel=1e-9)
    np.testing.assert_allclose(rec.modal_damping_ratios,
                               XI * rec.hub_frequencies_rad_s / rec.hub_frequencies_rad_s[0],
                               rtol=1e-9)


def test_record_errors_are_the_clamped_models(hub_model):
    """Against truth frequencies, a hub model's record gives the clamped model's errors."""
    clamped = build_model(BEAM, LENGTHS, SPRINGS)
    truth = clamped.natural_frequencies() * np.array([1.01, 0.995, 1.002])
    rec = export_record(hub_model, "mjcf", XI, omega_truth_rad_s=truth)
    np.testing.assert_allclose(rec.omega_errors_pct, [100 / 1.01 - 100, 100 / 0.995 - 100,
                                                      100 / 1.002 - 100], rtol=1e-8)
    assert "hub_frequencies_rad_s" in rec.comment_text()


def test_mjcf_actuators_apply_the_input_map(hub_model):
    """MuJoCo's actuator moments at a bent pose are input_map's columns for every input kind:
    the hub and joint motors, the strain tendons (1/2 on the joint a patch end sits on) and the
    tip forces through a site transmission with a world reference site (a dead world force)."""
    names = ("hub_torque", "joint_torque[1]", "strain[0]", "strain[1]", "tip_force_z",
             "tip_force_x")
    m, d = _mj(mjcf_text(hub_model, XI, actuators=ACTUATORS, inputs=names))
    assert [m.actuator(i).name for i in range(m.nu)] == [
        "hub_torque", "joint_torque_1", "strain_0", "strain_1", "tip_force_z", "tip_force_x"]
    assert not np.any(m.actuator_ctrllimited)
    d.qpos[:] = POSE
    mujoco.mj_forward(m, d)
    moment = np.zeros((m.nu, m.nv))
    mujoco.mju_sparse2dense(moment, d.actuator_moment, d.moment_rownnz, d.moment_rowadr,
                            d.moment_colind)
    B = input_map(hub_model, POSE, names, ACTUATORS)
    # MuJoCo's transmissions against the package's input map: two kinematics of a 1 m chain
    # (2 EPS measured); kept: the test's 1e-12 and 1e-15 (m)
    np.testing.assert_allclose(moment.T, B, rtol=5000 * EPS, atol=5 * EPS)
    # patch 0 from 0.05 L to 0.45 L: joint 1 (0.15 L) inside, joint 2 (0.45 L) under its end
    np.testing.assert_array_equal(moment[2], [0.0, 1.0, 0.5, 0.0])


def test_mjcf_fitted_weights_are_the_tendon_coefficients(hub_model):
    """A fitted map (a patch inside link 0, which the virtual-work map leaves without any joint)
    gives MuJoCo the same actuator moment as input_map: the weights on the beam joints, none on
    the hub; the record carries the weights and reads them back."""
    acts = ACTUATORS + FITTED
    names = ("hub_torque", "strain[0]", "strain[2]")
    text = mjcf_text(hub_model, XI, actuators=acts, inputs=names)
    m, d = _mj(text)
    d.qpos[:] = POSE
    mujoco.mj_forward(m, d)
    moment = np.zeros((m.nu, m.nv))
    mujoco.mju_sparse2dense(moment, d.actuator_moment, d.moment_rownnz, d.moment_rowadr,
                            d.moment_colind)
    # exact by construction: hub joint and tendons, their coefficients written in full; slack
    # 5 EPS (the test's 1e-15)
    np.testing.assert_allclose(moment.T, input_map(hub_model, POSE, names, acts), rtol=5 * EPS,
                               atol=0.0)
    np.testing.assert_array_equal(moment[2], [0.0, 0.43, -0.27, 1.6])
    assert read_export_record(text).actuators() == acts


def test_mjcf_default_inputs(hub_model):
    """Default inputs: hub_torque with a hub and strain[i] for every actuator; a clamped model
    without actuators gets none (the file is as before)."""
    m, _ = _mj(mjcf_text(hub_model, XI, actuators=ACTUATORS))
    assert [m.actuator(i).name for i in range(m.nu)] == ["hub_torque", "strain_0", "strain_1"]
    m, _ = _mj(mjcf_text(build_model(BEAM, LENGTHS, SPRINGS), XI))
    assert m.nu == 0 and m.ntendon == 0


def _reference_run(model, names, actuators, u, duration_s, xi):
    """Hub angle and tip z of the nonlinear equations M(q) a = -K q - C v + B(q) u(t) by
    Pinocchio's ABA, integrated by DOP853 at rtol 1e-10; C the plant's stiffness form."""
    K = model.stiffness_matrix()
    C = plant_damping(model, model.mass_matrix(), xi, "stiffness")
    data = model.new_data()
    nv = model.pin_model.nv

    def rhs(t, x):
        q, v = x[:nv], x[nv:]
        tau = -K @ q - C @ v + input_map(model, q, names, actuators) @ u(t)
        return np.concatenate([v, pin.aba(model.pin_model, data, q, v, tau)])

    t = np.linspace(0.0, duration_s, 501)
    # the integrator's request: rtol 1e-10, atol 4500 EPS (1e-12 m, rad)
    sol = solve_ivp(rhs, (0.0, duration_s), np.zeros(2 * nv), method="DOP853", t_eval=t,
                    rtol=1e-10, atol=4500 * EPS)
    assert sol.success
    tip_z = np.array([model.tip_position(q)[2] for q in sol.y[:nv].T])
    return t, sol.y[0], tip_z


def _mujoco_run(text, u, duration_s, step_s, every):
    """Hub angle and tip z of MuJoCo (RK4): the control held over a step is the input at the
    step's midpoint (second order in the step, as RK4 needs for a smooth input)."""
    m, d = _mj(text)
    m.opt.timestep = step_s
    tip = m.site("tip").id
    mujoco.mj_forward(m, d)
    hub, z = [d.qpos[0]], [d.site_xpos[tip][2]]
    for i in range(int(round(duration_s / step_s))):
        d.ctrl[:] = u((i + 0.5) * step_s)
        mujoco.mj_step(m, d)
        if (i + 1) % every == 0:
            mujoco.mj_kinematics(m, d)
            hub.append(d.qpos[0])
            z.append(d.site_xpos[tip][2])
    return np.array(hub), np.array(z)


def hub_and_strain_input(t: float) -> np.ndarray:
    """A 40 N m hub torque step and a 300 N m, 30 rad/s strain moment on the patch whose end
    sits on joint 2."""
    return np.array([40.0, 300.0 * np.sin(30.0 * t)])


@pytest.mark.parametrize("patch", [0, 1], ids=["end-on-joint", "inside"])
def test_mujoco_time_response_matches_the_nonlinear_equations(hub_model, patch):
    """A hub-torque step and a sine on one strain patch over 0.5 s: MuJoCo (RK4, 0.1 ms) of the
    MJCF against DOP853 of Pinocchio's ABA with the input map: hub angle and tip z within
    0.5 % of their peaks."""
    names = ("hub_torque", f"strain[{patch}]")
    text = mjcf_text(hub_model, XI, actuators=ACTUATORS, inputs=names)
    t, hub_ref, z_ref = _reference_run(hub_model, names, ACTUATORS, hub_and_strain_input, 0.5,
                                       XI)
    hub_mj, z_mj = _mujoco_run(text, hub_and_strain_input, 0.5, 1e-4, 10)
    assert np.abs(hub_ref).max() > 0.1 and np.abs(z_ref).max() > 0.05  # a large motion
    for ours, ref in ((hub_mj, hub_ref), (z_mj, z_ref)):
        assert np.abs(ours - ref).max() <= 5e-3 * np.abs(ref).max()


def test_urdf_hub_reads_back_in_every_consumer(hub_model, tmp_path):
    """The URDF of a hub model: load_urdf gives a hub model with build_model's M(q) and
    frequencies; pybullet and yourdfpy read the hub joint, the masses and the same M(q)."""
    from consumers import pybullet_mass_and_damping, yourdfpy_mass_and_damping

    path = export_model(hub_model, tmp_path / "hub.urdf", "urdf", XI, actuators=ACTUATORS)
    back = load_urdf(path)
    assert back.hub == HUB and back.n_joints == 3
    # exact by construction (lengths written in full); slack 5 EPS (the test's 1e-15)
    np.testing.assert_allclose(back.lengths_m, LENGTHS, rtol=5 * EPS)
    poses = [np.zeros(4), POSE]
    for q in poses:
        ref = hub_model.mass_matrix(q)
        assert np.abs(back.mass_matrix(q) - ref).max() <= 1e-12 * np.abs(ref).max()
        # the same mass matrix (to the bound above) through the same solve: exact here;
        # kept: the test's 1e-12
        np.testing.assert_allclose(back.natural_frequencies(q)[1:],
                                   hub_model.natural_frequencies(q)[1:], rtol=5000 * EPS)
    Ms, damping, masses = pybullet_mass_and_damping(path, poses)
    assert masses["hub_body"] == 0.0 and masses["tip"] == 0.0
    for i in range(4):
        # exact by construction (masses written in full); slack: the test's 1e-12
        assert masses[f"link_{i}"] == pytest.approx(hub_model.sections.mass_kg[i],
                                                    rel=5000 * EPS)
    Ms_y, damping_y = yourdfpy_mass_and_damping(path, poses)
    for q, M, My in zip(poses, Ms, Ms_y, strict=True):
        ref = hub_model.mass_matrix(q)
        assert np.abs(M - ref).max() <= 1e-9 * np.abs(ref).max()
        assert np.abs(My - ref).max() <= 1e-9 * np.abs(ref).max()
    C = plant_damping(hub_model, hub_model.mass_matrix(), XI, "stiffness")
    # exact by construction (beta k written in full, read back); slack: the tests' 1e-12
    np.testing.assert_allclose(damping, np.diag(C), rtol=5000 * EPS, atol=0.0)
    np.testing.assert_allclose(damping_y, np.diag(C), rtol=5000 * EPS, atol=0.0)
    # URDF has no tendons: the actuators are in the record, read back as written
    rec = read_export_record(path.read_text())
    np.testing.assert_array_equal(rec.strain_actuators_m,
                                  [[a.x_start_m, a.x_end_m] for a in ACTUATORS])
    assert rec.inputs == ()


def test_json_round_trip_rebuilds_hub_and_actuators(hub_model, tmp_path):
    path = export_model(hub_model, tmp_path / "m.json", "json", actuators=ACTUATORS)
    d = json.loads(path.read_text())
    assert d["hub"] == {"inertia_kg_m2": 2.0, "radius_m": 0.1, "axis": "y"}
    assert d["actuators"][0] == {"x_start_m": 0.05 * BEAM.length_m,
                                 "x_end_m": 0.45 * BEAM.length_m}
    model, acts = read_plant_json(path)
    assert model.hub == HUB and acts == ACTUATORS
    # fitted weights are recorded with their actuator and read back; virtual-work ones are not
    path = export_model(hub_model, tmp_path / "f.json", "json", actuators=ACTUATORS + FITTED)
    d2 = json.loads(path.read_text())
    assert "joint_weights" not in d2["actuators"][0]
    assert d2["actuators"][2]["joint_weights"] == [0.43, -0.27, 1.6]
    assert read_plant_json(path)[1] == ACTUATORS + FITTED
    # the plant read back builds the same Pinocchio chain: the same CRBA (exact here); kept:
    # the test's 1e-14 and 1e-15 (kg m^2)
    np.testing.assert_allclose(model.mass_matrix(POSE), _crba(hub_model, POSE), rtol=50 * EPS,
                               atol=5 * EPS)
    assert read_model_json(path).hub == HUB
    # a file without the plant fields reads as the clamped beam without actuators
    del d["hub"], d["actuators"]
    path.write_text(json.dumps(d))
    model, acts = read_plant_json(path)
    assert model.hub is None and acts == () and model.pin_model.nv == 3


@pytest.mark.parametrize("field, value, needle", [
    ("hub", {"inertia_kg_m2": -1.0, "radius_m": 0.1}, "hub.inertia_kg_m2 = -1.0"),
    ("hub", {"inertia_kg_m2": 1.0}, "hub.radius_m: missing"),
    ("actuators", [{"x_start_m": 0.1, "x_end_m": 0.2}, {"x_start_m": 0.1, "x_end_m": 2.0}],
     "actuators[1].x_end_m = 2.0: must lie on the beam"),
    ("actuators", [{"x_start_m": 0.5, "x_end_m": 0.2}], "actuators[0].x_end_m = 0.2"),
    ("actuators", [{"x_start_m": "a", "x_end_m": 0.2}], "actuators[0].x_start_m = 'a'"),
    ("actuators", [{"x_start_m": 0.1, "x_end_m": 0.2, "joint_weights": [0.5, 0.1]}],
     "actuators[0].joint_weights: has 2 entries, this model has 3 joints"),
    ("actuators", [{"x_start_m": 0.1, "x_end_m": 0.2, "joint_weights": [0.5, None, 0]}],
     "actuators[0].joint_weights[1] = None"),
])
def test_hand_edited_model_json_is_refused_naming_the_field(hub_model, tmp_path, capsys,
                                                            field, value, needle):
    path = export_model(hub_model, tmp_path / "m.json", "json", actuators=ACTUATORS)
    d = json.loads(path.read_text())
    d[field] = value
    path.write_text(json.dumps(d))
    with pytest.raises(BeamInputError, match=needle.replace("[", r"\[").replace("]", r"\]")):
        read_plant_json(path)
    assert main(["export", str(path), "--format", "mjcf", "--out",
                 str(tmp_path / "x.xml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err, err


@pytest.fixture(scope="module")
def clamped_json(tmp_path_factory):
    return export_model(build_model(BEAM, LENGTHS, SPRINGS),
                        tmp_path_factory.mktemp("m") / "model.json", "json")


@pytest.mark.parametrize("argv, needle", [
    (["--hub=-1:0.1"], "--hub = '-1:0.1': Hub inertia_kg_m2 = -1.0"),
    (["--hub", "1"], "--hub = '1'"),
    (["--actuator", "0.5:0.2"], "--actuator = '0.5:0.2'"),
    (["--actuator", "0.5:1.5"], "--actuator = '0.5:1.5': x_end_m = 1.5: must lie on the beam"),
    (["--inputs", "strain[0]"], "inputs[0] = 'strain[0]'"),
    (["--inputs", "hub_torque"], "inputs[0] = 'hub_torque'"),
    (["--format", "urdf", "--inputs", "tip_force_z"], "--inputs = 'tip_force_z'"),
])
def test_cli_bad_plant_options_exit_2_with_one_line(clamped_json, tmp_path, capsys, argv,
                                                    needle):
    out = tmp_path / "never.xml"
    fmt = [] if "--format" in argv else ["--format", "mjcf"]
    assert main(["export", str(clamped_json), *fmt, "--out", str(out), *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("prbdm export: error: "), err
    assert needle in err, err
    assert not out.exists()


def test_cli_export_carries_the_plant_through_files(clamped_json, hub_model, tmp_path):
    """--hub and --actuator on a clamped model JSON; the hub model JSON and URDF written so
    carry hub and actuators into the next MJCF; MuJoCo reads the same M and actuator moments
    as the hub model's CRBA and input map."""
    first = tmp_path / "plant.json"
    acts = [f"{a.x_start_m!r}:{a.x_end_m!r}" for a in ACTUATORS]
    assert main(["export", str(clamped_json), "--format", "json", "--hub", "2:0.1",
                 "--actuator", acts[0], "--actuator", acts[1], "--out", str(first), "-q"]) == 0
    urdf = tmp_path / "plant.urdf"
    assert main(["export", str(first), "--format", "urdf", "--out", str(urdf), "-q"]) == 0
    names = ("hub_torque", "strain[1]", "tip_force_z")
    for src in (first, urdf):
        xml = tmp_path / f"{src.suffix[1:]}.xml"
        assert main(["export", str(src), "--format", "mjcf", "--inputs", ",".join(names),
                     "--out", str(xml), "-q"]) == 0
        m = mujoco.MjModel.from_xml_path(str(xml))
        d = mujoco.MjData(m)
        M = _full_M(m, d, POSE)
        ref = _crba(hub_model, POSE)
        assert np.abs(M - ref).max() <= 1e-10 * np.abs(ref).max()
        moment = np.zeros((m.nu, m.nv))
        mujoco.mju_sparse2dense(moment, d.actuator_moment, d.moment_rownnz, d.moment_rowadr,
                                d.moment_colind)
        # as in test_mjcf_actuators_apply_the_input_map (exact here); kept: 1e-12, 1e-15 (m)
        np.testing.assert_allclose(moment.T, input_map(hub_model, POSE, names, ACTUATORS),
                                   rtol=5000 * EPS, atol=5 * EPS)
