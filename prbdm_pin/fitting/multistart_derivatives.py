"""Derivatives of a fit's parameters with respect to one design parameter p.

They come from the implicit-function theorem on the fit's optimality conditions G(z, p) = 0:
dz/dp = -G_z^-1 G_p.

- ``unique="nearest"``: the KKT conditions of the rule's last step, z = [x, lambda],
  G = [x - x_ref + J^T lambda, F], F(x, p) = ln w_model(x; design p) - ln w_truth(p).
- otherwise a ``joint`` least-squares fit: the normal equations G = J^T r(x, p) = 0 (singular
  when the fit is not unique, e.g. n frequencies matched exactly by 2n parameters: the error
  says so).

G_z and G_p are central differences of the residual functions (the fit's own, so analytic
model Jacobians can replace them); the truth is recomputed at p +- h for G_p.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..chain.stiffness import finite_segment_stiffness
from ..errors import BeamInputError, InputTypeError, SolveError
from ..member.geometry import Beam
from ..options.checks import shown
from ..options.choices import UniqueRule
from ..options.validate import check_type
from .joint import JointResiduals
from .parametrisation import parametrisation
from .problem import FitProblem, lengths_from_unit, make_problem, unit_from_lengths
from .results import FitResult
from .spec import FitSpec
from .target import FitTarget
from .unique import log_frequency_jacobian, reference_x

__all__ = ["FitDerivative", "fit_derivative"]

H_X = 1e-4  # outer central-difference step in x (second derivatives of nested differences)
# central-difference step in p, relative to max(|p|, tiny): the truth's own solver noise
# dominates G_p below about 1e-3 relative (measured on the 1D beam truth)
H_P_REL = 5e-3
COND_MAX = 1e10


@dataclass(frozen=True, eq=False)
class FitDerivative:
    """The derivatives d(fitted parameters)/dp at one design.

    Attributes
    ----------
    parameter : float
        The design parameter p where the derivatives are taken (its own unit).
    d_lengths_m : ndarray, shape (n+1,)
        dL_j/dp, m per unit of p.
    d_stiffness_Nm_per_rad : ndarray, shape (n,)
        dK_j/dp, N m/rad per unit of p.
    dx_dp : ndarray, shape (2n,)
        In the fit coordinates x = [u, ln s] (both dimensionless), per unit of p.
    conditions : str
        ``"kkt"`` (unique='nearest') or ``"normal"`` (least squares).
    cond : float
        Condition number of G_z (dimensionless).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> def eb_target(b):  # Euler-Bernoulli frequencies of a uniform 1 m strip, rad/s
    ...     EI = b.material.E_Pa * 0.05 * b.thickness_m**3 / 12
    ...     rho_A = b.material.rho_kg_m3 * 0.05 * b.thickness_m
    ...     w = np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)
    ...     return pp.FitTarget(omega_truth_rad_s=w, tip_force_N=[0.0, 0.0, -1.0])
    >>> result = pp.fit(beam, eb_target(beam), 2, objective="eigen", stiffness="joint",
    ...                 unique="nearest", progress=False)
    >>> thick = lambda t: pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=t)
    >>> d = pp.fit_derivative(result, thick, 0.01, eb_target)
    >>> d.parameter, d.d_lengths_m.shape, d.d_stiffness_Nm_per_rad.shape
    (0.01, (3,), (2,))
    """

    parameter: float
    d_lengths_m: np.ndarray
    d_stiffness_Nm_per_rad: np.ndarray
    dx_dp: np.ndarray
    conditions: str
    cond: float


def fit_problem_of(result: FitResult, beam: Beam, target: FitTarget) -> FitProblem:
    """Return the fit problem ``result``'s recorded options pose for ``beam`` and ``target``."""
    return make_problem(beam, target, result.joints, result.options)


def fit_coordinates(result: FitResult, problem: FitProblem) -> np.ndarray:
    """Return ``result``'s parameters in the joint fit's coordinates, shape (2n,).

    The coordinates are the link-length units and the log spring factors (dimensionless).
    """
    u = unit_from_lengths(result.lengths_m, problem.length_m, problem.min_fraction)
    return np.r_[u, np.log(result.factors)]


def kkt_residuals(problem: FitProblem, z: np.ndarray) -> np.ndarray:
    """Return the optimality conditions of the ``unique="nearest"`` fit at z = (x, multipliers).

    They are the stationarity conditions, then the n log-frequency matches (zero at the fit).
    """
    n = problem.n_joints
    x, lam = z[: 2 * n], z[2 * n :]
    w, J = log_frequency_jacobian(problem, x)
    F = w - np.log(problem.target.omega_truth_rad_s)
    return np.r_[x - reference_x(problem) + J.T @ lam, F]


def _normal(spec: FitSpec, x: np.ndarray) -> np.ndarray:
    R = JointResiduals(spec)
    return central_jacobian(R.residuals, x, 1e-6).T @ R.residuals(x)


