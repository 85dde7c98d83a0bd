"""linearize() of a spatial chain against independent references: central differences of
Pinocchio's ABA with the springs, the tip load and the inputs as external forces on the last
joint; the planar chain's linearisation (a different code path: closed-form planar kernels);
simulate() of the nonlinear chain; the rigid-body geometry of the tip corners."""

import numpy as np
import pinocchio as pin
import pytest
import scipy.linalg
from paths import ROOT
from tolerances import EPS

from prbdm_pin import build_model, linearize, simulate
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.files.beam_file import load_beam

BEAM = load_beam(ROOT / "examples/beams/reference-random.json")
LENGTHS = np.array([0.15, 0.3, 0.2, 0.35]) * BEAM.length_m
INPUTS = ("tip_force_z", "tip_force_y", "tip_force_x", "tip_moment_x", "corner_force_z_left",
          "corner_force_z_right", "joint_torque[4]")
OUTPUTS = ("tip_z", "tip_y", "tip_x", "tip_twist", "corner_z_left", "corner_z_right", "q[5]",
           "q_rate[2]", "tip_z_rate", "spring_torque[3]")
W = float(BEAM.half_width_m[-1])


def _model(axes="xyz"):
    return build_model(BEAM, LENGTHS, spatial_stiffness(BEAM, LENGTHS, axes), axes=axes)


def _load(model, fz=-0.4, fy=0.15):
    """A dead tip load that bends the chain by tenths of a radian: a multiple of k_y / L."""
    k = float(np.min(model.stiffness_Nm_per_rad[model.axis_index("y")]))
    return np.array([0.0, fy, fz]) * k / BEAM.length_m


def _point_force(pm, data, tip, offset, F, m):
    """World force F at the point ``offset`` (tip frame) and world moment m, as the last joint's
    external force in its local frame."""
    jid = pm.frames[tip].parentJoint
    R = data.oMi[jid].rotation
    X = pm.frames[tip].placement
    p_local = X.translation + X.rotation @ offset
    f_local, m_local = R.T @ F, R.T @ m
    return pin.Force(f_local, np.cross(p_local, f_local) + m_local)


def _dynamics(model, Cd, load):
    """x' = f(x, u) through pin.aba, every load an external force (no code of linearize)."""
    pm = model.pin_model
    data = pm.createData()
    nv, k, tip = pm.nv, model.stiffness_Nm_per_rad, model.tip_frame_id
    ey = np.array([0.0, 1.0, 0.0])
    points = {"tip_force": np.zeros(3), "corner_force_z_left": W * ey,
              "corner_force_z_right": -W * ey}

    def f(x, u):
        q, v = x[:nv], x[nv:]
        tau = -k * q - Cd @ v
        forces = {"tip_force": np.array(load, dtype=float)}
        m = np.zeros(3)
        for name, ui in zip(INPUTS, u, strict=True):
            if name.startswith("tip_force_"):
                forces["tip_force"][" xyz".index(name[-1]) - 1] += ui
            elif name.startswith("corner_"):
                forces[name] = np.array([0.0, 0.0, ui])
            elif name == "tip_moment_x":
                m[0] += ui
            else:
                tau[int(name[13:-1])] += ui
        pin.forwardKinematics(pm, data, q)
        total = pin.Force.Zero()
        for i, (name, F) in enumerate(forces.items()):
            total += _point_force(pm, data, tip, points[name], F, m if i == 0 else np.zeros(3))
        fext = [pin.Force.Zero() for _ in range(pm.njoints)]
        fext[pm.frames[tip].parentJoint] = total
        return np.concatenate([v, pin.aba(pm, data, q, v, tau, fext)])

    return f


