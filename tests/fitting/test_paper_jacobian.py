"""The ``paper`` parametrisation's analytic derivatives against central finite differences:
the variable-projected eigen residuals and their loss over u, the scalar loss with a deflection
term over [u, ln k]; on a uniform strip (Euler-Bernoulli and elastica target), a tapered and a
stepped beam, in omega and omega^2, both deflection normalisations.

Steps h = 1e-6 in u and ln k: truncation (h^2) and the rounding of the eigen and static solves
(1e-12 / h) are both below 1e-7 of the largest derivative, the bound checked. Every static solve
starts from the straight pose (the batched statics do), so the differences see no warm start.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from paths import BEAMS
from reference import strip_target

from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.fitting.paper import PaperEigenResiduals, PaperScalarLoss
from prbdm_pin.fitting.problem import make_problem
from prbdm_pin.fitting.spec import FitSpec
from prbdm_pin.options.objects import FitOptions


def _central(f, x, h):
    cols = []
    for j in range(x.size):
        e = np.zeros(x.size)
        e[j] = h
        cols.append((np.asarray(f(x + e)) - np.asarray(f(x - e))) / (2 * h))
    return np.column_stack(cols)


def _problem(name, n, squared, eps=0.1, deflection_norm="position"):
    beam = load_beam(BEAMS / f"{name}.json")
    return make_problem(beam, strip_target(beam), n, FitOptions(
        stiffness="paper", squared=squared, eps_rad=eps, deflection_norm=deflection_norm,
        eigen_norm="paper"))


@pytest.mark.parametrize("name", ["uniform-narrow", "tapered", "stepped-narrow"])
@pytest.mark.parametrize("n,squared", [(2, False), (3, True), (4, False)])
def test_projected_eigen_jacobian_equals_central_differences(name, n, squared):
    p = _problem(name, n, squared)
    P = PaperEigenResiduals(FitSpec(p, "eigen", 100))
    rng = np.random.default_rng(n)
    for _ in range(2):
        u = rng.uniform(0.1, 0.9, n)
        D = _central(P.residuals, u, 1e-6)
        np.testing.assert_allclose(P.jac(u), D, rtol=0, atol=1e-7 * np.max(np.abs(D)))
        g = _central(lambda v: [P.loss(v)], u, 1e-6)[0]
        np.testing.assert_allclose(P.loss_grad(u), g, rtol=0, atol=1e-7 * np.max(np.abs(g)))


@pytest.mark.parametrize("name", ["uniform-narrow", "tapered", "stepped-narrow"])
@pytest.mark.parametrize("objective,norm,squared", [("combined", "position", False),
                                                    ("deflection", "displacement", False),
                                                    ("combined", "displacement", True)])
def test_scalar_loss_gradient_equals_central_differences(name, objective, norm, squared):
    n = 3
    p = _problem(name, n, squared, eps=0.2, deflection_norm=norm)
    S = PaperScalarLoss(FitSpec(p, objective, 100))
    rng = np.random.default_rng(7)
    for _ in range(2):
        x = np.r_[rng.uniform(0.1, 0.9, n), rng.uniform(-0.7, 0.7, p.n_poses)]
        D = _central(lambda v: [S.loss(v)], x, 1e-6)[0]
        np.testing.assert_allclose(S.jac(x), D, rtol=0, atol=1e-7 * np.max(np.abs(D)))


def test_scalar_loss_gradient_is_zero_where_the_model_cannot_be_solved():
    # SCFs so small that the load exceeds what the statics accept: the loss is BAD_LOSS there
    p = _problem("uniform-narrow", 2, False)
    S = PaperScalarLoss(FitSpec(p, "combined", 100))
    x = np.r_[0.5, 0.5, np.full(p.n_poses, math.log(1e-9))]
    assert S.loss(x) == 1e3
    assert not np.any(S.jac(x))


def _forward(f, x, n, h=1e-7):
    """Forward differences, the step turned inward at the upper end of the n length
    coordinates' box (u <= 1)."""
    f0 = np.atleast_1d(f(x))
    cols = []
    for j in range(x.size):
        e = np.zeros(x.size)
        e[j] = h if j >= n or x[j] + h <= 1.0 else -h
        cols.append((np.atleast_1d(f(x + e)) - f0) / e[j])
    return np.column_stack(cols)


@pytest.mark.slow
def test_paper_eigen_fit_reaches_the_optimum_of_the_finite_difference_fit(monkeypatch):
    # the differenced fit evaluates its stencils one design at a time: slow
    from prbdm_pin.fitting import fit

    beam = load_beam(BEAMS / "uniform-narrow.json")
    target = strip_target(beam)
    objective = "eigen"
    kw = dict(objective=objective, stiffness="paper", starts=2, seed=0, progress=False)
    r_an = fit(beam, target, 3, **kw)
    with monkeypatch.context() as m:
        m.setattr(PaperEigenResiduals, "jac",
                  lambda self, u: _forward(self.residuals, u, u.size))
        m.setattr(PaperEigenResiduals, "loss_grad",
                  lambda self, u: _forward(self.loss, u, u.size)[0])
        m.setattr(PaperScalarLoss, "jac",
                  lambda self, x: _forward(self.loss, x, self.p.n_joints)[0])
        r_fd = fit(beam, target, 3, **kw)
    loss = f"{objective}_loss_pct"
    a, b = getattr(r_an, loss), getattr(r_fd, loss)
    # What holds on every BLAS kernel: the analytic fit reaches at least the differenced fit's
    # optimum. Its SLSQP polish stops on a loss change below 1e-14 relative (its losses agree to
    # 1.4e-13 across kernels); 1e-9 is far above that and far below any other optimum.
    assert a <= b * (1 + 1e-9), (a, b)
    # Both fits draw the same starts and stage-1 ends in the same basin, so the designs are one
    # local optimum by the fit's own test (multistart: lengths within 1e-3 L).
    np.testing.assert_allclose(r_an.lengths_m, r_fd.lengths_m, atol=1e-3 * beam.length_m)
    # How close the differenced fit gets is not a property of the derivatives: its forward
    # differences (1e-7 step) are off by the step's truncation and the loss's rounding over the
    # step, and its polish on them may stop on SLSQP's iteration limit short of the optimum by
    # an amount the kernel's rounding sets (with SkylakeX 1.9e-4 relative in loss and 1.1e-4 L
    # in lengths; with Prescott 7.8e-5). Only where that polish converged are both fits at the
    # optimum to the stencil's resolution: its error against the stage-1 tolerance, measured
    # 1.1e-5 relative above the analytic fit's loss, lengths within 6e-6 L (Haswell, Zen).
    if r_fd.message.endswith("polished: Optimization terminated successfully"):
        assert b - a <= 3e-5 * b, (a, b)
        np.testing.assert_allclose(r_an.lengths_m, r_fd.lengths_m, atol=1e-4 * beam.length_m)
