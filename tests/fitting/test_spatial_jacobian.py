"""The spatial fit's analytic Jacobian: against central differences of its residual, and the
fit it drives against the fit with forward differences.

References: a spatial chain taken as its own truth (its modes from one eigensolve of the whole
pencil, labelled by the axis their kinetic energy sits on), so an exact match exists.
"""

import numpy as np
import pytest
import scipy.linalg
from central_differences import central_difference
from chain_truth import self_target
from scipy.optimize import least_squares
from tolerances import EPS, eig_rtol

from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.fitting import spatial_fit
from prbdm_pin.fitting.multistart import fit
from prbdm_pin.fitting.problem import unit_from_lengths
from prbdm_pin.fitting.spatial_design import LOG_FACTOR_BOUND, EigenTerm, SpatialDesign
from prbdm_pin.fitting.spatial_jacobian import spatial_jacobian
from prbdm_pin.fitting.spatial_target import select_spatial
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.options.objects import FitOptions

LENGTHS = np.array([0.15, 0.3, 0.2, 0.2, 0.15])  # of L


def _self_target(beam, lengths, axes, scale):
    k = spatial_stiffness(beam, lengths, axes) * scale
    return self_target(build_model(beam, lengths, k, axes=axes))


def _design(beam, axes, n=4, terms=()):
    rng = np.random.default_rng(7)
    lengths = LENGTHS * beam.length_m
    target = _self_target(beam, lengths, axes, np.exp(rng.uniform(-0.3, 0.3, n * len(axes))))
    o = FitOptions(axes=axes, stiffness="joint")
    sel = select_spatial(target, o.axes, n, o.frequencies)
    return SpatialDesign(beam, sel, n, o, terms or (EigenTerm(sel),)), sel


def _residual_noise(d, x):
    """Rounding of each relative frequency error: the block eigensolver's (spread) and that of
    M's entries (CRBA: a few roundings of the largest entry) through 1 / lambda_min(block)."""
    model = d.model(x)
    M = model.mass_matrix()
    w = d.frequencies(model)
    noise = np.empty_like(w)
    for a in d.order:
        idx = model.axis_index(a)
        block = M[np.ix_(idx, idx)]
        k = model.stiffness_Nm_per_rad[idx]
        omega = np.sqrt(scipy.linalg.eigh(np.diag(k), block, eigvals_only=True))
        cond = np.abs(M).max() / np.linalg.eigvalsh(block).min()
        rows = d.sel.axis == a
        noise[rows] = eig_rtol(omega) + M.shape[0] * EPS * cond
    return noise * w / d.sel.omega_truth_rad_s


@pytest.mark.parametrize("axes", ["xy", "yz", "xyz"])
def test_the_analytic_jacobian_is_the_residuals_derivative(reference_panel, axes):
    d, _ = _design(reference_panel, axes)
    rng = np.random.default_rng(11)
    x = np.r_[rng.uniform(0.2, 0.8, d.n), rng.uniform(-0.5, 0.5, d.n * d.m)]
    J = spatial_jacobian(d)(x)
    # x is dimensionless (unit box, log factors): h = 1e-5 balances truncation and rounding
    fd, bound = central_difference(d.residual, x, 1e-5, _residual_noise(d, x))
    assert J.shape == fd.shape == (d.sel.omega_truth_rad_s.size, x.size)
    assert np.all(np.abs(J - fd) <= bound)
    # a factor of one axis moves that axis' frequencies only: structural zeros
    for c, a in enumerate(d.order):
        assert np.all(J[d.sel.axis != a][:, d.n + c::d.m] == 0.0)


class _Near:
    """A regulariser w (x - x_ref) read back from the model (so the minimum is unique)."""

    label = "near"

    def __init__(self, x_ref, weight):
        self.x_ref, self.weight, self.size = x_ref, weight, x_ref.size

    def residual(self, d, model):
        L = model.lengths_m
        u = unit_from_lengths(L, d.beam.length_m, d.o.min_fraction)
        log_s = np.log(model.stiffness_Nm_per_rad / d.unit_springs(L))
        return self.weight * (np.r_[u, log_s] - self.x_ref)

    def jacobian(self, d, x):
        return self.weight * np.eye(x.size)


