"""A beam on a free-floating bus: its frequencies against the clamped and the free-free chain,
its linearisation against central differences of the nonlinear dynamics, and bad input.

References: the clamped chain (a bus of huge mass, the error falling as 1 / mass); the planar
free-free chain's mass matrix written by hand from the links' masses, centres of mass and
inertias (a massless bus: the member alone floats); central differences of Pinocchio's ABA (the
nonlinear equations of motion) and of its frame kinematics (the outputs).
"""

import numpy as np
import pinocchio as pin
import pytest
from central_differences import central_difference
from paths import ROOT
from tolerances import EPS, eig_rtol

from prbdm_pin import (
    BeamInputError,
    Hub,
    InputTypeError,
    build_model,
    export_model,
    linearize,
    statics,
)
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.model.supports import FreeBus

BEAM = load_beam(ROOT / "examples/beams/reference-random.json")
L = BEAM.length_m
LENGTHS = np.array([0.15, 0.3, 0.2, 0.35]) * L
SPRINGS = np.array([400.0, 150.0, 60.0])


def _bus(mass, **kw):
    # a bus of uniform density: inertia ~ mass (kg m^2 per kg of a ~0.5 m box)
    return FreeBus(mass, np.array([0.05, 0.06, 0.07]) * mass, **kw)


def _free_free_omega(model):
    """Flexible frequencies of the planar chain floating freely in the x-z plane, rad/s.

    Coordinates (X, Z, phi_0, q_1..q_n) at the straight pose: body i's COM at x_i moves by
    dZ = -x_i dphi_0 - sum_{j<=i} (x_i - p_j) dq_j (rotation about +y lowers +x), X moves
    all bodies alike; body i turns by phi_0 + q_1 + ... + q_i.
    """
    s = model.sections
    m, x, Iy = s.mass_kg, s.com_m[:, 0], s.inertia_com_kg_m2[:, 1, 1]
    joints = np.cumsum(LENGTHS)[:-1]  # joint j at the end of link j - 1
    n = joints.size
    M = np.zeros((n + 3, n + 3))
    for i in range(n + 1):
        jz = np.zeros(n + 3)  # dZ_i / d coordinates
        jz[1] = 1.0
        jz[2] = -x[i]
        jz[3:3 + i] = -(x[i] - joints[:i])
        jx = np.zeros(n + 3)
        jx[0] = 1.0
        rot = np.zeros(n + 3)
        rot[2] = 1.0
        rot[3:3 + i] = 1.0
        M += m[i] * (np.outer(jx, jx) + np.outer(jz, jz)) + Iy[i] * np.outer(rot, rot)
    S = M[3:, 3:] - M[3:, :3] @ np.linalg.solve(M[:3, :3], M[:3, 3:])
    w2 = np.linalg.eigvals(np.linalg.solve(S, np.diag(SPRINGS))).real
    return np.sqrt(np.sort(w2))


def test_a_heavy_bus_tends_to_the_clamped_chain():
    clamped = build_model(BEAM, LENGTHS, SPRINGS).natural_frequencies()
    errs = []
    for mass in (1e5, 1e7, 1e9):
        model = build_model(BEAM, LENGTHS, SPRINGS, support=_bus(mass, root_m=[0.2, 0.0, 0.05]))
        w = linearize(model, damping_ratio=0.0).modal().omega_rad_s  # the plant's modes
        assert np.all(w[:6] == 0.0)  # the rigid modes taken out exactly
        # the plant's modes are the model's: two solves of one pencil, one unscaled (1.2e-14
        # measured against eig_rtol's 1.8e-13)
        np.testing.assert_allclose(w, model.natural_frequencies(), rtol=eig_rtol(w))
        errs.append(np.max(np.abs(w[6:] / clamped - 1.0)))
    assert errs[0] > errs[1] > errs[2]
    # the member's 37 kg and ~5 kg m^2 against 1e9 kg and 5e7 kg m^2: 2e-7 measured
    assert errs[2] < 1e-6
    # the error goes as 1 / mass (a first-order perturbation of the constraint)
    assert errs[0] / errs[1] == pytest.approx(100.0, rel=1e-2)
    assert errs[1] / errs[2] == pytest.approx(100.0, rel=1e-2)


