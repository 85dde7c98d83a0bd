"""The fit problem.

Everything fixed during a fit (FitProblem: the beam, the target, the options and the spring
parametrisation) and the length parametrisation.

The spring parametrisation (how a design's stiffness factors become springs) is an object of
``fitting.parametrisation``: ``paper`` (Eq. 14, one stiffness correction factor per pose of the
sweep) or ``joint`` (one pose-independent factor per joint on the finite-segment springs);
:func:`make_problem` turns the ``stiffness`` option into it.

Link lengths live on the bounded simplex ``sum L_j = L, L_j >= f L`` (f = 0.02, Eq. 15); the
upper bound (1 - f) L of Eq. 15d is implied by the others. The single-objective local solvers
use the stick-breaking map :func:`lengths_from_unit` from the box [0, 1]^n onto that simplex, so
box-bounded solvers (least_squares, L-BFGS-B) handle the equality exactly; NSGA-II uses
``fitting.pareto_problem.LengthRepair`` instead.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import BeamInputError
from ..member.geometry import Beam
from ..options.choices import MIN_FRACTION, DeflectionNorm, EigenNorm
from ..options.objects import FitOptions, ParetoOptions
from .target import FitTarget, read_only

if TYPE_CHECKING:
    from .parametrisation import Parametrisation

__all__ = [
    "FitProblem",
    "make_problem",
    "lengths_from_unit",
    "unit_from_lengths",
    "unit_frequencies",
    "static_tips",
]



# --- the length parametrisation -------------------------------------------------------------
def lengths_from_unit(u: np.ndarray, length_m: float,
                      min_fraction: float = MIN_FRACTION) -> np.ndarray:
    """Stick-breaking map from the box [0, 1]^n onto the bounded length simplex (m).

    ``L_j = a + e_j`` with ``a = min_fraction * L``; link j takes the fraction ``u_j`` of the
    excess length ``L - (n+1) a`` still unassigned, the last link takes the rest. Smooth, onto,
    and every boundary point of the simplex is reached at a finite u.
    """
    u = np.asarray(u, dtype=float).tolist()
    n1 = len(u) + 1
    a = min_fraction * length_m
    rest = length_m - n1 * a
    e = []
    for uj in u:  # Python floats: the same IEEE arithmetic as numpy's, without numpy scalars
        ej = min(max(uj, 0.0), 1.0) * rest  # u clipped to [0, 1]
        e.append(ej)
        rest -= ej
    e.append(max(rest, 0.0))
    return a + np.array(e)


def unit_from_lengths(lengths_m: np.ndarray, length_m: float, min_fraction: float = MIN_FRACTION):
    """Inverse of :func:`lengths_from_unit` (u_j = 0.5 where the remaining excess is zero)."""
    lengths = np.asarray(lengths_m, dtype=float)
    a = min_fraction * length_m
    e = np.maximum(lengths - a, 0.0)
    rest = length_m - lengths.size * a
    u = np.empty(lengths.size - 1)
    for j in range(u.size):
        u[j] = e[j] / rest if rest > 1e-15 * length_m else 0.5
        rest -= e[j]
    return np.clip(u, 0.0, 1.0)


# --- the problem --------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class FitProblem:
    """Everything fixed during a fit.

    Attributes
    ----------
    beam : Beam
    target : FitTarget
        Already cut to the N frequencies to match.
    n_joints : int
    options : FitOptions or ParetoOptions
        The validated options the problem was made from, carried whole: the pose sweep, the
        frequency form and the norms are read from them.
    parametrisation : Parametrisation
        The object of ``options.stiffness`` (``parametrisation.parametrisation``): how a
        design's factors become springs, and what the fit does with them.
    poses_rad : ndarray, shape (m, n)
        Joint angles of the poses where frequencies are compared.
    """

    beam: Beam
    target: FitTarget
    n_joints: int
    options: FitOptions | ParetoOptions
    parametrisation: Parametrisation
    poses_rad: np.ndarray

    @property
    def squared(self) -> bool:
        """Compare omega^2 instead of omega (``options.squared``)."""
        return self.options.squared

    @property
    def min_fraction(self) -> float:
        """A link length's lower bound over L, equation 15c (``options.min_fraction``)."""
        return self.options.min_fraction

    @property
    def eigen_norm(self) -> EigenNorm:
        """The per-pose eigen error's norm: ``options.eigen_norm`` (``eigen_weights``)."""
        return self.options.eigen_norm

    @property
    def deflection_norm(self) -> DeflectionNorm:
        """What a tip error is divided by: ``options.deflection_norm`` (``tip_scale_m``)."""
        return self.options.deflection_norm

    @property
    def n_freq(self) -> int:
        """Number of truth frequencies fitted, N."""
        return int(self.target.omega_truth_rad_s.size)

    @property
    def n_poses(self) -> int:
        """Number of poses where frequencies are compared, m."""
        return int(self.poses_rad.shape[0])

    @property
    def length_m(self) -> float:
        """Beam length L, m."""
        return self.beam.length_m

    @property
    def n_factors(self) -> int:
        """Number of stiffness factors: m SCFs (paper) or n joint factors (joint)."""
        return self.parametrisation.n_factors(self.n_poses, self.n_joints)


