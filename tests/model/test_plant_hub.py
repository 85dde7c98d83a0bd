"""The hub model: a hand-derived 1R hub-beam, the clamped limit, the rigid mode, and what the
PrbdmModel methods do with a hub."""


import numpy as np
import pytest
from paths import ROOT
from tolerances import EPS

from prbdm_pin import BeamInputError, Hub, build_model, linearize
from prbdm_pin.files.beam_file import load_beam

BEAM = load_beam(ROOT / "examples/beams/reference-random.json")
L = BEAM.length_m
LENGTHS = np.array([0.15, 0.3, 0.2, 0.35]) * L
SPRINGS = np.array([400.0, 150.0, 60.0])


@pytest.mark.parametrize("J,r", [(0.05, 0.0), (0.3, 0.12), (5.0, 0.5)])
def test_one_joint_hub_beam_equals_its_lagrangian(J, r):
    lengths = np.array([0.4, 0.6]) * L
    k = 90.0
    model = build_model(BEAM, lengths, [k], hub=Hub(J, r))
    s = model.sections
    # centres of mass in the xz-plane measured from the hub axis; joint 1 at r + L_0
    c = np.column_stack([r + s.com_m[:, 0], s.com_m[:, 2]])
    p1 = np.array([r + lengths[0], 0.0])
    Iy = s.inertia_com_kg_m2[:, 1, 1]
    m = s.mass_kg
    # T = 1/2 [th, q] M [th, q]^T: the hub turns both links, the joint link 1 only
    Mhh = J + sum(Iy[i] + m[i] * c[i] @ c[i] for i in range(2))
    Mhq = Iy[1] + m[1] * c[1] @ (c[1] - p1)
    Mqq = Iy[1] + m[1] * (c[1] - p1) @ (c[1] - p1)
    Mref = np.array([[Mhh, Mhq], [Mhq, Mqq]])
    # CRBA against the Lagrangian by hand: a few roundings (7 EPS measured); kept: the test's
    # 1e-13
    np.testing.assert_allclose(model.mass_matrix(), Mref, rtol=500 * EPS)
    w2 = k * Mhh / (Mhh * Mqq - Mhq**2)  # det(K - w^2 M) = 0 with K = diag(0, k)
    w = model.natural_frequencies()
    assert w[0] == 0.0
    # the determinant cancels to 1/9 of Mhh Mqq at most here: ~9 EPS (4 EPS measured); kept:
    # the tests' 1e-12
    assert w[1] == pytest.approx(np.sqrt(w2), rel=5000 * EPS)
    lin = linearize(model, inputs=("hub_torque",), outputs=("hub_angle",))
    md = lin.modal()
    assert md.omega_rad_s[0] == 0.0 and md.damping_ratio[0] == 0.0
    assert md.omega_rad_s[1] == pytest.approx(np.sqrt(w2), rel=5000 * EPS)
    # undamped rigid mode: A has a double eigenvalue 0, the flexible pair has ratio 0.02
    ev = np.linalg.eigvals(lin.A)
    assert np.sum(np.abs(ev) < 1e-9 * np.max(np.abs(ev))) == 2
    flex = ev[np.abs(ev) > 1e-9 * np.max(np.abs(ev))]
    np.testing.assert_allclose(-flex.real / np.abs(flex), 0.02, rtol=1e-9)


def test_infinite_hub_inertia_tends_to_the_clamped_model():
    clamped = build_model(BEAM, LENGTHS, SPRINGS).natural_frequencies()
    errs = []
    for J in (1e4, 1e6, 1e8):
        w = build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(J, 0.2)).natural_frequencies()
        assert w[0] == 0.0
        errs.append(np.max(np.abs(w[1:] / clamped - 1.0)))
    assert errs[0] > errs[1] > errs[2]
    assert errs[2] < 1e-6
    assert errs[1] / errs[2] == pytest.approx(100.0, rel=1e-2)  # the error goes as 1/J


@pytest.mark.parametrize("kind", ["modal", "stiffness"])
def test_damping_leaves_the_rigid_mode_undamped(kind):
    model = build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(0.2, 0.05))
    lin = linearize(model, inputs=("hub_torque",), outputs=("hub_rate",), damping=kind,
                    damping_ratio=0.04)
    md = lin.modal()
    rigid = md.shapes[:, 0]
    assert abs(rigid @ lin.damping_Nms_per_rad @ rigid) < 1e-12 * np.max(
        np.abs(lin.damping_Nms_per_rad))
    assert md.damping_ratio[1] == pytest.approx(0.04, rel=1e-9)
    if kind == "modal":
        np.testing.assert_allclose(md.damping_ratio[1:], 0.04, rtol=1e-9)
    with pytest.raises(BeamInputError, match="eq5c"):
        linearize(model, damping="eq5c")