def test_a_light_bus_tends_to_the_free_free_chain():
    ref = _free_free_omega(build_model(BEAM, LENGTHS, SPRINGS))
    errs = []
    for mass in (1e-5, 1e-7):
        model = build_model(BEAM, LENGTHS, SPRINGS, support=_bus(mass))
        w = linearize(model, damping_ratio=0.0).modal().omega_rad_s[6:]
        errs.append(np.max(np.abs(w / ref - 1.0)))
    # a bus of 1e-7 kg (5e-9 kg m^2) at the root of a 37 kg member: 2.4e-7 measured (mode 3,
    # whose node is nearest the root, feels the bus most); the error falls as the bus's mass
    assert errs[1] < 1e-6
    assert errs[0] / errs[1] == pytest.approx(100.0, rel=0.05)
    # and the free-free chain is not the clamped one (the check discriminates)
    clamped = build_model(BEAM, LENGTHS, SPRINGS).natural_frequencies()
    assert np.min(np.abs(ref / clamped - 1.0)) > 0.1


def test_modes_are_mass_orthonormal_with_six_rigid_ones():
    model = build_model(BEAM, LENGTHS, SPRINGS, support=_bus(20.0, com_m=[-0.1, 0.02, 0.03],
                                                             root_m=[0.3, 0.0, 0.1]))
    q = np.r_[0.1, -0.2, 0.3, 0.4, -0.3, 0.2, 0.0, 0.0, 0.0]
    w, Phi = model.modes(q)
    M = model.mass_matrix(q)
    K = model.stiffness_matrix()
    # orthonormality: a few solves with M_rr and S (cond ~1e3 here): 1e-12 of unity
    np.testing.assert_allclose(Phi.T @ M @ Phi, np.eye(9), atol=5000 * EPS)
    np.testing.assert_allclose(Phi.T @ K @ Phi, np.diag(w**2), atol=1e-9 * w[-1] ** 2)
    assert np.all(w[:6] == 0.0) and np.all(w[6:] > 0.0)


def _rhs(model, q, v, tau):
    return pin.aba(model.pin_model, model.pin_model.createData(), q, v, tau)


def test_linearize_matches_central_differences_of_the_nonlinear_dynamics():
    bus = FreeBus(12.0, [[0.4, 0.02, 0.0], [0.02, 0.5, 0.01], [0.0, 0.01, 0.6]],
                  com_m=[-0.1, 0.05, 0.0], root_m=[0.25, 0.0, -0.05])
    model = build_model(BEAM, LENGTHS, SPRINGS, support=bus)
    q0 = np.r_[0.3, -0.1, 0.2, 0.5, -0.4, 0.3, 0.0, 0.0, 0.0]  # a rotated, displaced bus
    lin = linearize(model, inputs=("tip_force_z", "joint_torque[1]"),
                    outputs=("tip_z", "bus_rate_y", "bus_attitude_x", "bus_position_z"),
                    q_eq=q0, damping_ratio=0.0)
    K = model.stiffness_matrix()
    nv = 9

    def f(x):  # x = [q, v, u]: the nonlinear state rate
        q, v, u = x[:nv], x[nv:2 * nv], x[2 * nv:]
        J = model.tip_jacobian(q)
        tau = -K @ q + J[2] * u[0]
        tau[7] += u[1]
        return np.concatenate([v, _rhs(model, q, v, tau)])

    x0 = np.zeros(2 * nv + 2)
    x0[:nv] = q0
    # each value of f: ABA through M (entries up to ~40 kg m^2) and the springs: a few hundred
    # roundings of its ~1e-2 size at most
    Jfd, err = central_difference(f, x0, np.full(x0.size, 1e-5), 500 * EPS)
    AB = np.hstack([lin.A, lin.B])
    # the differences' truncation and rounding bound (err), at least 1e-9 of the largest entry
    tol = np.maximum(err, 1e-9 * np.abs(AB).max())
    assert np.all(np.abs(AB - Jfd) <= 10 * tol)
    assert np.abs(lin.A[nv:, :nv]).max() > 1.0  # the springs show through the bus's mass


