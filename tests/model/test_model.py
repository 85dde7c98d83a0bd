"""Mass matrix, kinematics and frequencies of the hand-built Pinocchio chain."""


import numpy as np
import pinocchio as pin
import pytest
import scipy.linalg
from paths import BEAMS
from tolerances import EPS, eig_rtol

from prbdm_pin.chain.stiffness import pose_sweep
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.model.prbdm_model import build_model

RANDOM = load_beam(BEAMS / "reference-random.json")
LENGTHS6 = np.array([0.08, 0.22, 0.17, 0.2, 0.13, 0.12, 0.08])


@pytest.fixture(scope="module")
def model6():
    return build_model(RANDOM, LENGTHS6, np.linspace(300.0, 50.0, 6))


def _lagrangian_mass_matrix_2link(sec, lengths, q2):
    """M of a planar two-link arm about y from its Lagrangian (links 1 and 2 move)."""
    m1, m2 = sec.mass_kg[1], sec.mass_kg[2]
    I1, I2 = sec.inertia_com_kg_m2[1, 1, 1], sec.inertia_com_kg_m2[2, 1, 1]  # about y
    d1 = sec.com_m[1, 0] - sec.start_m[1]
    d2 = sec.com_m[2, 0] - sec.start_m[2]
    l1 = lengths[1]
    c = np.cos(q2)
    M11 = I1 + m1 * d1**2 + I2 + m2 * (l1**2 + d2**2 + 2 * l1 * d2 * c)
    M12 = I2 + m2 * (d2**2 + l1 * d2 * c)
    M22 = I2 + m2 * d2**2
    return np.array([[M11, M12], [M12, M22]])


@pytest.mark.parametrize("q", [[0.0, 0.0], [0.3, -0.7], [1.2, 2.5], [-2.0, 3.0]])
def test_mass_matrix_equals_two_link_lagrangian(q):
    lengths = np.array([0.3, 0.45, 0.25])
    m = build_model(RANDOM, lengths, [100.0, 50.0])
    expected = _lagrangian_mass_matrix_2link(m.sections, lengths, q[1])
    # CRBA against the hand Lagrangian: a few dozen roundings of terms of M's size (1.6 EPS
    # measured); kept: the test's 1e-13
    np.testing.assert_allclose(m.mass_matrix(np.array(q)), expected, rtol=500 * EPS, atol=0)


def test_one_joint_mass_is_the_parallel_axis_inertia():
    m = build_model(RANDOM, [0.4, 0.6], [80.0])
    s = m.sections
    d = s.com_m[1, 0] - 0.4
    J = s.inertia_com_kg_m2[1, 1, 1] + s.mass_kg[1] * d**2
    # Pinocchio's inertia algebra against the parallel axes by hand: a few roundings (6 EPS
    # measured); kept: the tests' 1e-14
    assert m.mass_matrix()[0, 0] == pytest.approx(J, rel=50 * EPS)
    # one degree of freedom: omega^2 = K / J
    assert m.natural_frequencies()[0] == pytest.approx(np.sqrt(80.0 / J), rel=50 * EPS)


def test_mass_matrix_spd_straight_and_over_the_sweep(model6):
    rng = np.random.default_rng(0)
    poses = np.vstack([np.zeros(6), pose_sweep(6, eps=0.01), rng.uniform(0, np.pi / 2, (20, 6))])
    for q in poses:
        M = model6.mass_matrix(q)
        np.testing.assert_array_equal(M, M.T)
        assert np.linalg.eigvalsh(M).min() > 0
        np.linalg.cholesky(M)


