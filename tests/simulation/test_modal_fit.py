"""The modal_fit damping form: a diagonal joint damping c >= 0 fitted to per-mode ratios.

References: the stiffness form C = beta K (its ratios xi_1 omega_k / omega_1 are carried by a
diagonal C exactly, so the fit must return c = beta k); another bounded least-squares
algorithm (scipy's BVLS) for the fit's optimum; the one-degree-of-freedom oscillator's
analytic ratio c / (2 sqrt(k m)), under- and overdamped, for the exact ratios from the complex
eigenvalues; the proportional-damping approximation's order (its error vanishes faster than
the damping squared); bad input refused by name.
"""

import numpy as np
import pytest
import scipy.optimize as so
from tolerances import EPS, eig_rtol

import prbdm_pin as pp
from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.errors import BeamInputError
from prbdm_pin.model.hub import Hub
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.simulation.damping import damping_matrix
from prbdm_pin.simulation.hub_damping import plant_damping
from prbdm_pin.simulation.modal_fit import damped_ratios, flexible_modes, modal_fit_damping

LENGTHS = {3: np.array([0.15, 0.3, 0.3, 0.25]), 5: np.array([0.1, 0.2, 0.2, 0.2, 0.15, 0.15])}
# per-mode ratios as a calibration returns them (modes 1..5)
CALIBRATED = np.array([0.03, 0.02, 0.025, 0.02, 0.01])


@pytest.fixture(scope="module", params=[3, 5], ids=["3R", "5R"])
def chain(request, reference_panel):
    L = LENGTHS[request.param] * reference_panel.length_m / LENGTHS[request.param].sum()
    return build_model(reference_panel, L, finite_segment_stiffness(reference_panel, L))


def _fit_matrix(M, k, n_free=0):
    """xi(c) = G c in the unknowns s = c / k: the fit's matrix, for its conditioning."""
    omega, Phi = flexible_modes(M, k, n_free)
    return (Phi[n_free:] ** 2).T / (2.0 * omega[:, None]) * k


def test_stiffness_form_ratios_give_beta_k(chain):
    M, k = chain.mass_matrix(), np.asarray(chain.stiffness_Nm_per_rad)
    w = np.asarray(chain.natural_frequencies())
    xi1 = 0.5 * w[0] / w[-1]  # the top mode at 0.5: underdamped
    beta = 2.0 * xi1 / w[0]
    fit = modal_fit_damping(M, k, xi1 * w / w[0])
    # the modes' entries are good to eig_rtol (the pencil's spread); the square solve
    # amplifies that by cond(G)
    tol = np.linalg.cond(_fit_matrix(M, k)) * eig_rtol(w)
    np.testing.assert_allclose(fit.joint_damping_Nms_per_rad, beta * k, rtol=tol)
    # C = beta K is diagonalised by the modes: the exact ratios are the asked ones
    np.testing.assert_allclose(fit.achieved_ratios, xi1 * w / w[0], rtol=tol)
    assert fit.residual <= tol * np.linalg.norm(fit.requested_ratios)
    # and the simulation's modal_fit matrix is that diagonal
    C = damping_matrix(M, chain.stiffness_matrix(), xi1 * w / w[0], "modal_fit")
    np.testing.assert_array_equal(C, np.diag(fit.joint_damping_Nms_per_rad))


def test_fit_is_the_bounded_least_squares_optimum(chain):
    M, k = chain.mass_matrix(), np.asarray(chain.stiffness_Nm_per_rad)
    xi = CALIBRATED[:chain.n_joints]
    fit = modal_fit_damping(M, k, xi)
    G = _fit_matrix(M, k)
    ref = so.lsq_linear(G, xi, bounds=(0.0, np.inf), method="bvls", tol=1e-15)
    # two active-set solvers on the same square system: roundings times cond(G), a few dozen
    # of them over the iterations
    tol = 50 * np.linalg.cond(G) * EPS * np.abs(fit.joint_damping_Nms_per_rad).max()
    np.testing.assert_allclose(fit.joint_damping_Nms_per_rad, ref.x * k, rtol=0, atol=tol)
    assert np.all(fit.joint_damping_Nms_per_rad >= 0.0)
    # c = beta k is feasible: the fit never does worse than the best stiffness form
    betas = np.linspace(0.0, 2.0 * xi.max() / np.asarray(chain.natural_frequencies())[0], 2001)
    best_beta = min(np.linalg.norm(G @ np.full(k.size, b) - xi) for b in betas)
    assert fit.residual <= fit.stiffness_residual <= best_beta
    print(f"{chain.n_joints}R asked {xi}: achieved {fit.achieved_ratios}, residual "
          f"{fit.residual:.4g} (best stiffness form {fit.stiffness_residual:.4g})")


