"""d(fitted parameters)/dp of a ``unique="nearest"`` fit for every design variable at once, with
the truth's frequency gradient supplied (``truth_gradient``) instead of re-solving the truth at
p +- h.

The rule's model is the KKT point z = [x, lambda] of min |x - x_ref|^2 s.t. F = 0 with
``G(z, p, omega) = [x - x_ref + J(x, p)^T lambda, ln w(x, p) - ln omega]``, omega the truth's
frequencies, themselves a function of the design. The implicit-function theorem gives

    dz/dp = -G_z^-1 (G_p + G_omega d omega/dp),   G_omega = [0; -diag(1 / omega)].

G_z is the nested central difference of ``fit_derivative``; G_p is a central difference of the
model at fixed x and fixed truth frequencies: the sections and finite-segment springs of the
moved planform (no truth solve). The physical parameters move with x and, through the springs
``K = s K0(L, p)``, with the design directly: central differences of that cheap map too.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..design import Design
from ..errors import BeamInputError, SolveError
from ..results import FitResult
from ..target import FitTarget, read_only
from ..truth.gradient import TruthGradient
from .derivative import (
    COND_MAX,
    H_X,
    central_jacobian,
    fit_coordinates,
    fit_problem_of,
    kkt_residuals,
    physical_parameters,
)
from .unique import log_frequency_jacobian, reference_x

__all__ = ["FitDesignGradient", "fit_design_gradient", "STEP_REL"]

# central-difference step in the design at fixed truth frequencies, times ``Design.scales``:
# the model is smooth in the planform and thickness (exact section integrals), so the step is
# set by the O(h^2) truncation from above and by the O(1e-10) rounding of the inner
# frequency Jacobian from below
STEP_REL = 1e-3
MATCH_RTOL = 1e-6  # the fit must reproduce the truth frequencies it is differentiated about


@dataclass(frozen=True, eq=False)
class FitDesignGradient:
    """d(fitted parameters)/dp of a ``unique="nearest"`` fit, one column per design variable.

    Attributes
    ----------
    names, units : tuple of str
        The design variables and their SI units.
    d_lengths_m : ndarray, shape (n+1, nv)
        dL_i/dp_j, m per unit of p_j.
    d_stiffness_Nm_per_rad : ndarray, shape (n, nv)
        dK_i/dp_j, N m/rad per unit of p_j.
    dx_dp : ndarray, shape (2n, nv)
        In the fit coordinates x = [u, ln s].
    cond : float
        Condition number of G_z.
    """

    names: tuple[str, ...]
    units: tuple[str, ...]
    d_lengths_m: np.ndarray
    d_stiffness_Nm_per_rad: np.ndarray
    dx_dp: np.ndarray
    cond: float


def fit_design_gradient(result: FitResult, design: Design, p: np.ndarray,
                        truth: TruthGradient, *, step_rel: float = STEP_REL
                        ) -> FitDesignGradient:
    """dtheta/dp of ``result``, the ``unique="nearest"`` fit of ``design.beam_at(p)`` to the
    truth frequencies ``truth.omega_rad_s``, with their gradient ``truth.d_omega_rad_s``.

    Parameters
    ----------
    result : FitResult
        ``fit(design.beam_at(p), target, n, stiffness="joint", unique="nearest")`` of a target
        with the frequencies of ``truth``.
    design : Design
    p : array_like, shape (nv,)
        The design (SI units).
    truth : TruthGradient
        ``truth_gradient(design.beam_at(p), design, ...)``: at least n modes, the same variables.
    step_rel : float
        Step of G_p's central difference, times ``design.scales``.

    Raises
    ------
    BeamInputError
        Not a ``unique="nearest"`` fit, variables that differ, or a fit of other frequencies.
    SolveError
        Singular KKT conditions.
    """
    if result.options is None or result.options.unique != "nearest":
        raise BeamInputError("result: needs a fit with unique = 'nearest' (its KKT conditions "
                             "define the model as a function of the design)")
    if tuple(truth.names) != tuple(design.names):
        raise BeamInputError(f"truth.names = {truth.names}: must be the design's variables "
                             f"{design.names}")
    p = design.check(p)
    n = result.joints
    if truth.omega_rad_s.size < n:
        raise BeamInputError(f"truth: {truth.omega_rad_s.size} modes for a {n}R fit (needs {n})")
    beam = design.beam_at(p)
    omega, d_omega = truth.omega_rad_s[:n], truth.d_omega_rad_s[:n]
    model_w = np.asarray(result.omega_model_rad_s)[0, :n]
    if not np.allclose(model_w, omega, rtol=MATCH_RTOL, atol=0.0):
        raise BeamInputError(f"result: its frequencies {model_w.tolist()} rad/s are not the "
                             f"truth's {omega.tolist()}: a fit of another design or target")
    target = FitTarget(omega, beam.tip_force_N)
    P0 = fit_problem_of(result, beam, target)
    x = fit_coordinates(result, P0)
    _, J = log_frequency_jacobian(P0, x)
    lam = -np.linalg.lstsq(J.T, x - reference_x(P0), rcond=None)[0]
    z = np.r_[x, lam]
    Gz = central_jacobian(lambda v: kkt_residuals(P0, v), z, H_X)
    c = float(np.linalg.cond(Gz))
    if not c < COND_MAX:
        raise SolveError(f"fit_design_gradient: the KKT conditions are singular (cond {c:.3g})")
    nv = design.size
    h = float(step_rel) * design.scales
    Gp = np.zeros((z.size, nv))
    problems = []
    for j in range(nv):
        e = np.zeros(nv)
        e[j] = h[j]
        pair = [fit_problem_of(result, design.beam_at(p + s * e), target) for s in (1.0, -1.0)]
        Gp[:, j] = (kkt_residuals(pair[0], z) - kkt_residuals(pair[1], z)) / (2.0 * h[j])
        problems.append(pair)
    # the truth frequencies move the constraint rows only: d(-ln omega)/dp
    Gp[2 * n:] -= d_omega / omega[:, None]
    dz = -np.linalg.solve(Gz, Gp)
    dx = dz[: 2 * n]
    dL = np.zeros((n + 1, nv))
    dK = np.zeros((n, nv))
    for j, (Pp, Pm) in enumerate(problems):
        Lp, Kp = physical_parameters(Pp, x + h[j] * dx[:, j])
        Lm, Km = physical_parameters(Pm, x - h[j] * dx[:, j])
        dL[:, j] = (Lp - Lm) / (2.0 * h[j])
        dK[:, j] = (Kp - Km) / (2.0 * h[j])
    return FitDesignGradient(design.names, design.units, read_only(dL), read_only(dK),
                             read_only(dx), c)
