"""Derivatives of a ``unique="nearest"`` fit's parameters for every design variable at once.

The truth's frequency gradient is supplied (``truth_gradient``) instead of re-solving the truth
at p +- h.

The rule's model is the KKT point z = [x, lambda] of ``min |x - x_ref|^2`` s.t. F = 0 with
``G(z, p, omega) = [x - x_ref + J(x, p)^T lambda, ln w(x, p) - ln omega]``, omega the truth's
frequencies, themselves a function of the design. The implicit-function theorem gives::

    dz/dp = -G_z^-1 (G_p + G_omega d omega/dp),   G_omega = [0; -diag(1 / omega)].

G_z is the nested central difference of ``fit_derivative``. G_p is the model's direct dependence
on the design at fixed x (the lengths fixed, the springs s K0(L, p)), analytic
(``model_design_gradient.frequency_design_gradient`` with ``finite_segment_design_gradient``):
its constraint rows are d ln w/dp; its stationarity rows d(J^T lambda)/dp, the x-gradient of
lambda . d ln w/dp, take one central difference in x of that analytic term (the same for every
variable, no model rebuilt at a moved design). The physical parameters L(u) and
K = s K0(L, p) follow in closed form.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..chain.sections_derivatives import finite_segment_stiffness_gradient
from ..chain.sections_design_derivatives import (
    finite_segment_design_gradient,
    section_design_gradient,
)
from ..errors import BeamInputError, SolveError
from ..member.design import Design
from ..model.prbdm_model_derivatives import frequency_design_gradient
from ..options.choices import UniqueRule
from ..options.validate import check_type
from ..truth.compute_derivatives import TruthGradient
from .joint_jacobian import unit_lengths_jacobian
from .multistart_derivatives import (
    COND_MAX,
    H_X,
    central_jacobian,
    fit_coordinates,
    fit_problem_of,
    kkt_residuals,
)
from .problem import FitProblem, lengths_from_unit
from .results import FitResult
from .target import FitTarget, read_only
from .unique import log_frequency_jacobian, reference_x

__all__ = ["FitDesignGradient", "fit_design_gradient", "kkt_design_jacobian",
           "log_frequency_design_gradient"]

# central-difference step in x (stick-breaking units and log spring factors) of the analytic
# d ln w/dp in G_p's stationarity rows: O(h^2) truncation against O(1e-16 / h) rounding
H_MIXED = 1e-5
MATCH_RTOL = 1e-6  # the fit must reproduce the truth frequencies it is differentiated about


@dataclass(frozen=True, eq=False)
class FitDesignGradient:
    """Derivatives d(fitted parameters)/dp of a ``unique="nearest"`` fit, a column per variable.

    Attributes
    ----------
    names, units : tuple of str
        The design variables and their SI units.
    d_lengths_m : ndarray, shape (n+1, nv)
        dL_i/dp_j, m per unit of p_j.
    d_stiffness_Nm_per_rad : ndarray, shape (n, nv)
        dK_i/dp_j, N m/rad per unit of p_j.
    dx_dp : ndarray, shape (2n, nv)
        In the fit coordinates x = [u, ln s] (both dimensionless), per unit of p_j.
    cond : float
        Condition number of G_z (dimensionless).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -100.0])
    >>> design = pp.Design(beam, ("thickness",))
    >>> truth = pp.truth_gradient(beam, design, model="beam", modes=2)
    >>> target = pp.FitTarget(omega_truth_rad_s=truth.omega_rad_s, tip_force_N=[0.0, 0.0, -1.0])
    >>> result = pp.fit(beam, target, 2, objective="eigen", stiffness="joint",
    ...                 unique="nearest", progress=False)
    >>> g = pp.fit_design_gradient(result, design, [0.01], truth)
    >>> g.names, g.units, g.d_lengths_m.shape
    (('thickness',), ('m',), (3, 1))
    """

    names: tuple[str, ...]
    units: tuple[str, ...]
    d_lengths_m: np.ndarray
    d_stiffness_Nm_per_rad: np.ndarray
    dx_dp: np.ndarray
    cond: float


def log_frequency_design_gradient(problem: FitProblem, design: Design, x: np.ndarray,
                                  cache: dict | None = None) -> np.ndarray:
    """Return d ln w/dp of the ``joint`` fit problem's model at fixed fit coordinates x.

    The lengths are fixed and the springs are s K0(L, p); the result has shape (n, nv), per unit
    of each variable of ``design``; ``problem.beam`` is the design's beam at p. ``cache``: a dict
    that keeps the sections and springs of the lengths already seen (points that differ in the
    spring factors only).
    """
    n = problem.n_joints
    key = x[:n].tobytes()
    if cache is None or key not in cache:
        L = lengths_from_unit(x[:n], problem.length_m, problem.min_fraction)
        sec = section_design_gradient(problem.beam, design, L, problem.min_fraction)
        springs = finite_segment_design_gradient(problem.beam, design, L, problem.min_fraction)
        if cache is None:
            cache = {}
        cache[key] = (L, sec, springs)
    L, sec, (K0, dK0) = cache[key]
    s = np.exp(x[n:])
    omega, d_omega = frequency_design_gradient(problem.beam, design, L, s * K0,
                                               s[:, None] * dK0, problem.min_fraction, sec)
    return d_omega / omega[:, None]


def kkt_design_jacobian(problem: FitProblem, design: Design, z: np.ndarray) -> np.ndarray:
    """Return dG/dp of the ``unique="nearest"`` fit's KKT conditions, shape (3n, nv).

    G is ``derivative.kkt_residuals``, at fixed z = [x, lambda] and fixed truth frequencies: the
    stationarity rows d/dx (lambda . d ln w/dp) (one central difference in x), then the
    constraint rows d ln w/dp; ``problem.beam`` is the design's beam at p.
    """
    n = problem.n_joints
    x, lam = z[: 2 * n], z[2 * n:]
    cache: dict = {}  # the spring-factor steps keep the lengths: their sections are reused

    def weighted(v: np.ndarray) -> np.ndarray:
        return lam @ log_frequency_design_gradient(problem, design, v, cache)

    return np.vstack([central_jacobian(weighted, x, H_MIXED).T,
                      log_frequency_design_gradient(problem, design, x, cache)])


def fit_design_gradient(result: FitResult, design: Design, p: np.ndarray,
                        truth: TruthGradient) -> FitDesignGradient:
    """Return dtheta/dp of ``result`` for every variable of ``design``.

    ``result`` is the ``unique="nearest"`` fit of ``design.beam_at(p)`` to the truth frequencies
    ``truth.omega_rad_s``, whose gradient is ``truth.d_omega_rad_s``.

    Parameters
    ----------
    result : FitResult
        ``fit(design.beam_at(p), target, n, stiffness="joint", unique="nearest")`` of a target
        with the frequencies of ``truth``.
    design : Design
        The design variables and the beam they act on.
    p : array_like, shape (nv,)
        The design (SI units).
    truth : TruthGradient
        ``truth_gradient(design.beam_at(p), design, ...)``: at least n modes, the same variables.

    Returns
    -------
    FitDesignGradient
        The derivatives of the link lengths (m) and joint springs (N m/rad) per SI unit of each
        design variable.

    Raises
    ------
    BeamInputError
        Not a ``unique="nearest"`` fit, variables that differ, or a fit of other frequencies.
    SolveError
        Singular KKT conditions.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -100.0])
    >>> design = pp.Design(beam, ("thickness",))
    >>> truth = pp.truth_gradient(beam, design, model="beam", modes=2)
    >>> target = pp.FitTarget(omega_truth_rad_s=truth.omega_rad_s, tip_force_N=[0.0, 0.0, -1.0])
    >>> result = pp.fit(beam, target, 2, objective="eigen", stiffness="joint",
    ...                 unique="nearest", progress=False)
    >>> g = pp.fit_design_gradient(result, design, [0.01], truth)
    >>> (g.d_stiffness_Nm_per_rad[:, 0] * 0.01 / result.stiffness_Nm_per_rad).round(3)  # k ~ t^3
    array([3., 3.])
    """
    check_type("result", result, FitResult)
    check_type("design", design, Design)
    check_type("truth", truth, TruthGradient, "a prbdm_pin.TruthGradient (truth_gradient)")
    if result.options is None or result.options.unique is not UniqueRule.NEAREST:
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
    # the truth frequencies move the constraint rows only: d(-ln omega)/dp
    Gp = kkt_design_jacobian(P0, design, z)
    Gp[2 * n:] -= d_omega / omega[:, None]
    dz = -np.linalg.solve(Gz, Gp)
    dx = dz[: 2 * n]
    # the physical parameters: L(u) does not see the design; K = s K0(L(u), p)
    u, s = x[:n], np.exp(x[n:])
    L = lengths_from_unit(u, P0.length_m, P0.min_fraction)
    dL = unit_lengths_jacobian(u, P0.length_m, P0.min_fraction) @ dx[:n]
    K0, dK0_station = finite_segment_stiffness_gradient(beam, L)
    _, dK0_design = finite_segment_design_gradient(beam, design, L, P0.min_fraction)
    dK0 = dK0_station @ dL.cumsum(axis=0)[:-1] + dK0_design
    dK = s[:, None] * dK0 + (s * K0)[:, None] * dx[n:]
    return FitDesignGradient(design.names, design.units, read_only(dL), read_only(dK),
                             read_only(dx), c)
