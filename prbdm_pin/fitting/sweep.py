"""Fits along a path of designs (:func:`fit_sweep`).

Each step is warm-started from the one before, or, with ``unique="nearest"``, each is the rule's
model of its design (one model per design).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..member.geometry import Beam
from ..options.checks import shown
from ..options.choices import UniqueRule
from ..options.objects import FitOptions
from ..options.validate import check_type
from .multistart import fit, resolve_options
from .results import FitResult
from .target import FitTarget

__all__ = ["SweepResult", "fit_sweep", "check_path", "max_relative_step"]


@dataclass(frozen=True, eq=False)
class SweepResult:
    """The fits along a design path.

    Attributes
    ----------
    fits : tuple of FitResult
        Each step's fit.
    parameter : ndarray, shape (S,)
        The design parameter of each step (the step index when none was given).
    lengths_m : ndarray, shape (S, n+1)
        Each fit's link lengths, m.
    stiffness_Nm_per_rad : ndarray, shape (S, n)
        Each fit's exported joint springs, N m/rad.
    loss_pct : ndarray, shape (S,)
        Each fit's loss in its objective, %.
    wall_time_s : ndarray, shape (S,)
        Each fit's time (the truth excluded), s.
    warm : ndarray of bool, shape (S,)
        Whether the step was warm-started from the step before.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> def eb_target(b):  # Euler-Bernoulli frequencies of a uniform 1 m strip, rad/s
    ...     EI = b.material.E_Pa * 0.05 * b.thickness_m**3 / 12
    ...     rho_A = b.material.rho_kg_m3 * 0.05 * b.thickness_m
    ...     w = np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)
    ...     return pp.FitTarget(omega_truth_rad_s=w, tip_force_N=[0.0, 0.0, -1.0])
    >>> designs = [pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=t)
    ...            for t in (0.01, 0.011)]
    >>> sweep = pp.fit_sweep(designs, eb_target, 2, objective="eigen", stiffness="joint",
    ...                      unique="nearest", parameter=[0.01, 0.011], progress=False)
    >>> len(sweep.fits), sweep.lengths_m.shape, sweep.parameter
    (2, (2, 3), array([0.01 , 0.011]))
    """

    fits: tuple[FitResult, ...]
    parameter: np.ndarray
    lengths_m: np.ndarray
    stiffness_Nm_per_rad: np.ndarray
    loss_pct: np.ndarray
    wall_time_s: np.ndarray
    warm: np.ndarray

    def max_relative_step(self) -> np.ndarray:
        """Return each fitted parameter's largest relative step per relative design step.

        Per parameter (the n+1 lengths, then the n springs): the largest step-to-step change
        relative to the parameter's mean along the path, divided by the design's relative step:
        max_i (abs(dtheta_i) / mean abs(theta)) / (abs(dp_i) / mean abs(p)) (dimensionless),
        shape (2n+1,). A jump shows as a value far above the smooth map's elasticity.
        """
        return max_relative_step(np.hstack([self.lengths_m, self.stiffness_Nm_per_rad]),
                                 self.parameter)


def max_relative_step(theta: np.ndarray, parameter: np.ndarray) -> np.ndarray:
    """Return :meth:`SweepResult.max_relative_step` of ``theta`` (S, k) along ``parameter`` (S,).

    Parameters
    ----------
    theta : ndarray, shape (S, k)
        The fitted parameters of each step (any units; each column is scaled by its mean).
    parameter : ndarray, shape (S,)
        The design parameter of each step (its own unit).

    Returns
    -------
    ndarray, shape (k,)
        The largest relative step of each column per relative design step (dimensionless).
    """
    theta = np.asarray(theta, dtype=float)
    p = np.asarray(parameter, dtype=float)
    rel = np.abs(np.diff(theta, axis=0)) / np.mean(np.abs(theta), axis=0)
    dp = np.abs(np.diff(p)) / max(float(np.mean(np.abs(p))), 1e-300)
    return np.max(rel / dp[:, None], axis=0)


def check_path(designs: Sequence[Beam]) -> None:
    """Refuse a path that cannot be continuous.

    That is fewer than two designs, or planforms whose vertex count or width steps change (a
    vertex appearing is a jump, not a step).

    Parameters
    ----------
    designs : sequence of Beam
        The path.

    Raises
    ------
    BeamInputError
        Naming the first design that breaks the path.
    """
    if isinstance(designs, (str, bytes, dict, Beam)) or not isinstance(designs, Sequence):
        raise InputTypeError(f"designs = {shown(designs)}: must be a sequence of prbdm_pin.Beam")
    for i, b in enumerate(designs):
        check_type(f"designs[{i}]", b, Beam)
    if len(designs) < 2:
        raise BeamInputError(f"designs: {len(designs)} given: a sweep needs at least 2")
    first = designs[0]
    for i, b in enumerate(designs):
        if b.x_m.size != first.x_m.size:
            raise BeamInputError(f"designs[{i}]: {b.x_m.size} planform vertices, designs[0] "
                                 f"has {first.x_m.size}: a continuous path keeps the planform's "
                                 "vertices (move them instead)")
        if not np.array_equal(b.step_index, first.step_index):
            raise BeamInputError(f"designs[{i}]: width steps at vertices "
                                 f"{b.step_index.tolist()}, designs[0] at "
                                 f"{first.step_index.tolist()}: a continuous path keeps them")


def fit_sweep(
    designs: Sequence[Beam],
    targets: Sequence[FitTarget] | Callable[[Beam], FitTarget],
    joints: int,
    options: FitOptions | None = None,
    *,
    parameter: Sequence[float] | None = None,
    start: Any = None,
    progress: bool = True,
    **changes: Any,
) -> SweepResult:
    """Fit an nR PRBDM to every design of a path.

    Parameters
    ----------
    designs : sequence of Beam
        The path (e.g. a parameter sweep), same planform topology throughout.
    targets : sequence of FitTarget, or callable Beam -> FitTarget
        The truth of each design, or a function computing it.
    joints : int
        n, the number of revolute joints.
    options : FitOptions, optional
        The first step runs as these say (a multistart, or from ``start``); each later step
        is warm-started from the one before. With ``unique="nearest"`` every step is the
        rule's model of its design instead (no warm start: the rule does not depend on the
        path).
    parameter : sequence of float, optional
        The design parameter of each step, recorded in the result (m, or its unit).
    start : FitResult or (lengths m, springs N m/rad), optional
        Warm start of the first step.
    progress : bool
        Show a tqdm bar over the steps.
    **changes
        Options by name, as for :func:`prbdm_pin.fit`.

    Returns
    -------
    SweepResult
        Each step's fit, link lengths (m), springs (N m/rad), loss (%) and time (s).

    Raises
    ------
    BeamInputError
        On a path that cannot be continuous, or parameters or targets that do not match it.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> def eb_target(b):  # Euler-Bernoulli frequencies of a uniform 1 m strip, rad/s
    ...     EI = b.material.E_Pa * 0.05 * b.thickness_m**3 / 12
    ...     rho_A = b.material.rho_kg_m3 * 0.05 * b.thickness_m
    ...     w = np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)
    ...     return pp.FitTarget(omega_truth_rad_s=w, tip_force_N=[0.0, 0.0, -1.0])
    >>> designs = [pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=t)
    ...            for t in (0.01, 0.011)]
    >>> sweep = pp.fit_sweep(designs, eb_target, 2, objective="eigen", stiffness="joint",
    ...                      unique="nearest", progress=False)
    >>> (sweep.stiffness_Nm_per_rad[1] / sweep.stiffness_Nm_per_rad[0]).round(3)  # k ~ t^3
    array([1.331, 1.331])
    >>> round(1.1**3, 3)
    1.331
    """
    from ..io.progress import progress_bar

    check_path(designs)
    o = resolve_options(options, FitOptions, changes)
    S = len(designs)
    p = np.arange(S, dtype=float) if parameter is None else np.asarray(parameter, dtype=float)
    if p.shape != (S,) or not np.all(np.isfinite(p)):
        raise BeamInputError(f"parameter: {np.size(p)} values: one finite value per design "
                             f"({S}) needed")
    if not callable(targets) and len(targets) != S:
        raise BeamInputError(f"targets: {len(targets)} given for {S} designs")
    fits: list[FitResult] = []
    times, warm = np.zeros(S), np.zeros(S, dtype=bool)
    prev = start
    for i in progress_bar(iterable=range(S), enabled=progress, desc="sweep", unit="design"):
        beam = designs[i]
        target = targets(beam) if callable(targets) else targets[i]
        t0 = time.perf_counter()
        use = None if o.unique is not UniqueRule.NONE else prev
        r = fit(beam, target, joints, o, progress=False, start=use)
        times[i] = time.perf_counter() - t0
        warm[i] = use is not None
        fits.append(r)
        prev = r
    return SweepResult(
        fits=tuple(fits), parameter=p, lengths_m=np.array([f.lengths_m for f in fits]),
        stiffness_Nm_per_rad=np.array([f.stiffness_Nm_per_rad for f in fits]),
        loss_pct=np.array([f.loss_pct for f in fits]), wall_time_s=times, warm=warm)