def test_crba_columns_equal_rnea_differences(model6):
    pm, data = model6.pin_model, model6.new_data()
    rng = np.random.default_rng(1)
    for _ in range(5):
        q = rng.uniform(-1.5, 1.5, 6)
        M = pin.crba(pm, data, q).copy()
        v0 = np.zeros(6)
        base = pin.rnea(pm, data, q, v0, v0).copy()
        for j in range(6):
            e = np.zeros(6)
            e[j] = 1.0
            col = pin.rnea(pm, data, q, v0, e) - base
            # two recursions over six bodies: a few roundings (2 EPS measured); kept: the
            # test's 1e-12 and 1e-15 kg m^2
            np.testing.assert_allclose(M[:, j], col, rtol=5000 * EPS, atol=5 * EPS)


def test_python_crba_returns_a_symmetric_matrix(model6):
    # Pinocchio's C++ CRBA fills the upper triangle only; the Python binding symmetrises. The
    # frequency code relies on it: if a release changes it, this test says so.
    M = pin.crba(model6.pin_model, model6.new_data(), np.array([0.3, -0.2, 0.9, 0.1, 1.1, -0.4]))
    assert np.abs(np.tril(M, -1)).max() > 0
    np.testing.assert_array_equal(M, M.T)


def test_hand_built_model_equals_urdf_built_model(model6):
    parsed = pin.buildModelFromXML(model6.urdf)
    parsed.gravity = pin.Motion.Zero()
    assert parsed == model6.pin_model
    assert model6.pin_model.frames[model6.tip_frame_id].name == "tip"


def test_tip_kinematics_closed_form_and_finite_differences(model6):
    rng = np.random.default_rng(2)
    lengths = LENGTHS6
    for _ in range(4):
        q = rng.uniform(-2, 2, 6)
        phi = np.cumsum(q)
        p = np.array([lengths[0] + lengths[1:] @ np.cos(phi), 0.0, -(lengths[1:] @ np.sin(phi))])
        # six placements either side: a few roundings of the 1 m chain (0.3 EPS measured);
        # kept: the test's 1e-15 m
        np.testing.assert_allclose(model6.tip_position(q), p, atol=5 * EPS)
        J = model6.tip_jacobian(q)
        h = 1e-6
        Jfd = np.column_stack([
            (model6.tip_position(q + h * e) - model6.tip_position(q - h * e)) / (2 * h)
            for e in np.eye(6)
        ])
        np.testing.assert_allclose(J, Jfd, atol=1e-9)
    # straight: a positive angle sends the tip to -z
    assert model6.tip_jacobian(np.zeros(6))[2, 0] == pytest.approx(-(1 - lengths[0]))


def test_frequencies_match_scipy_generalised_eigh(model6):
    K = model6.stiffness_matrix()
    rng = np.random.default_rng(4)
    Q = rng.uniform(0, np.pi / 2 / 6, (25, 6))
    batch = model6.natural_frequencies_batch(Q)
    for q, w in zip(Q, batch, strict=True):
        ref = np.sqrt(scipy.linalg.eigh(K, model6.mass_matrix(q), eigvals_only=True))
        np.testing.assert_allclose(w, ref, rtol=1e-11)
        # different LAPACK drivers: the top mode carries eps * (w_max / w_min)^2 ~ 1e-12
        np.testing.assert_allclose(model6.natural_frequencies(q), w, rtol=1e-11)
    np.testing.assert_allclose(
        model6.natural_frequencies(Q[0], squared=True), batch[0] ** 2, rtol=1e-11
    )
    # per-pose stiffness: scaling row i by c_i scales its frequencies by sqrt(c_i)
    c = np.linspace(0.5, 3.0, 25)
    scaled = model6.natural_frequencies_batch(Q, stiffness=c[:, None] * model6.stiffness_Nm_per_rad)
    # per-pose springs take another solver than the scaled one: eig_rtol, 2.6e-12 (9e-14
    # measured)
    np.testing.assert_allclose(scaled, batch * np.sqrt(c)[:, None],
                               rtol=max(eig_rtol(w) for w in batch))