def test_projection_error_vanishes_faster_than_the_damping_squared(chain):
    """The proportional-damping approximation is exact to first order in C: halving every
    asked ratio (c halves: the fit is linear) must cut |achieved - projected| at least
    fourfold (measured: eightfold, third order)."""
    M, k = chain.mass_matrix(), np.asarray(chain.stiffness_Nm_per_rad)
    gaps = []
    for s in (1.0, 0.5, 0.25):
        fit = modal_fit_damping(M, k, s * CALIBRATED[:chain.n_joints])
        gaps.append(np.abs(fit.achieved_ratios - fit.projected_ratios).max())
    order = np.log2(np.array(gaps[:-1]) / np.array(gaps[1:]))
    print(f"{chain.n_joints}R approximation gaps {gaps}, orders {order}")
    assert np.all(order > 2.0)


def test_damped_ratios_of_one_oscillator():
    """One mass on a spring and damper: zeta = c / (2 sqrt(k m)), below and above critical,
    and two uncoupled oscillators come back in ascending frequency."""
    m, k = 2.0, 800.0
    for zeta in (0.0, 0.02, 0.7, 1.5, 3.0):
        c = 2.0 * zeta * np.sqrt(k * m)
        w, z = damped_ratios(np.array([[m]]), np.array([[k]]), np.array([[c]]))
        # a 2x2 eigen solve and a sum, product and square root of its roots: a few dozen
        # roundings (at zeta = 3 the roots differ 34-fold; sum and product stay well
        # conditioned)
        np.testing.assert_allclose([w[0], z[0]], [np.sqrt(k / m), zeta], rtol=50 * EPS,
                                   atol=50 * EPS)
    M, K, C = np.diag([1.0, 3.0]), np.diag([900.0, 27.0]), np.diag([0.6, 0.9])
    w, z = damped_ratios(M, K, C)
    np.testing.assert_allclose(w, [3.0, 30.0], rtol=50 * EPS)
    np.testing.assert_allclose(z, [0.9 / (2 * 9.0), 0.6 / (2 * 30.0)], rtol=50 * EPS)


def test_hub_joint_stays_undamped_and_the_stiffness_case_holds(chain):
    """On a hub the ratios go to the flexible modes; the hub model's stiffness-form ratios
    give plant_damping's stiffness form back."""
    model = build_model(chain.beam, chain.lengths_m, chain.stiffness_Nm_per_rad,
                        hub=Hub(50.0, 0.05))
    M, k = model.mass_matrix(), np.asarray(model.stiffness_Nm_per_rad)
    w = np.asarray(model.natural_frequencies())[1:]
    xi = 0.5 * w[0] / w[-1] * w / w[0]
    C = plant_damping(model, M, xi, "modal_fit")
    ref = plant_damping(model, M, xi[0], "stiffness")
    assert C[0, 0] == 0.0
    # the public door: the same fit at the straight pose (the same arithmetic)
    np.testing.assert_array_equal(pp.fit_joint_damping(model, xi).joint_damping_Nms_per_rad,
                                  np.diag(C))
    tol = np.linalg.cond(_fit_matrix(M, k, 1)) * eig_rtol(w)  # as for the clamped chain
    np.testing.assert_allclose(np.diag(C), np.diag(ref), rtol=tol)
    _, z = damped_ratios(M, model.stiffness_matrix(), C, n_free=1)
    np.testing.assert_allclose(z, xi, rtol=tol)


@pytest.mark.parametrize("bad, match", [
    ([0.02, -0.01, 0.02], r"damping_ratio\[1\]"),
    ([0.02, 0.02], "damping_ratio has shape"),
    ([0.02, 1.0, 0.02], r"damping_ratio\[1\]"),
    ([0.02, float("nan"), 0.02], "damping_ratio"),
])
def test_bad_ratios_are_refused_by_name(reference_panel, bad, match):
    L = LENGTHS[3] * reference_panel.length_m / LENGTHS[3].sum()
    model = build_model(reference_panel, L, finite_segment_stiffness(reference_panel, L))
    with pytest.raises(BeamInputError, match=match):
        modal_fit_damping(model.mass_matrix(), model.stiffness_Nm_per_rad, bad)
    with pytest.raises(BeamInputError, match=match):
        damping_matrix(model.mass_matrix(), model.stiffness_matrix(), bad, "modal_fit")
