"""Large-deflection statics against the linear solution, the elastica table and the equilibrium."""


import numpy as np
import pinocchio as pin
import pytest
from paths import BEAMS
from reference import ELASTICA
from scipy.optimize import brentq
from scipy.special import ellipk
from tolerances import EPS

from prbdm_pin.chain import statics
from prbdm_pin.errors import SolveError
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.model.prbdm_model import build_model

BEAM = load_beam(BEAMS / "uniform-narrow.json")
EI = BEAM.root_EI_Nm2
L = BEAM.length_m

# Inextensible elastica, dead vertical tip load, rows alpha2 = P L^2/(E I) of
# shared/reference/elastica_vertical_tip_load.csv (Mattiasson 1981, Table 1):
# alpha2: (retreat (L - x_tip)/L, deflection y_tip/L)


def chain(n, beam=BEAM):
    h = L / n
    lengths = np.concatenate([[h / 2], np.full(n - 1, h), [h / 2]])
    return build_model(beam, lengths, np.full(n, EI / h), min_fraction=0.0)


@pytest.fixture(scope="module")
def chain32():
    return chain(32)


def relative_residual(model, q, F):
    """||K q - J(q)^T F|| / ||J^T F|| with Pinocchio's frame Jacobian (not the solver's)."""
    JtF = model.tip_jacobian(q).T @ F
    return np.linalg.norm(model.stiffness_Nm_per_rad * q - JtF) / np.linalg.norm(JtF)


def test_small_load_equals_linear_solution():
    m = build_model(load_beam(BEAMS / "reference-random.json"), [0.1, 0.25, 0.2, 0.3, 0.15],
                    [900.0, 700.0, 400.0, 150.0])
    F = np.array([0.0, 0.0, -1e-5])
    q, p = m.static_deflection(F)
    q_lin = np.linalg.solve(m.stiffness_matrix(), m.tip_jacobian(np.zeros(4)).T @ F)
    np.testing.assert_allclose(q, q_lin, rtol=1e-6)
    np.testing.assert_allclose(p, m.tip_position(q), atol=0)


@pytest.mark.parametrize("alpha", [1.0, 2.0, 10.0])
def test_elastica_table(chain32, alpha):
    F = np.array([0.0, 0.0, -alpha * EI / L**2])
    q, p = chain32.static_deflection(F)
    retreat, deflection = ELASTICA[alpha]
    assert abs((L - p[0]) / L - retreat) < 1e-3
    assert abs(-p[2] / L - deflection) < 1e-3
    assert relative_residual(chain32, q, F) <= 1e-9
    # a minimum, not just a stationary point
    h = 1e-6
    g = lambda x: chain32.stiffness_Nm_per_rad * x - chain32.tip_jacobian(x).T @ F  # noqa: E731
    H = np.column_stack([(g(q + h * e) - g(q - h * e)) / (2 * h) for e in np.eye(32)])
    assert np.linalg.eigvalsh(0.5 * (H + H.T)).min() > 0


def test_residual_on_a_tapered_beam():
    beam = load_beam(BEAMS / "reference-random.json")
    lengths = [0.1, 0.25, 0.2, 0.3, 0.15]
    from prbdm_pin.chain.stiffness import finite_segment_stiffness

    m = build_model(beam, lengths, finite_segment_stiffness(beam, lengths))
    for F in ([0.0, 0.0, -2500.0], [300.0, 0.0, -8000.0], [-2000.0, 50.0, -20000.0]):
        q, _ = m.static_deflection(np.array(F))
        assert relative_residual(m, q, np.array(F)) <= 1e-9


def test_tip_rotates_past_90_degrees(chain32):
    # a load pointing back and down at 135 degrees: the tip turns towards it, past 90 degrees
    P = 20.0 * EI / L**2
    F = P * np.array([-1.0, 0.0, -1.0]) / np.sqrt(2.0)
    q, p = chain32.static_deflection(F)
    tip_angle = np.degrees(q.sum())
    assert 95.0 < tip_angle < 135.0
    assert relative_residual(chain32, q, F) <= 1e-9


def test_postbuckling_tip_angle():
    # Euler's elastica, cantilever under an axial compressive tip load P above P_cr = pi^2 EI/4L^2:
    # the tip angle theta0 solves sqrt(P L^2/EI) = K(sin^2(theta0/2)) (complete elliptic, m = k^2)
    alpha = 4.0
    theta0 = brentq(lambda t: ellipk(np.sin(t / 2) ** 2) - np.sqrt(alpha), 1e-6, 3.0)
    m = chain(64)
    F = np.array([-alpha * EI / L**2, 0.0, 0.0])
    q, _ = m.static_deflection(F)
    assert abs(abs(q.sum()) - theta0) < 2e-4 * theta0  # 4e-5 measured at n = 64
    assert np.linalg.norm(m.stiffness_Nm_per_rad * q - m.tip_jacobian(q).T @ F) <= \
        1e-9 * np.linalg.norm(m.stiffness_Nm_per_rad * q)


def test_non_convergence_raises_solve_error(chain32):
    F = np.array([0.0, 0.0, -10 * EI / L**2])
    with pytest.raises(SolveError, match="no equilibrium"):
        statics.static_deflection_planar(chain32.lengths_m, chain32.stiffness_Nm_per_rad, F,
                                     rtol=0.0, max_iter=3)


def test_free_function_matches_method(chain32):
    F = np.array([0.0, 0.0, -1.5 * EI / L**2])
    q, p = statics.static_deflection(chain32.pin_model, chain32.new_data(),
                                 chain32.stiffness_Nm_per_rad, chain32.tip_frame_id, F)
    q2, p2 = chain32.static_deflection(F)
    np.testing.assert_array_equal(q, q2)
    data = chain32.new_data()
    pin.framesForwardKinematics(chain32.pin_model, data, q)
    # the statics' tip is this placement (exact here); kept: the test's 1e-15 m
    np.testing.assert_allclose(p, data.oMf[chain32.tip_frame_id].translation, atol=5 * EPS * L)
