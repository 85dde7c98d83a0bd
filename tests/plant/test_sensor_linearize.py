"""linearize() with sensor outputs: the state space's C and D (the acceleration path of the
root reaction and the strain near the root) against central differences of the nonlinear
outputs, whose acceleration is Pinocchio's ABA of the full equations of motion here; the root
reaction's step response against a nonlinear simulate at small amplitude; bad outputs
refused by name.

References: central differences (tests/central_differences.py) of y(q, v, u) with a(q, v, u)
from ``pinocchio.aba`` (springs, damping, weight, the tip load and the inputs' forces); a
nonlinear time response (DOP853) of a small step."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from central_differences import central_difference
from paths import ROOT
from scipy.linalg import expm
from tolerances import EPS, REFERENCE_RTOL

from prbdm_pin import Hub, build_model, linearize, simulate
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.model.inputs import input_map, parse_inputs
from prbdm_pin.model.load_outputs import is_load_output, load_output_values
from prbdm_pin.model.outputs import output_values, parse_outputs
from prbdm_pin.model.reaction import input_loads

BEAM = load_beam(ROOT / "examples/beams/uniform-narrow.json")
LENGTHS = np.array([0.2, 0.3, 0.3, 0.2])
SPRINGS = np.array([1000.0, 800.0, 500.0])
SENSORS = ("root_force_x", "root_force_z", "root_moment_y", "root_moment_z", "strain@0.05",
           "strain@0.35", "strain@0.95", "slope@0.6", "point_z@0.7:0.02", "tip_z")


def _model(kind):
    if kind == "planar":
        return build_model(BEAM, LENGTHS, SPRINGS)
    if kind == "hub":
        return build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(5.0, 0.05))
    return build_model(BEAM, LENGTHS, np.repeat(SPRINGS, 3), axes="xyz")


def _nonlinear_outputs(model, lin, names, in_names, F, g):
    """y(x, du): the outputs in the state x = (q, v) under the input deviations du.

    The tip load F is the tip force inputs' nominal value (``u_eq``): the tip force is F + du;
    the other inputs act at u_eq + du (the hub's trim torque).
    """
    pm = pin.Model(model.pin_model)
    pm.gravity = pin.Motion(np.concatenate([g, np.zeros(3)]))
    data = pm.createData()
    nv = pm.nv
    parsed_out = parse_outputs(names, model.n_springs, model.hub is not None)
    parsed_in = parse_inputs(in_names, model.n_springs, 0, model.hub is not None)
    kinematic = [n for n, b, _ in parsed_out if not is_load_output(b)]
    rows = [i for i, (_, b, _) in enumerate(parsed_out) if not is_load_output(b)]
    K = np.diag(model.stiffness_matrix())
    Cd = lin.damping_Nms_per_rad
    held = np.array([0.0 if b.startswith("tip_force") else u for (_, b, _), u in
                     zip(parsed_in, lin.u_eq, strict=True)])

    def y(x, du):
        q, v = x[:nv], x[nv:]
        u = held + du
        tau = -K * q - Cd @ v + model.tip_jacobian(q).T @ F + input_map(model, q, in_names) @ u
        a = pin.aba(pm, data, q, v, tau)
        out = load_output_values(model, q, v, a, parsed_out, input_loads(parsed_in, u, F), g)
        out[rows] = output_values(model, q, kinematic)
        return out

    return y


@pytest.mark.parametrize("kind", ["planar", "hub", "spatial"])
def test_C_and_D_match_central_differences_of_the_nonlinear_outputs(kind):
    model = _model(kind)
    in_names = ("tip_force_z", "tip_force_x", "tip_moment_y", "joint_torque[1]") + (
        ("hub_torque",) if kind == "hub" else ("corner_force_z_left",))
    F = np.array([0.0, 0.0, 20.0])
    g = np.array([0.0, 0.0, -9.81]) if kind != "spatial" else np.array([0.0, -4.0, -9.81])
    lin = linearize(model, inputs=in_names, outputs=SENSORS, load_N=F, gravity_m_s2=g,
                    damping_ratio=0.05)
    y = _nonlinear_outputs(model, lin, SENSORS, in_names, F, g)
    x_eq = np.concatenate([lin.q_eq, np.zeros(model.pin_model.nv)])
    du0 = np.zeros(len(in_names))
    y_eq = y(x_eq, du0)
    scale = np.abs(y_eq) + 1.0
    # the equilibrium (Newton to rtol 1e-10 of the spring torques): the nonlinear outputs at
    # rest there are the linear model's y_eq, the reaction's rest value the weight and the load
    assert np.all(np.abs(y_eq - lin.y_eq) <= 1e-7 * scale)
    # each output a sum of a few terms of its own scale: a few roundings of it
    noise = 64 * EPS * scale
    Cfd, Cerr = central_difference(lambda x: y(x, du0), x_eq, 1e-5, noise)
    Dfd, Derr = central_difference(lambda du: y(x_eq, du), du0, 1e-3, noise)
    assert np.all(np.abs(lin.C - Cfd) <= Cerr), np.abs(lin.C - Cfd).max()
    assert np.all(np.abs(lin.D - Dfd) <= Derr), np.abs(lin.D - Dfd).max()
    # the direct path is not empty (its value is checked above): an axial tip force reaches the
    # root through the links at once, a transverse one mostly through their inertia
    assert abs(lin.D[0, 1]) > 0.9 and abs(lin.D[1, 0]) > 0.01


@pytest.mark.parametrize(("kind", "step"), [("planar", "tip_force_z"), ("hub", "hub_torque")])
def test_root_reaction_step_response_matches_a_nonlinear_run(kind, step):
    model = _model(kind)
    # (the axial root force is second order here: the linear model has none)
    outs = ("root_force_z", "root_moment_y", "strain@0.05", "strain@0.5")
    lin = linearize(model, inputs=(step,), outputs=outs, damping_ratio=0.02)
    dt, T = 2e-4, 0.2  # s: the lowest period is 0.18 s
    t = np.arange(0.0, T + dt / 2, dt)
    # the linear model's exact zero-order-hold response: exp([[A, B], [0, 0]] dt)
    n, m = lin.B.shape
    E = expm(np.block([[lin.A, lin.B], [np.zeros((m, n + m))]]) * dt)
    Ad, Bd = E[:n, :n], E[:n, n:]
    errors = []
    for A_N in (0.05, 0.1):  # N or N m: angles ~ 1e-4 rad
        x = np.zeros(lin.A.shape[0])
        Y = np.empty((t.size, len(outs)))
        for k in range(t.size):
            Y[k] = lin.C @ x + lin.D[:, 0] * A_N
            x = Ad @ x + Bd[:, 0] * A_N
        # DOP853 at rtol 1e-12: its error stays below the O(q^2) being measured (the
        # exponential integrator's on a hub, ~4e-7 of the response, would not)
        run = simulate(model, T, inputs=(step,), u=np.array([A_N]), outputs=outs,
                       output_dt_s=dt, damping_ratio=0.02, method="DOP853",
                       rtol=REFERENCE_RTOL)
        peak = np.abs(Y).max(axis=0)
        run_y = run.output_values
        q_max = np.abs(run.q_rad).max()
        err = np.abs(run_y - Y).max(axis=0) / peak
        # the chain's geometric and velocity terms are even in the motion (cos, sin x sin, v^2):
        # what the linear model leaves out is O(q^2) of the response
        assert np.all(err <= 10.0 * q_max**2), (err, q_max)
        # at t = 0+ the member has not moved: the root feels the step through D alone
        assert np.allclose(run_y[0], Y[0], rtol=10.0 * q_max**2, atol=0.0)
        errors.append(err)
    # twice the step, four times the error: the linear model is the response's exact first
    # order (an error in C or D would grow with the step, not its square)
    ratio = errors[1] / errors[0]
    assert np.all((ratio > 3.5) & (ratio < 4.5)), ratio


def test_bad_sensor_outputs_are_refused_by_name(tmp_path):
    model = _model("planar")
    with pytest.raises(BeamInputError, match=r"outputs\[1\] = 'strain@1.2': station x = 1.2 m "
                                             "is off the member"):
        linearize(model, outputs=("tip_z", "strain@1.2"))
    with pytest.raises(BeamInputError, match=r"outputs\[0\] = 'point_y@0.2:0.5': point y = "
                                             "0.5 m is off the planform"):
        simulate(model, 0.01, outputs=("point_y@0.2:0.5",))
    with pytest.raises(BeamInputError, match=r"outputs\[0\] = 'root_torque_y': unknown"):
        linearize(model, outputs=("root_torque_y",))