class _Bare:
    """A term with a residual and no Jacobian."""

    label = "bare"
    size = 1

    def residual(self, d, model):
        return np.array([model.lengths_m[0]])


def test_terms_without_a_jacobian_fall_back_to_differences(reference_panel):
    d, sel = _design(reference_panel, "xy")
    assert callable(spatial_jacobian(d))
    d2, _ = _design(reference_panel, "xy", terms=(EigenTerm(sel), _Bare()))
    assert spatial_jacobian(d2) == "2-point"
    d3, _ = _design(reference_panel, "xy", terms=(EigenTerm(sel), _Near(np.zeros(12), 1.0)))
    x = np.r_[np.full(4, 0.5), np.zeros(8)]
    J = spatial_jacobian(d3)(x)
    # the terms' Jacobians stacked in their order: the regulariser's is w I exactly
    assert J.shape == (8 + 12, 12) and np.array_equal(J[8:], np.eye(12))


def test_the_fit_reaches_the_optimum_of_forward_differences(reference_panel):
    # the eigen residual alone has a manifold of exact solutions (3n unknowns, 2n modes); a
    # regulariser toward the start makes the minimum unique, so both Jacobians must find it
    d0, sel = _design(reference_panel, "xy")
    x0 = np.r_[np.full(4, 0.5), np.linspace(-0.4, 0.4, 8)]
    weight = 0.1
    d, _ = _design(reference_panel, "xy", terms=(EigenTerm(sel), _Near(x0, weight)))
    lo = np.r_[np.zeros(4), np.full(8, -LOG_FACTOR_BOUND)]
    hi = np.r_[np.ones(4), np.full(8, LOG_FACTOR_BOUND)]
    tight = {"ftol": 1e-12, "xtol": 1e-12, "gtol": 1e-12}  # converge to the solvers' limit
    a = least_squares(d.residual, x0, jac=spatial_jacobian(d), bounds=(lo, hi), **tight)
    b = least_squares(d.residual, x0, jac="2-point", bounds=(lo, hi), **tight)
    assert a.status > 0 and b.status > 0
    # each stops where its gradient is small: near the minimum the distance to it is at most
    # |g| / mu, mu the Hessian's least eigenvalue, taken as half Gauss-Newton's J^T J (>= w^2)
    # for the curvature of the small eigen residuals it drops
    J = spatial_jacobian(d)(a.x)
    mu = 0.5 * np.linalg.eigvalsh(J.T @ J).min()
    gap = (np.linalg.norm(a.grad) + np.linalg.norm(b.grad)) / mu
    assert np.linalg.norm(a.x - b.x) <= gap
    # the costs then agree to second order in that distance
    assert abs(a.cost - b.cost) <= gap * np.linalg.norm(a.grad) + np.linalg.eigvalsh(
        J.T @ J).max() * gap**2


def test_the_multistart_fit_matches_exactly_with_either_jacobian(reference_panel, monkeypatch):
    beam = reference_panel
    target = _self_target(beam, LENGTHS * beam.length_m, "xy", np.exp(np.linspace(-.3, .3, 8)))
    r = fit(beam, target, 4, axes="xy", stiffness="joint", starts=3, progress=False)
    monkeypatch.setattr(spatial_fit, "spatial_jacobian", lambda d: "2-point")
    r_fd = fit(beam, target, 4, axes="xy", stiffness="joint", starts=3, progress=False)
    # an exact match exists: the solver's tolerance on the relative residuals (least_squares'
    # default ftol 1e-8) bounds both fits' errors, as in test_spatial_fit
    assert r.worst_mode_error_pct < 1e-4 and r_fd.worst_mode_error_pct < 1e-4
    # the analytic Jacobian costs one evaluation where differences cost 1 + 12
    assert r.nfev < r_fd.nfev