def test_modes_are_mass_normalised(model6):
    q = np.full(6, 0.2)
    w, Phi = model6.modes(q)
    M, K = model6.mass_matrix(q), model6.stiffness_matrix()
    np.testing.assert_allclose(Phi.T @ M @ Phi, np.eye(6), atol=1e-11)
    np.testing.assert_allclose(Phi.T @ K @ Phi, np.diag(w**2), rtol=1e-10, atol=1e-8 * w[-1] ** 2)
    # the modes' solve against the frequencies' scaled one: eig_rtol, 2.5e-12 (7e-14 measured)
    np.testing.assert_allclose(w, model6.natural_frequencies(q), rtol=eig_rtol(w))


def test_with_stiffness_shares_the_chain(model6):
    other = model6.with_stiffness(4.0 * model6.stiffness_Nm_per_rad)
    assert other.pin_model is model6.pin_model
    # exact by construction: K^(-1/2) of 4 K is half K's, a power of two, so the scaled solve
    # is the same and w doubles exactly; slack 500 EPS (the test's 1e-13)
    np.testing.assert_allclose(other.natural_frequencies(), 2.0 * model6.natural_frequencies(),
                               rtol=500 * EPS)
    assert "springStiffness>1200.0<" in other.urdf


def test_modal_damping_gives_each_mode_its_ratio(model6):
    from prbdm_pin.chain.pin_dynamics import modal_damping

    q = np.full(6, 0.1)
    w, Phi = model6.modes(q)
    M = model6.mass_matrix(q)
    xi = np.linspace(0.01, 0.06, 6)
    C = modal_damping(M, Phi, w, xi)
    # M Phi diag Phi^T M in one order and its transpose: sums of six products of C's size
    # (0.5 EPS measured); kept: the test's 1e-14 of max |C|
    np.testing.assert_allclose(C, C.T, rtol=0, atol=50 * EPS * np.abs(C).max())
    # Phi^T C Phi = diag(2 xi omega): each mode decouples with damping ratio xi
    np.testing.assert_allclose(Phi.T @ C @ Phi, np.diag(2 * xi * w), atol=1e-9 * (2 * xi * w).max())


def _arrays(result):
    return result if isinstance(result, tuple) else (result,)


def test_a_given_workspace_gives_the_same_numbers_and_leaves_the_built_in_one_alone():
    model = build_model(RANDOM, LENGTHS6, np.linspace(300.0, 50.0, 6))
    q0, q1 = np.zeros(6), np.linspace(-0.4, 0.5, 6)
    Q = np.stack([q0, q1])
    calls = [
        lambda d: model.mass_matrix(q1, data=d),
        lambda d: model.natural_frequencies(q1, data=d),
        lambda d: model.natural_frequencies(q1, squared=True, data=d),
        lambda d: model.natural_frequencies_batch(Q, data=d),
        lambda d: model.natural_frequencies_batch(Q, 2.0 * model.stiffness_Nm_per_rad, data=d),
        lambda d: model.modes(q1, data=d),
        lambda d: model.tip_position(q1, data=d),
        lambda d: model.tip_jacobian(q1, data=d),
        lambda d: model.tip_kinematics(q1, data=d),
        lambda d: model.static_deflection(np.array([0.0, 0.0, -0.5]), data=d),
    ]
    refs = [_arrays(call(None)) for call in calls]  # through the built-in workspace
    # leave the built-in workspace at the straight pose and remember what it holds
    built_in = model.default_data
    model.mass_matrix(q0)
    model.tip_kinematics(q0)
    M0 = built_in.M.copy()
    tip0 = built_in.oMf[model.tip_frame_id].translation.copy()
    a, b = model.new_data(), model.new_data()
    assert a is not b and built_in not in (a, b)
    for call, ref in zip(calls, refs, strict=True):
        for data in (a, b):
            for got, want in zip(_arrays(call(data)), ref, strict=True):
                assert np.array_equal(got, want)
            assert np.array_equal(built_in.M, M0)
            assert np.array_equal(built_in.oMf[model.tip_frame_id].translation, tip0)
    assert model.default_data is built_in