def make_problem(beam: Beam, target: FitTarget, joints: int,
                 options: FitOptions | ParetoOptions | None = None) -> FitProblem:
    """Check the settings that depend on the beam, the target and n; build a :class:`FitProblem`.

    Parameters
    ----------
    beam : Beam
        The planform, thickness, material and tip load.
    target : FitTarget
        Truth frequencies (rad/s) and load cases; cut to the N frequencies the fit matches.
    joints : int
        n, the number of revolute joints.
    options : FitOptions or ParetoOptions, optional
        The validated options (default ``FitOptions()``), held whole by the problem.
        ``frequencies`` None matches ``min(joints, available truth frequencies)``; the
        ``paper`` parametrisation compares frequencies over ``pose_sweep(joints, xi_rad,
        eps_rad)``, ``joint`` at the straight pose (over the sweep with ``joint_sweep``).

    Returns
    -------
    FitProblem

    Raises
    ------
    BeamInputError
        On a joint count, frequency count or minimum link fraction this beam and target cannot
        have, or an empty pose sweep.
    """
    if options is None:
        options = FitOptions()
    elif not isinstance(options, (FitOptions, ParetoOptions)):
        raise BeamInputError(f"options = {options!r:.80}: must be a FitOptions or ParetoOptions")
    if isinstance(joints, bool) or not isinstance(joints, (int, np.integer)) or joints < 1:
        raise BeamInputError(f"joints = {joints!r}: must be an integer >= 1")
    joints = int(joints)
    min_fraction = options.min_fraction
    if not (joints + 1) * min_fraction < 1.0:
        raise BeamInputError(
            f"min_fraction = {min_fraction}: needs 0 < min_fraction < 1/(joints+1)"
        )
    n_avail = target.omega_truth_rad_s.size
    frequencies = min(joints, n_avail) if options.frequencies is None else options.frequencies
    if not 1 <= frequencies <= joints:
        raise BeamInputError(
            f"frequencies = {frequencies}: must be in 1..{joints} (an {joints}R model has "
            f"{joints} frequencies)"
        )
    target = target.first(int(frequencies))
    # the parametrisations import the solvers, which import this module: looked up here
    from .parametrisation import parametrisation

    springs = parametrisation(options.stiffness)
    poses = springs.poses(joints, options)
    if poses.shape[0] == 0:
        raise BeamInputError(f"xi = {options.xi_rad}, eps = {options.eps_rad}: the pose sweep "
                             "is empty")
    return FitProblem(beam, target, joints, options, springs, read_only(poses))


def unit_frequencies(problem: FitProblem, lengths_m: np.ndarray):
    """Build the model at unit stiffness factor; compute its frequencies over the poses.

    Returns
    -------
    model : PrbdmModel
        Built with the unit-factor springs.
    K0 : ndarray, shape (n,)
        Unit-factor springs, N m/rad.
    omega : ndarray, shape (m, N)
        Frequencies at each pose with ``K0`` (rad/s); with factor k on every spring each one
        scales by sqrt(k) (the variable projection of the ``paper`` fit uses this).
    """
    model, K0 = problem.parametrisation.build(problem, lengths_m)
    omega = model.natural_frequencies_batch(problem.poses_rad, stiffness=K0)
    return model, K0, np.asarray(omega)[:, : problem.n_freq]


def static_tips(model, tip_force_N: np.ndarray, stiffness_rows: np.ndarray) -> np.ndarray:
    """Tip positions (m) under the load for each row of springs, stiffest first with warm starts."""
    rows = np.atleast_2d(stiffness_rows)
    order = np.argsort(-rows.sum(axis=1), kind="stable")
    tips = np.empty((rows.shape[0], 3))
    q0 = None
    for r in order:
        q, tip = model.with_stiffness(rows[r]).static_deflection(tip_force_N, q0=q0)
        tips[r] = tip
        q0 = q
    return tips