def test_hub_model_methods():
    hub = Hub(0.2, 0.05)
    model = build_model(BEAM, LENGTHS, SPRINGS, hub=hub)
    assert model.hub == hub and model.n_joints == 3 and model.pin_model.nv == 4
    K = model.stiffness_matrix()
    assert K.shape == (4, 4) and not np.any(K[0]) and not np.any(K[:, 0])
    w, Phi = model.modes()
    M = model.mass_matrix()
    # M-orthonormal to about n EPS (w_max / w_min)^2 = 160 EPS (64 measured); the solves of
    # the modes, of one pose and of a stack agree to eig_rtol(w) = 1.8e-14 (<= 8 EPS
    # measured); kept: the tests' 1e-12, 1e-13, 1e-12, 1e-12
    np.testing.assert_allclose(Phi.T @ M @ Phi, np.eye(4), atol=5000 * EPS)
    np.testing.assert_allclose(Phi.T @ K @ Phi, np.diag(w**2), atol=1e-9 * w[-1] ** 2)
    np.testing.assert_allclose(w, model.natural_frequencies(), rtol=500 * EPS)
    Q = np.array([[0.3, 0.1, -0.2, 0.05], [0.0, 0.0, 0.0, 0.0]])
    np.testing.assert_allclose(model.natural_frequencies_batch(Q)[1], w, rtol=5000 * EPS)
    np.testing.assert_allclose(model.natural_frequencies_batch(Q)[0],
                               model.natural_frequencies(Q[0]), rtol=5000 * EPS)
    # the hub angle turns the whole beam about the hub axis
    p = model.tip_position(np.array([0.4, 0.0, 0.0, 0.0]))
    R = 0.05 + L
    # a few roundings of R ~ 1 m (0.5 EPS measured); kept: the test's 1e-14 m
    np.testing.assert_allclose(p, [R * np.cos(0.4), 0.0, -R * np.sin(0.4)], atol=50 * EPS * R)
    assert model.tip_jacobian().shape == (3, 4)
    stiffer = model.with_stiffness(2 * SPRINGS)
    assert stiffer.hub == hub
    # one solve against another of the doubled springs, and sqrt(2) rounded: eig_rtol(w) =
    # 1.8e-14 (10 EPS measured); kept: the test's 1e-12
    np.testing.assert_allclose(stiffer.natural_frequencies()[1:],
                               np.sqrt(2) * w[1:], rtol=5000 * EPS)
    with pytest.raises(BeamInputError, match="hub"):
        model.static_deflection(np.array([0.0, 0.0, -1.0]))
    # the URDF carries the hub: Pinocchio's parser of it gives the hand-built chain's M(q)
    import pinocchio as pin

    parsed = pin.buildModelFromXML(model.urdf)
    assert parsed.names[1] == "hub" and parsed.nv == 4
    M_urdf = pin.crba(parsed, parsed.createData(), Q[0])
    # the URDF writes every number in full: the same chain, the same CRBA (exact here); kept:
    # the test's 1e-13 and 1e-15 kg m^2
    np.testing.assert_allclose(np.triu(M_urdf) + np.triu(M_urdf, 1).T, model.mass_matrix(Q[0]),
                               rtol=500 * EPS, atol=5 * EPS)
    # without a hub nothing changed: n joints, the clamped chain
    plain = build_model(BEAM, LENGTHS, SPRINGS)
    assert plain.hub is None and plain.pin_model.nv == 3


def test_loaded_hub_is_held_by_a_trim_torque():
    model = build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(0.2, 0.05))
    F = np.array([0.0, 0.0, -20.0])
    lin = linearize(model, inputs=("hub_torque", "tip_force_z"), outputs=("q[0]",), load_N=F)
    assert lin.q_eq[0] == 0.0
    clamped = build_model(BEAM, LENGTHS, SPRINGS).static_deflection(F)[0]
    np.testing.assert_allclose(lin.q_eq[1:], clamped, rtol=1e-9)
    # the motor balances the moment of the load about the hub axis
    tip = model.tip_position(lin.q_eq)
    # the same moment of the same tip (exact here); kept: the test's 1e-12
    assert lin.u_eq[0] == pytest.approx(-(tip[2] * F[0] - tip[0] * F[2]), rel=5000 * EPS)