def _outputs(model):
    """y(x) from Pinocchio's placements: the tip, its roll about its own axis, the corners."""
    pm = model.pin_model
    data = pm.createData()
    nv = pm.nv

    def y(x):
        q, v = x[:nv], x[nv:]
        J = pin.computeFrameJacobian(pm, data, q, model.tip_frame_id,
                                     pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)[:3]
        M = pin.updateFramePlacement(pm, data, model.tip_frame_id)
        p, R = M.translation, M.rotation
        left, right = p + W * R[:, 1], p - W * R[:, 1]
        # the roll of a z-y-x (yaw, pitch, roll) decomposition: the twist's definition
        roll = np.arctan2(R[2, 1], R[2, 2])
        return np.array([p[2], p[1], p[0], roll, left[2], right[2], q[5], v[2], (J @ v)[2],
                         model.stiffness_Nm_per_rad[3] * q[3]])

    return y


def _central(f, x0, h):
    return np.column_stack([(f(x0 + h * e) - f(x0 - h * e)) / (2 * h) for e in np.eye(x0.size)])


@pytest.mark.parametrize("axes", ["xyz", "xy"])
def test_A_B_C_equal_central_differences_at_the_loaded_equilibrium(axes):
    model = _model(axes)
    load = _load(model)
    inputs = INPUTS if axes == "xyz" else INPUTS[:-1]  # joint_torque[4] is a z spring of xyz
    lin = linearize(model, inputs=inputs, outputs=OUTPUTS, load_N=load)
    nv = model.pin_model.nv
    assert np.max(np.abs(lin.q_eq)) > 0.05  # a deflected pose, not the straight one
    assert abs(lin.y_eq[3]) > 1e-3  # a lateral force on a bent chain twists its tip
    f = _dynamics(model, lin.damping_Nms_per_rad, load)
    if axes != "xyz":
        f0 = f

        def f(x, u):
            return f0(x, np.append(u, 0.0))
    x0 = np.concatenate([lin.q_eq, np.zeros(nv)])
    u0 = np.zeros(len(inputs))
    # the equilibrium: the residual rounding of K q against J^T F, over M (cond ~ spread of A)
    assert np.max(np.abs(f(x0, u0)[nv:])) < 1e-8 * np.max(np.abs(lin.A))
    h = 1e-6  # central differences: truncation h^2 |f'''| ~ 1e-12 relative, rounding EPS / h
    Afd = _central(lambda x: f(x, u0), x0, h)
    # ABA is linear in the forces: no truncation, so a step of the load's size keeps the
    # rounding of the large, cancelling K q - J^T F (EPS omega_max^2 |q| / h) small
    Bfd = _central(lambda u: f(x0, u), u0, float(np.abs(load).max()))
    np.testing.assert_allclose(lin.A, Afd, rtol=1e-6, atol=1e-6 * np.max(np.abs(lin.A)))
    np.testing.assert_allclose(lin.B, Bfd, rtol=1e-6, atol=1e-6 * np.max(np.abs(lin.B)))
    y = _outputs(model)
    Cfd = _central(y, x0, h)
    # the outputs are smooth in q of unit scale: truncation ~h^2, rounding EPS L / h ~ 1e-10 L
    np.testing.assert_allclose(lin.C, Cfd, rtol=1e-7, atol=1e-9 * BEAM.length_m)
    # the same placements two ways (the tip's and the corners' rotated offsets): rounding of
    # a few 3x3 products on L-sized numbers
    np.testing.assert_allclose(lin.y_eq, y(x0), rtol=500 * EPS, atol=500 * EPS * BEAM.length_m)