def test_bus_outputs_match_the_clamp_frame_and_differences():
    bus = FreeBus(8.0, [0.3, 0.4, 0.5], com_m=[0.0, 0.1, 0.0], root_m=[0.2, 0.0, 0.0])
    model = build_model(BEAM, LENGTHS, SPRINGS, support=bus)
    q0 = np.r_[0.1, 0.2, -0.3, 0.4, 0.3, -0.2, 0.0, 0.0, 0.0]
    names = ("bus_rate_x", "bus_rate_y", "bus_rate_z", "tip_z", "q[2]")
    lin = linearize(model, inputs=("tip_force_z",), outputs=names, q_eq=q0)
    pm = model.pin_model
    data = pm.createData()
    fid = pm.getFrameId("bus")
    # the bus rate row against Pinocchio's body angular velocity of the bus frame
    v = np.r_[0.3, -0.2, 0.1, 0.7, -0.5, 0.4, 1.0, -2.0, 0.5]
    pin.forwardKinematics(pm, data, q0, v)
    omega = pin.getFrameVelocity(pm, data, fid, pin.LOCAL).angular
    Cv = lin.C[:, 9:]
    # the Euler-rate matrix against Pinocchio's composition of the three rotations: roundings
    np.testing.assert_allclose(Cv[:3] @ v, omega, rtol=0, atol=50 * EPS * np.abs(v).max())

    clamp = pin.SE3(np.eye(3), np.array(bus.root_m))

    def tip_in_bus(q):  # the tip in the clamp frame, from the whole system's kinematics
        pin.framesForwardKinematics(pm, data, q)
        return ((data.oMf[fid] * clamp).inverse() * data.oMf[model.tip_frame_id]).translation

    Jfd, err = central_difference(tip_in_bus, q0, np.full(9, 1e-6), 5 * EPS)  # ~1 m, products
    assert np.all(np.abs(lin.C[3, :9] - Jfd[2]) <= 10 * np.maximum(err[2], 1e-10))
    assert np.abs(Jfd[2, :6]).max() < 1e-8  # the bus's motion does not move the tip in its frame
    # the closed-form tip of the member against Pinocchio's placements: roundings of ~1 m
    assert lin.C[4, 8] == 1.0 and lin.y_eq[3] == pytest.approx(tip_in_bus(q0)[2], abs=50 * EPS)


@pytest.mark.parametrize("kwargs,match", [
    (dict(mass_kg=0.0, inertia_kg_m2=[1, 1, 1]), "mass_kg"),
    (dict(mass_kg=-2.0, inertia_kg_m2=[1, 1, 1]), "mass_kg"),
    (dict(mass_kg=1.0, inertia_kg_m2=[1, -1, 1]), "positive definite"),
    (dict(mass_kg=1.0, inertia_kg_m2=[[1, 0, 0], [0, 1, 2], [0, 2, 1]]), "positive definite"),
    (dict(mass_kg=1.0, inertia_kg_m2=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), "symmetric"),
    (dict(mass_kg=1.0, inertia_kg_m2=[1, 1]), "inertia_kg_m2"),
    (dict(mass_kg=1.0, inertia_kg_m2=[1, np.nan, 1]), "inertia_kg_m2"),
    (dict(mass_kg=1.0, inertia_kg_m2=[1, 1, 1], com_m=[0, 0]), "com_m"),
    (dict(mass_kg=1.0, inertia_kg_m2=[1, 1, 1], root_m=[0, np.inf, 0]), "root_m"),
])
def test_bad_bus_is_refused_naming_the_field(kwargs, match):
    with pytest.raises(BeamInputError, match=match):
        FreeBus(**kwargs)


def test_bad_use_of_a_bus_is_refused(tmp_path):
    with pytest.raises(InputTypeError, match="mass_kg"):
        FreeBus("heavy", [1, 1, 1])
    with pytest.raises(InputTypeError, match="support"):
        build_model(BEAM, LENGTHS, SPRINGS, support="bus")
    with pytest.raises(BeamInputError, match="support"):
        build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(1.0), support=_bus(1.0))
    model = build_model(BEAM, LENGTHS, SPRINGS, support=_bus(5.0))
    for kw, match in ((dict(load_N=[0, 0, 1.0]), "load_N"),
                      (dict(gravity_m_s2=[0, 0, -9.81]), "gravity_m_s2"),
                      (dict(q_eq=np.r_[np.zeros(6), 0.1, 0, 0]), "unbent"),
                      (dict(outputs=("hub_angle",)), "outputs"),
                      (dict(inputs=("hub_torque",)), "inputs")):
        with pytest.raises(BeamInputError, match=match):
            linearize(model, **kw)
    with pytest.raises(BeamInputError, match="free bus"):
        model.static_deflection(np.array([0.0, 0.0, -1.0]))
    with pytest.raises(BeamInputError, match="free bus"):
        statics(model)
    for fmt in ("json", "urdf", "mjcf"):  # no format carries the bus: refused, nothing written
        with pytest.raises(BeamInputError, match="free bus"):
            export_model(model, tmp_path / f"bus.{fmt}", fmt)
    assert list(tmp_path.iterdir()) == []
    # buses compare by value (their tensors are kept as tuples)
    assert FreeBus(1.0, [1, 2, 3]) == FreeBus(1, np.diag([1.0, 2.0, 3.0]))
    assert FreeBus(1.0, [1, 2, 3]) != FreeBus(1.0, [1, 2, 3], root_m=[0.1, 0, 0])
    # a Hub passed as the support is the hub model of hub=
    a = build_model(BEAM, LENGTHS, SPRINGS, support=Hub(200.0, 0.1)).natural_frequencies()
    b = build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(200.0, 0.1)).natural_frequencies()
    np.testing.assert_array_equal(a, b)  # the same model, the same arithmetic