def central_jacobian(G: Callable[[np.ndarray], np.ndarray], z: np.ndarray, h: float
                     ) -> np.ndarray:
    """dG/dz by central differences of step ``h`` (in z's units), shape (len(G), len(z))."""
    E = h * np.eye(z.size)
    return np.array([(G(z + e) - G(z - e)) / (2 * h) for e in E]).T


def physical_parameters(problem: FitProblem, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Link lengths (m) and joint springs (N m/rad) of the fit coordinates ``x``."""
    n = problem.n_joints
    L = lengths_from_unit(x[:n], problem.length_m, problem.min_fraction)
    K = np.exp(x[n:]) * finite_segment_stiffness(problem.beam, L, problem.min_fraction)
    return L, K


def fit_derivative(result: FitResult, beam_at: Callable[[float], Beam], parameter: float,
                   target_at: Callable[[Beam], FitTarget], *,
                   step: float | None = None) -> FitDerivative:
    """Return dtheta/dp of ``result``, the fit of ``beam_at(parameter)`` to ``target_at`` of it.

    Parameters
    ----------
    result : FitResult
        A ``joint`` fit (``unique="nearest"``, or a least-squares fit with a unique optimum).
    beam_at : callable float -> Beam
        The design at a parameter value.
    parameter : float
        p of ``result``'s design.
    target_at : callable Beam -> FitTarget
        The truth of a design (called at p, p + h, p - h).
    step : float, optional
        h of G_p's central difference, in p's unit (default 5e-3 max(abs(p), 1e-12)).

    Returns
    -------
    FitDerivative
        The derivatives of the link lengths (m) and the joint springs (N m/rad) per unit of p.

    Raises
    ------
    BeamInputError
        When ``result`` is not a ``joint`` fit that recorded its options.
    SolveError
        When the optimality conditions are singular (a fit that is not unique).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> def eb_target(b):  # Euler-Bernoulli frequencies of a uniform 1 m strip, rad/s
    ...     EI = b.material.E_Pa * 0.05 * b.thickness_m**3 / 12
    ...     rho_A = b.material.rho_kg_m3 * 0.05 * b.thickness_m
    ...     w = np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)
    ...     return pp.FitTarget(omega_truth_rad_s=w, tip_force_N=[0.0, 0.0, -1.0])
    >>> result = pp.fit(beam, eb_target(beam), 2, objective="eigen", stiffness="joint",
    ...                 unique="nearest", progress=False)
    >>> thick = lambda t: pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=t)
    >>> d = pp.fit_derivative(result, thick, 0.01, eb_target)
    >>> (d.d_stiffness_Nm_per_rad / (3 * result.stiffness_Nm_per_rad / 0.01)).round(3)
    array([1., 1.])
    """
    check_type("result", result, FitResult)
    for name, f in (("beam_at", beam_at), ("target_at", target_at)):
        if not callable(f):
            raise InputTypeError(f"{name} = {shown(f)}: must be a function (of the parameter; "
                                 "of the beam)")
    if result.options is None or not parametrisation(result.stiffness).pose_independent:
        raise BeamInputError("result: needs a joint fit that recorded its options")
    p = float(parameter)
    h = H_P_REL * max(abs(p), 1e-12) if step is None else float(step)
    probs = {s: fit_problem_of(result, b, target_at(b))
             for s, b in ((0, beam_at(p)), (1, beam_at(p + h)), (-1, beam_at(p - h)))}
    P0 = probs[0]
    x = fit_coordinates(result, P0)
    n = P0.n_joints
    if result.options.unique is UniqueRule.NEAREST:
        w, J = log_frequency_jacobian(P0, x)
        # the multipliers of the KKT point: x - x_ref + J^T lambda = 0
        lam = -np.linalg.lstsq(J.T, x - reference_x(P0), rcond=None)[0]
        z = np.r_[x, lam]
        Gz = central_jacobian(lambda v: kkt_residuals(P0, v), z, H_X)
        Gp = (kkt_residuals(probs[1], z) - kkt_residuals(probs[-1], z)) / (2 * h)
        kind = "kkt"
    else:
        specs = {s: FitSpec(q, result.objective, result.options.max_nfev)
                 for s, q in probs.items()}
        z = x
        Gz = central_jacobian(lambda v: _normal(specs[0], v), z, H_X)
        Gp = (_normal(specs[1], z) - _normal(specs[-1], z)) / (2 * h)
        kind = "normal"
    c = float(np.linalg.cond(Gz))
    if not c < COND_MAX:
        raise SolveError(f"fit_derivative: the {kind} conditions are singular (cond {c:.3g}): "
                         "the fitted parameters are not a function of the design here (a fit "
                         "that is not unique: use unique='nearest')")
    dz = -np.linalg.solve(Gz, Gp)
    dx = dz[: 2 * n]
    # the physical parameters also move with the design directly (K0, the span)
    Lp, Kp = physical_parameters(probs[1], x + h * dx)
    Lm, Km = physical_parameters(probs[-1], x - h * dx)
    return FitDerivative(p, (Lp - Lm) / (2 * h), (Kp - Km) / (2 * h), dx, kind, c)