def test_the_y_block_under_an_out_of_plane_load_is_the_planar_chain():
    spatial = _model("xyz")
    y = spatial.axis_index("y")
    planar = build_model(BEAM, LENGTHS, spatial.stiffness_Nm_per_rad[y])
    load = _load(spatial, fz=-0.5, fy=0.0)  # in the xz plane: no twist, no in-plane bending
    names = dict(inputs=("tip_force_z", "tip_force_x"), outputs=("tip_z", "tip_x", "tip_z_rate"),
                 load_N=load, damping_ratio=0.0)
    ls, lp = linearize(spatial, **names), linearize(planar, **names)
    n = spatial.pin_model.nv
    other = np.setdiff1d(np.arange(n), y)
    assert np.max(np.abs(ls.q_eq[other])) == 0.0  # no force leaves the plane: exactly zero
    # the equilibria: two Newton solvers to rtol 1e-10 on the springs' torques
    np.testing.assert_allclose(ls.q_eq[y], lp.q_eq, rtol=1e-9, atol=1e-9 * np.abs(lp.q_eq).max())
    K, M = ls.stiffness_Nm_per_rad, ls.mass_kg_m2
    # out of plane and in plane decouple: the symmetry plane xz holds the loaded chain
    scale_k, scale_m = np.abs(K).max(), np.abs(M).max()
    assert np.abs(K[np.ix_(y, other)]).max() <= 1e-9 * scale_k
    assert np.abs(M[np.ix_(y, other)]).max() <= 50 * EPS * n * scale_m
    # K_e: the exact spatial tangent against the closed-form planar one at poses equal to
    # 1e-9 (above): the load term F L ~ k moves by about that much
    np.testing.assert_allclose(K[np.ix_(y, y)], lp.stiffness_Nm_per_rad, rtol=1e-8,
                               atol=1e-8 * scale_k)
    # CRBA through the massless node links against CRBA of the planar chain: sums of n terms
    np.testing.assert_allclose(M[np.ix_(y, y)], lp.mass_kg_m2, rtol=1e-8, atol=1e-8 * scale_m)
    ys = np.concatenate([y, n + y])
    # A = M^-1 K: the two inputs' gaps times cond(M) (~1e3 here) and the 1e-8 above
    np.testing.assert_allclose(ls.A[np.ix_(ys, ys)], lp.A, rtol=1e-5,
                               atol=1e-5 * np.abs(lp.A).max())
    np.testing.assert_allclose(ls.B[ys], lp.B, rtol=1e-5, atol=1e-5 * np.abs(lp.B).max())
    np.testing.assert_allclose(ls.C[:, ys], lp.C, rtol=1e-8, atol=1e-8 * np.abs(lp.C).max())
    assert np.abs(ls.B[np.concatenate([other, n + other])]).max() <= 1e-9 * np.abs(lp.B).max()


def _step(lin, t, u):
    """Unit-free step response y(t) = C A^-1 (e^{At} - I) B u of the linear model."""
    n = lin.A.shape[0]
    out = []
    for ti in t:
        E = scipy.linalg.expm(np.block([[lin.A, lin.B @ u[:, None]],
                                        [np.zeros((1, n + 1))]]) * ti)
        out.append(lin.C @ E[:n, n])
    return np.array(out)


def test_step_response_equals_the_nonlinear_simulation_at_small_amplitude():
    model = _model("xyz")
    load = _load(model, fz=-0.3, fy=0.0)
    outputs = ("tip_z", "tip_y", "tip_twist", "corner_z_left")
    lin = linearize(model, inputs=("tip_force_y", "tip_force_z"), outputs=outputs,
                    load_N=load, damping_ratio=0.05)
    delta = 1e-4 * np.abs(load).max()  # a step small against the load: nonlinearity ~1e-4
    du = np.array([delta, 0.5 * delta])
    w1 = lin.modal().omega_rad_s[0]
    T = 3 * 2 * np.pi / w1
    traj = simulate(model, T, q0=lin.q_eq, tip_force=load + np.array([0.0, *du]),
                    outputs=outputs, damping_ratio=0.05, output_dt_s=T / 60)
    y_lin = _step(lin, traj.t_s, du)
    y_nl = traj.output_values - lin.y_eq
    for j in range(len(outputs)):
        peak = np.abs(y_lin[:, j]).max()
        assert peak > 0.0
        # second order in the step (delta / load = 1e-4) and the integrator's local error
        assert np.abs(y_nl[:, j] - y_lin[:, j]).max() <= 2e-3 * peak, outputs[j]


