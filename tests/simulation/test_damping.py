"""Damping matrices: modal damping gives each mode its ratio; Eq. 5c is the paper's matrix root."""

import numpy as np
import pytest
import scipy.linalg as sla
from tolerances import EPS

from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.simulation.damping import (
    damping_matrix,
    eq5c_damping,
    modal_damping,
    modal_ratios,
    stiffness_damping,
)


@pytest.fixture(scope="module")
def model():
    beam = load_beam("examples/beams/reference-random.json")
    lengths = np.array([0.1, 0.2, 0.2, 0.2, 0.15, 0.15])
    return build_model(beam, lengths, finite_segment_stiffness(beam, lengths))


def _damped_ratios(M, K, C):
    """Damping ratios -Re(s)/|s| of the linear system M a + C v + K q = 0, from its state pencil."""
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -C]])
    B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), M]])
    s = sla.eigvals(A, B)
    s = s[s.imag > 0]
    s = s[np.argsort(np.abs(s))]
    return -s.real / np.abs(s), np.abs(s)


@pytest.mark.parametrize("pose", [0.0, 0.15])
def test_modal_damping_gives_each_mode_its_ratio(model, pose):
    q = np.full(model.n_joints, pose)
    M, K = model.mass_matrix(q), model.stiffness_matrix()
    xi = np.array([0.01, 0.02, 0.05, 0.1, 0.3])
    C = modal_damping(M, K, xi)
    ratios, wn = _damped_ratios(M, K, C)
    np.testing.assert_allclose(ratios, xi, rtol=1e-9)
    # undamped natural frequencies are |s| of the damped pair
    np.testing.assert_allclose(wn, model.natural_frequencies(q), rtol=1e-9)
    np.testing.assert_allclose(C, C.T, atol=0.0)


def test_scalar_modal_damping_is_caughey(model):
    """One ratio for all modes is Caughey's 2 xi M (M^-1 K)^(1/2)."""
    M, K = model.mass_matrix(), model.stiffness_matrix()
    root = np.real(sla.sqrtm(np.linalg.solve(M, K)))
    np.testing.assert_allclose(modal_damping(M, K, 0.03), 2 * 0.03 * M @ root,
                               rtol=1e-7, atol=1e-9 * np.abs(M @ root).max())


def test_eq5c_is_the_principal_root_and_not_symmetric(model):
    M, K = model.mass_matrix(np.full(5, 0.1)), model.stiffness_matrix()
    C = eq5c_damping(M, K, 0.5)  # 2 * 0.5 = 1: C is (M K)^(1/2) itself
    np.testing.assert_allclose(C, np.real(sla.sqrtm(M @ K)), rtol=1e-7,
                               atol=1e-9 * np.abs(C).max())
    assert np.abs(C - C.T).max() > 1e-3 * np.abs(C).max()
    # per-joint factors scale rows
    xi = np.array([0.01, 0.02, 0.03, 0.04, 0.05])
    # exact by construction: the form is 2 xi[:, None] times one root, and 2 * 0.5 = 1 gave C
    # that root itself; slack 5000 EPS (the test's 1e-12)
    np.testing.assert_allclose(eq5c_damping(M, K, xi), 2 * xi[:, None] * C, rtol=5000 * EPS)


def test_single_dof_forms_agree():
    m, k, xi = 2.0, 800.0, 0.05
    expected = 2 * xi * np.sqrt(m * k)
    # a handful of roundings each (1 EPS measured); kept: the test's 1e-14
    assert modal_damping([[m]], [[k]], xi)[0, 0] == pytest.approx(expected, rel=50 * EPS)
    assert eq5c_damping([[m]], [[k]], xi)[0, 0] == pytest.approx(expected, rel=50 * EPS)
    assert stiffness_damping([[m]], [[k]], xi)[0, 0] == pytest.approx(expected, rel=50 * EPS)


@pytest.mark.parametrize("pose", [0.0, 0.15])
def test_stiffness_damping_ratios_from_the_damped_eigenvalues(pose):
    """C = beta K: the damped pairs of M a + C v + K q = 0 have -Re(s)/|s| = xi_1 omega_k/omega_1
    (a 3R chain, every mode underdamped at xi_1 = 0.01)."""
    beam = load_beam("examples/beams/reference-random.json")
    lengths = np.array([0.15, 0.3, 0.3, 0.25])
    m3 = build_model(beam, lengths, finite_segment_stiffness(beam, lengths))
    q = np.full(3, pose)
    M, K = m3.mass_matrix(q), m3.stiffness_matrix()
    C = stiffness_damping(M, K, 0.01)
    np.testing.assert_array_equal(C, np.diag(np.diag(C)))
    ratios, wn = _damped_ratios(M, K, C)
    omega = m3.natural_frequencies(q)
    np.testing.assert_allclose(wn, omega, rtol=1e-9)
    np.testing.assert_allclose(ratios, 0.01 * omega / omega[0], rtol=1e-9)
    np.testing.assert_allclose(modal_ratios(M, K, C), 0.01 * omega / omega[0], rtol=1e-9)
    np.testing.assert_allclose(damping_matrix(M, K, 0.01, kind="stiffness"), C, rtol=0)


def test_stiffness_damping_takes_one_ratio(model):
    M, K = model.mass_matrix(), model.stiffness_matrix()
    with pytest.raises(BeamInputError, match="one ratio"):
        stiffness_damping(M, K, [0.01, 0.02, 0.02, 0.02, 0.02])
    # the same value for every mode is that one ratio
    np.testing.assert_allclose(stiffness_damping(M, K, np.full(5, 0.02)),
                               stiffness_damping(M, K, 0.02), rtol=0)


@pytest.mark.parametrize("bad", [-0.1, np.nan, [0.1, 0.2], "x"])
def test_bad_ratio_is_input_error(model, bad):
    M, K = model.mass_matrix(), model.stiffness_matrix()
    with pytest.raises(BeamInputError, match="damping_ratio"):
        modal_damping(M, K, bad)


def test_unknown_kind_is_input_error(model):
    with pytest.raises(BeamInputError, match="damping"):
        damping_matrix(model.mass_matrix(), model.stiffness_matrix(), 0.02, kind="rayleigh")