def test_corner_outputs_and_inputs_are_the_rigid_tip_geometry():
    model = _model("xyz")
    lin = linearize(model, inputs=("tip_moment_x", "corner_force_z_left",
                                   "corner_force_z_right", "tip_force_z"),
                    outputs=("corner_z_left", "corner_z_right", "tip_twist", "tip_z"))
    nv = model.pin_model.nv
    Cq = lin.C[:, :nv]
    # at the straight pose: corner_z_left - corner_z_right = 2 w tip_twist, row for row (the
    # same Jacobian entries scaled: a rounding of w)
    np.testing.assert_allclose(Cq[0] - Cq[1], 2 * W * Cq[2], rtol=0.0,
                               atol=50 * EPS * np.abs(Cq).max())
    # and their mean is the tip centre's z (the corners' offsets cancel)
    np.testing.assert_allclose(0.5 * (Cq[0] + Cq[1]), Cq[3], rtol=0.0,
                               atol=50 * EPS * np.abs(Cq).max())
    # the corner input's generalised force is J_corner^T e_z, J_corner by central differences
    # of the rigid corner position p_tip + R (+-w e_y) at the straight pose
    def corner(q, side):
        p, R = model.tip_pose(q)
        return p[2] + side * W * R[2, 1]
    h = 1e-6  # truncation h^2, rounding EPS L / h
    for col, side in ((1, 1.0), (2, -1.0)):
        Jz = np.array([(corner(h * e, side) - corner(-h * e, side)) / (2 * h)
                       for e in np.eye(nv)])
        np.testing.assert_allclose(lin.input_map[:, col], Jz, rtol=1e-7,
                                   atol=1e-9 * BEAM.length_m)
    # at small amplitude: a static moment about x twists the tip; the corners move apart by
    # 2 w sin(phi) ~ 2 w phi (second order: phi^2 / 6 relative)
    m = 1e-3 * float(np.min(model.stiffness_Nm_per_rad[model.axis_index("x")]))
    q, _ = model.static_deflection(np.zeros(3), tip_moment_Nm=np.array([m, 0.0, 0.0]))
    phi = model.tip_twist(q)[0]
    zl = model.point_kinematics("tip_corner_left", q)[0][2]
    zr = model.point_kinematics("tip_corner_right", q)[0][2]
    assert phi > 1e-4
    assert abs((zl - zr) - 2 * W * phi) <= phi**2 * 2 * W
    # the linear model's static twist under that moment: the twist's compliance sum 1 / k_x
    dc = -lin.C[2] @ np.linalg.solve(lin.A, lin.B[:, 0])
    k_x = model.stiffness_Nm_per_rad[model.axis_index("x")]
    np.testing.assert_allclose(dc, np.sum(1.0 / k_x), rtol=1e-9)  # a solve of cond ~ k spread
    np.testing.assert_allclose(phi, m * dc, rtol=1e-3)  # nonlinearity ~ phi ~ 1e-3


def test_a_planar_chain_feels_the_bending_part_of_a_corner_force():
    planar = build_model(BEAM, LENGTHS, spatial_stiffness(BEAM, LENGTHS, "y"))
    lin = linearize(planar, inputs=("corner_force_z_left", "tip_force_z", "tip_force_y",
                                    "tip_moment_x"),
                    outputs=("corner_z_right", "tip_z", "tip_twist", "tip_y"))
    nv = planar.pin_model.nv
    # at the straight pose the corners' z Jacobian is the tip's (y joints do not roll the tip);
    # the lateral force, the moment about x and the twist and y outputs are structural zeros
    np.testing.assert_allclose(lin.input_map[:, 0], lin.input_map[:, 1], rtol=0.0,
                               atol=5 * EPS * np.abs(lin.input_map).max())
    np.testing.assert_allclose(lin.C[0], lin.C[1], rtol=0.0, atol=5 * EPS * np.abs(lin.C).max())
    assert not np.any(lin.input_map[:, 2:]) and not np.any(lin.C[2:, :nv])

