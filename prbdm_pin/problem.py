"""The fit problems: what a fit matches (FitTarget), how a design vector becomes a model, and the
pymoo problem and repair used by the Pareto fit.

Two stiffness parametrisations:

- ``paper`` (Eq. 14): pose i uses the springs ``K_j(i) = k_i sqrt(E I_{j+1} / m_{j+1})``, one
  stiffness correction factor (SCF) k_i per pose; design vector [gamma, k] (Eq. 22). Frequencies
  are compared over the pose sweep of Eqs. 10-11.
- ``joint``: one pose-independent factor s_j per joint on the finite-segment physical stiffness
  (``stiffness.finite_segment_stiffness``), ``K_j = s_j E / integral(dx / I)``; design vector
  [gamma, s]; frequencies at the straight pose unless a sweep is asked for. One spring per joint,
  valid in every pose: the model a simulation exports as it is.

Link lengths live on the bounded simplex ``sum L_j = L, L_j >= f L`` (f = 0.02, Eq. 15); the
upper bound (1 - f) L of Eq. 15d is implied by the others. The single-objective local solvers
use the stick-breaking map :func:`lengths_from_unit` from the box [0, 1]^n onto that simplex, so
box-bounded solvers (least_squares, L-BFGS-B) handle the equality exactly; NSGA-II uses
:class:`LengthRepair` instead.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from .choices import STIFFNESS_KINDS
from .eigen import eig_scaled
from .errors import BeamInputError, SolveError
from .geometry import Beam
from .objectives import (
    check_eigen_norm,
    eigen_errors,
    tip_displacement_errors,
    tip_position_errors,
)
from .planar import planar_mass_matrices, planar_tips
from .sections import _planar_sections
from .statics import static_deflection_planar_batch
from .stiffness import _finite_segment

if TYPE_CHECKING:
    from .truth.request import TruthRequest

__all__ = [
    "LoadCase",
    "FitTarget",
    "target_from_truth",
    "model_target",
    "FitProblem",
    "make_problem",
    "Evaluation",
    "lengths_from_unit",
    "unit_from_lengths",
    "build",
    "unit_frequencies",
    "chain_mass_matrices",
    "fast_unit_frequencies",
    "chain_frequencies",
    "evaluate",
    "BatchLosses",
    "batch_losses",
    "LengthRepair",
    "ParetoProblem",
    "pareto_objectives",
    "pareto_objectives_batch",
]



def _ro(a, shape: tuple | None = None) -> np.ndarray:
    a = np.array(a, dtype=float)
    if shape is not None:
        a = a.reshape(shape)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class LoadCase:
    """A static load case of the truth: a dead tip force and the truth's tip under it.

    Attributes
    ----------
    tip_force_N : ndarray, shape (3,)
        Force at the tip, N (world).
    tip_position_m, tip_displacement_m : ndarray, shape (3,)
        Truth large-deflection tip position and displacement under it, m.
    """

    tip_force_N: np.ndarray
    tip_position_m: np.ndarray
    tip_displacement_m: np.ndarray

    def __post_init__(self) -> None:
        for name in ("tip_force_N", "tip_position_m", "tip_displacement_m"):
            v = np.asarray(getattr(self, name), dtype=float)
            if v.size != 3 or not np.all(np.isfinite(v)):
                raise BeamInputError(f"{name} = {v.tolist()}: must be 3 finite numbers")
            object.__setattr__(self, name, _ro(v, (3,)))
        if not np.linalg.norm(self.tip_displacement_m) > 0.0:
            raise BeamInputError("tip_displacement_m = 0: a load case needs a deflection")


@dataclass(frozen=True, eq=False)
class FitTarget:
    """What a fit needs from a truth.

    Attributes
    ----------
    omega_truth_rad_s : ndarray, shape (N,)
        Truth bending frequencies, ascending, rad/s.
    tip_force_N : ndarray, shape (3,)
        The static load case: a force at the tip, N.
    tip_position_m, tip_displacement_m : ndarray, shape (3,), or None
        Truth large-deflection tip position and displacement under ``tip_force_N``, m.
    mac : ndarray, shape (N,), or None
        MAC of each truth mode with a beam bending mode (recorded, not fitted).
    source : str
        Where the numbers come from (e.g. ``"plate, level 3, selection paper"``).
    labels : tuple of str, or None
        Each truth mode's shape label (``"bending"``, ``"chordwise"``, ``"mixed"``, ...).
    extra_loads : tuple of LoadCase
        Further load cases (e.g. a load sweep). The deflection objective averages the tip error
        of every case, each normalised by its own truth tip position or displacement; with none,
        it is the paper's single-load Eq. 19. n frequencies and one planar tip cannot fix the
        2n lengths and springs of a ``joint`` model for n >= 2; more load cases can.
    truth_request : TruthRequest or None
        The ``compute_truth`` call the numbers came from, when they came from one.
    static_theory_gap_pct : float or None
        100 (u_1D / u_truth - 1): the 1D beam's linear tip deflection against the truth model's
        under the same small load, in % (the gap between the two theories; None when unknown).
    """

    omega_truth_rad_s: np.ndarray
    tip_force_N: np.ndarray
    tip_position_m: np.ndarray | None = None
    tip_displacement_m: np.ndarray | None = None
    mac: np.ndarray | None = None
    source: str = ""
    extra_loads: tuple[LoadCase, ...] = ()
    labels: tuple[str, ...] | None = None
    truth_request: TruthRequest | None = None
    static_theory_gap_pct: float | None = None

    def __post_init__(self) -> None:
        w = np.asarray(self.omega_truth_rad_s, dtype=float).reshape(-1)
        if w.size == 0 or not np.all(np.isfinite(w)) or np.any(w <= 0):
            raise BeamInputError(f"omega_truth_rad_s = {w.tolist()}: must be finite and > 0")
        if np.any(np.diff(w) < 0):
            raise BeamInputError(f"omega_truth_rad_s = {w.tolist()}: must be ascending")
        object.__setattr__(self, "omega_truth_rad_s", _ro(w))
        object.__setattr__(self, "tip_force_N", _ro(self.tip_force_N, (3,)))
        for name in ("tip_position_m", "tip_displacement_m"):
            v = getattr(self, name)
            if v is not None:
                object.__setattr__(self, name, _ro(v, (3,)))
        if self.mac is not None:
            object.__setattr__(self, "mac", _ro(self.mac, (-1,)))
        extra = tuple(self.extra_loads)
        if extra and not self.has_static:
            raise BeamInputError("extra_loads: need the primary load case's truth tip position "
                                 "and displacement too")
        for i, c in enumerate(extra):
            if not isinstance(c, LoadCase):
                raise BeamInputError(f"extra_loads[{i}] = {c!r}: must be a LoadCase")
        object.__setattr__(self, "extra_loads", extra)
        if self.labels is not None:
            labels = tuple(str(v) for v in self.labels)
            if len(labels) != w.size:
                raise BeamInputError(f"labels has {len(labels)} entries: one per truth "
                                     f"frequency ({w.size}) needed")
            object.__setattr__(self, "labels", labels)

    @property
    def has_static(self) -> bool:
        """Whether a truth tip position (and displacement) is available."""
        return self.tip_position_m is not None and self.tip_displacement_m is not None

    @property
    def load_cases(self) -> tuple[LoadCase, ...]:
        """Every static load case, the primary one (``tip_force_N``) first; () without one."""
        if not self.has_static:
            return ()
        return (LoadCase(self.tip_force_N, self.tip_position_m, self.tip_displacement_m),
                *self.extra_loads)

    def first(self, n_freq: int) -> FitTarget:
        """The same target keeping only the first ``n_freq`` frequencies."""
        if not 1 <= n_freq <= self.omega_truth_rad_s.size:
            raise BeamInputError(
                f"frequencies = {n_freq}: must be in 1..{self.omega_truth_rad_s.size} "
                "(truth frequencies available)"
            )
        mac = None if self.mac is None else self.mac[:n_freq]
        labels = None if self.labels is None else self.labels[:n_freq]
        return replace(self, omega_truth_rad_s=self.omega_truth_rad_s[:n_freq], mac=mac,
                       labels=labels)

    def shape_notes(self) -> list[str]:
        """Why a chain may miss this target: truth modes that are not beam-like (labelled other
        than bending, or MAC < 0.8 with a beam bending mode), one line each."""
        out = []
        for k in range(self.omega_truth_rad_s.size):
            label = None if self.labels is None else self.labels[k]
            mac = None if self.mac is None else float(self.mac[k])
            if (label is not None and label != "bending") or (mac is not None and mac < 0.8):
                what = f"{label}, " if label is not None else ""
                out.append(f"truth mode {k + 1} ({self.omega_truth_rad_s[k]:.6g} rad/s; {what}"
                           f"MAC {mac:.2f} with a beam bending mode) is not beam-like: a chain "
                           "of rigid links has no mode of its shape")
        return out


def target_from_truth(truth, tip_force_N: np.ndarray,
                      request: TruthRequest | None = None) -> FitTarget:
    """A :class:`FitTarget` from a ``truth.TruthResult`` computed under ``tip_force_N`` (N), by
    ``request`` when given."""
    mac = getattr(truth, "mac_beam", None)
    src = f"{truth.model}, mesh level {truth.mesh_level}, selection {truth.selection}"
    labels = tuple(truth.labels[int(i)] for i in truth.mode_index)
    return FitTarget(
        omega_truth_rad_s=truth.omega_rad_s,
        tip_force_N=tip_force_N,
        tip_position_m=truth.tip_position_m,
        tip_displacement_m=truth.tip_displacement_m,
        mac=mac,
        source=src,
        labels=labels,
        truth_request=request,
        static_theory_gap_pct=getattr(truth, "static_theory_gap_pct", None),
    )


def model_target(model, tip_forces_N) -> FitTarget:
    """A PRBDM as its own truth: its frequencies (rad/s) and its large-deflection tip (m) under
    each force of ``tip_forces_N`` (k, 3), N; the first is the primary load case, the others
    ``extra_loads``. A fit to it should recover the model (identifiability checks)."""
    forces = np.asarray(tip_forces_N, dtype=float).reshape(-1, 3)
    rest = model.tip_position()
    cases = []
    for F in forces:
        tip = model.static_deflection(F)[1]
        cases.append(LoadCase(F, tip, tip - rest))
    first = cases[0]
    return FitTarget(model.natural_frequencies(), first.tip_force_N, first.tip_position_m,
                     first.tip_displacement_m, extra_loads=tuple(cases[1:]),
                     source=f"a {model.n_joints}R PRBDM")


# --- the length parametrisation -------------------------------------------------------------
def lengths_from_unit(u: np.ndarray, length_m: float, min_fraction: float = 0.02) -> np.ndarray:
    """Stick-breaking map from the box [0, 1]^n onto the bounded length simplex (m).

    ``L_j = a + e_j`` with ``a = min_fraction * L``; link j takes the fraction ``u_j`` of the
    excess length ``L - (n+1) a`` still unassigned, the last link takes the rest. Smooth, onto,
    and every boundary point of the simplex is reached at a finite u.
    """
    u = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
    n1 = u.size + 1
    a = min_fraction * length_m
    rest = length_m - n1 * a
    e = []
    for uj in u.tolist():  # Python floats: the same IEEE arithmetic, without numpy scalars
        ej = uj * rest
        e.append(ej)
        rest -= ej
    e.append(max(rest, 0.0))
    return a + np.array(e)


def unit_from_lengths(lengths_m: np.ndarray, length_m: float, min_fraction: float = 0.02):
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
    stiffness : str
        ``"paper"`` or ``"joint"``.
    poses_rad : ndarray, shape (m, n)
        Joint angles of the poses where frequencies are compared.
    squared : bool
        Compare omega^2 instead of omega.
    min_fraction : float
        Lower bound of a link length as a fraction of L (Eq. 15c).
    xi, eps : float
        The pose sweep's offset and step (Eqs. 10-11), rad (recorded for provenance).
    eigen_norm : str
        The per-pose eigen error: ``"paper"`` (Eq. 16) or ``"relative"`` (rms of the per-mode
        relative errors; ``objectives.eigen_weights``).
    """

    beam: Beam
    target: FitTarget
    n_joints: int
    stiffness: str
    poses_rad: np.ndarray
    squared: bool = False
    min_fraction: float = 0.02
    xi: float = 0.05
    eps: float = 0.1
    eigen_norm: str = "paper"

    @property
    def n_freq(self) -> int:
        return int(self.target.omega_truth_rad_s.size)

    @property
    def n_poses(self) -> int:
        return int(self.poses_rad.shape[0])

    @property
    def length_m(self) -> float:
        return self.beam.length_m

    @property
    def n_factors(self) -> int:
        """Number of stiffness factors: m SCFs (paper) or n joint factors (joint)."""
        return self.n_poses if self.stiffness == "paper" else self.n_joints


def make_problem(
    beam: Beam,
    target: FitTarget,
    joints: int,
    frequencies: int | None = None,
    stiffness: str = "paper",
    xi: float = 0.05,
    eps: float = 0.1,
    squared: bool = False,
    joint_sweep: bool = False,
    min_fraction: float = 0.02,
    eigen_norm: str = "paper",
) -> FitProblem:
    """Validate the fit settings and build a :class:`FitProblem`.

    ``frequencies`` defaults to ``min(joints, available truth frequencies)``; the ``paper``
    parametrisation compares frequencies over ``pose_sweep(joints, xi, eps)``, ``joint`` at the
    straight pose (over the sweep when ``joint_sweep``). ``eigen_norm`` is ``"paper"`` (Eq. 16)
    or ``"relative"``.
    """
    from .stiffness import pose_sweep

    if isinstance(joints, bool) or not isinstance(joints, (int, np.integer)) or joints < 1:
        raise BeamInputError(f"joints = {joints!r}: must be an integer >= 1")
    if stiffness not in STIFFNESS_KINDS:
        raise BeamInputError(f"stiffness = {stiffness!r}: must be one of {STIFFNESS_KINDS}")
    check_eigen_norm(eigen_norm)
    if not (0.0 < min_fraction and (joints + 1) * min_fraction < 1.0):
        raise BeamInputError(
            f"min_fraction = {min_fraction}: needs 0 < min_fraction < 1/(joints+1)"
        )
    n_avail = target.omega_truth_rad_s.size
    if frequencies is None:
        frequencies = min(int(joints), n_avail)
    if isinstance(frequencies, bool) or not isinstance(frequencies, (int, np.integer)):
        raise BeamInputError(f"frequencies = {frequencies!r}: must be an integer")
    if not 1 <= frequencies <= joints:
        raise BeamInputError(
            f"frequencies = {frequencies}: must be in 1..{joints} (an {joints}R model has "
            f"{joints} frequencies)"
        )
    target = target.first(int(frequencies))
    for name, v in (("xi", xi), ("eps", eps)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
            raise BeamInputError(f"{name} = {v!r}: must be a finite angle >= 0 (rad)")
    if stiffness == "paper" or joint_sweep:
        if eps <= 0:
            raise BeamInputError(f"eps = {eps}: must be > 0 rad for a pose sweep")
        poses = np.asarray(pose_sweep(int(joints), xi=xi, eps=eps), dtype=float)
        if poses.shape[0] == 0:
            raise BeamInputError(f"xi = {xi}, eps = {eps}: the pose sweep is empty")
    else:
        poses = np.zeros((1, int(joints)))
    return FitProblem(beam, target, int(joints), stiffness, _ro(poses), bool(squared),
                      float(min_fraction), float(xi), float(eps), eigen_norm)


# --- evaluation --------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Evaluation:
    """A design evaluated against the target.

    Attributes
    ----------
    lengths_m : ndarray, shape (n+1,)
    factors : ndarray
        The SCFs k_i, shape (m,) (paper), or the joint factors s_j, shape (n,) (joint).
    stiffness_Nm_per_rad : ndarray, shape (m, n)
        The springs of every pose (rows identical for ``joint``), N m/rad.
    omega_model_rad_s : ndarray, shape (m, N)
    eigen_errors : ndarray, shape (m,)
        Per-pose relative eigen error in the problem's norm (fraction).
    tip_position_m : ndarray, shape (m', 3), or None
        Model tip under the load for each distinct stiffness (m' = m for paper, 1 for joint).
    position_errors, displacement_errors : ndarray, shape (m',), or None
        Relative tip errors (fractions), normalised by the truth tip position / displacement,
        averaged over the target's load cases.
    extra_tip_position_m : ndarray, shape (k, m', 3), or None
        Model tips under the target's ``extra_loads``.
    """

    lengths_m: np.ndarray
    factors: np.ndarray
    stiffness_Nm_per_rad: np.ndarray
    omega_model_rad_s: np.ndarray
    eigen_errors: np.ndarray
    tip_position_m: np.ndarray | None = None
    position_errors: np.ndarray | None = None
    displacement_errors: np.ndarray | None = None
    extra_tip_position_m: np.ndarray | None = None

    @property
    def eigen_loss_pct(self) -> float:
        return float(100.0 * np.mean(self.eigen_errors))

    @property
    def deflection_loss_pct(self) -> float:
        return math.nan if self.position_errors is None else float(
            100.0 * np.mean(self.position_errors))

    @property
    def displacement_loss_pct(self) -> float:
        return math.nan if self.displacement_errors is None else float(
            100.0 * np.mean(self.displacement_errors))

    @property
    def combined_loss_pct(self) -> float:
        return float(math.hypot(self.eigen_loss_pct, self.deflection_loss_pct))


def base_stiffness(problem: FitProblem, model_or_lengths) -> np.ndarray:
    """Springs at unit factor, N m/rad: ``sqrt(E I/m)`` of Eq. 14 (paper) or finite-segment."""
    from .stiffness import finite_segment_stiffness, paper_stiffness

    if problem.stiffness == "paper":
        return np.asarray(paper_stiffness(model_or_lengths.sections,
                                          problem.beam.material.E_Pa, 1.0), dtype=float)
    return np.asarray(finite_segment_stiffness(problem.beam, model_or_lengths,
                                               problem.min_fraction), dtype=float)


def build(problem: FitProblem, lengths_m: np.ndarray):
    """The model with unit-factor springs and those springs ``K0`` (n,), N m/rad."""
    from .model import build_model

    lengths = np.asarray(lengths_m, dtype=float)
    f = problem.min_fraction  # the fit's own bound (below 0.02 for long chains)
    if problem.stiffness == "paper":
        model = build_model(problem.beam, lengths, np.ones(problem.n_joints), min_fraction=f)
        K0 = base_stiffness(problem, model)
        return model.with_stiffness(K0), K0
    K0 = base_stiffness(problem, lengths)
    return build_model(problem.beam, lengths, K0, min_fraction=f), K0


def unit_frequencies(problem: FitProblem, lengths_m: np.ndarray):
    """The model at unit stiffness factor and its frequencies over the problem's poses.

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
    model, K0 = build(problem, lengths_m)
    omega = model.natural_frequencies_batch(problem.poses_rad, stiffness=K0)
    return model, K0, np.asarray(omega)[:, : problem.n_freq]


def chain_mass_matrices(problem: FitProblem, lengths_m: np.ndarray):
    """Mass matrices over the problem's poses and the unit-factor springs, without Pinocchio.

    The fit's inner loop calls this instead of :func:`build`: the closed-form planar mass
    matrix (``dynamics.planar_mass_matrices``, checked against Pinocchio's CRBA in the tests)
    saves building a ``pinocchio.Model`` for each trial design. ``lengths_m`` must already be
    valid (as ``lengths_from_unit`` makes them); every reported result is re-evaluated with
    the Pinocchio model by :func:`evaluate`.

    Parameters
    ----------
    problem : FitProblem
    lengths_m : ndarray, shape (n+1,) or (B, n+1)
        One design, or a stack of designs (e.g. a finite-difference stencil), m.

    Returns
    -------
    M : ndarray, shape (m, n, n) or (B, m, n, n)
        Mass matrices at the poses, kg m^2.
    K0 : ndarray, shape (n,) or (B, n)
        Unit-factor springs, N m/rad (as :func:`base_stiffness`).
    """
    lengths = np.asarray(lengths_m, dtype=float)
    mass, offset, Iyy, area_moment = _planar_sections(problem.beam, lengths)
    if problem.stiffness == "paper":
        K0 = np.sqrt(problem.beam.material.E_Pa * area_moment[..., 1:] / mass[..., 1:])
    else:
        K0 = _finite_segment(problem.beam, lengths)
    M = planar_mass_matrices(lengths, mass, offset, Iyy, problem.poses_rad)
    return M, K0


def chain_frequencies(M: np.ndarray, K: np.ndarray) -> np.ndarray:
    """Frequencies (rad/s, ascending) from :func:`chain_mass_matrices`' M, shape (..., m, n, n),
    and springs K, shape (..., n) (N m/rad): shape (..., m, n)."""
    n = M.shape[-1]
    s = np.broadcast_to((1.0 / np.sqrt(K))[..., None, :], M.shape[:-1])
    return eig_scaled(M.reshape(-1, n, n), s.reshape(-1, n)).reshape(M.shape[:-1])


def fast_unit_frequencies(problem: FitProblem, lengths_m: np.ndarray):
    """Unit-factor springs ``K0`` and frequencies over the poses (rad/s), as
    :func:`unit_frequencies` but through :func:`chain_mass_matrices` (the fit's inner loop);
    shapes (n,), (m, N) for one design, (B, n), (B, m, N) for a stack."""
    M, K0 = chain_mass_matrices(problem, lengths_m)
    return K0, chain_frequencies(M, K0)[..., : problem.n_freq]


def pose_stiffness(problem: FitProblem, K0: np.ndarray, factors: np.ndarray) -> np.ndarray:
    """Springs of every pose, shape (m, n), N m/rad."""
    f = np.asarray(factors, dtype=float)
    if problem.stiffness == "paper":
        return f[:, None] * K0[None, :]
    return np.broadcast_to(f * K0, (problem.n_poses, problem.n_joints)).copy()


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


def evaluate(
    problem: FitProblem,
    lengths_m: np.ndarray,
    factors: np.ndarray,
    deflection: bool = True,
    unit: tuple | None = None,
) -> Evaluation:
    """Evaluate a design: frequencies over the poses and (when asked) the tip under the load.

    Parameters
    ----------
    problem : FitProblem
    lengths_m : ndarray, shape (n+1,)
    factors : ndarray
        SCFs k_i (m,) for ``paper``, joint factors s_j (n,) for ``joint``.
    deflection : bool
        Also solve the static deflection (needs a target with a tip position). For ``paper``
        one static solve per pose's stiffness (Eq. 18 averages over them).
    unit : tuple, optional
        A precomputed :func:`unit_frequencies` result for these lengths.

    Raises
    ------
    SolveError
        When a static solve does not converge.
    """
    lengths = np.asarray(lengths_m, dtype=float)
    factors = np.asarray(factors, dtype=float).reshape(-1)
    if factors.size != problem.n_factors:
        raise BeamInputError(f"factors has {factors.size} entries: {problem.n_factors} needed")
    if problem.stiffness == "paper":
        model, K0, W = unit if unit is not None else unit_frequencies(problem, lengths)
        omega = W * np.sqrt(factors)[:, None]
    else:
        # the joint factors change the spring ratios: a new eigen-solve per pose
        model, K0 = build(problem, lengths) if unit is None else unit[:2]
        omega = np.asarray(model.natural_frequencies_batch(
            problem.poses_rad, stiffness=factors * K0))[:, : problem.n_freq]
    err = eigen_errors(omega, problem.target.omega_truth_rad_s, problem.squared,
                       problem.eigen_norm)
    K = pose_stiffness(problem, K0, factors)
    tips = pos = disp = extra = None
    if deflection and problem.target.has_static:
        rows = K if problem.stiffness == "paper" else K[:1]
        cases = problem.target.load_cases
        all_tips = np.array([static_tips(model, c.tip_force_N, rows) for c in cases])
        pos = np.mean([tip_position_errors(t, c.tip_position_m)
                       for t, c in zip(all_tips, cases, strict=True)], axis=0)
        disp = np.mean([tip_displacement_errors(t, c.tip_position_m, c.tip_displacement_m)
                        for t, c in zip(all_tips, cases, strict=True)], axis=0)
        tips = all_tips[0]
        extra = all_tips[1:] if len(cases) > 1 else None
    return Evaluation(lengths, factors, K, omega, err, tips, pos, disp, extra)


@dataclass(frozen=True, eq=False)
class BatchLosses:
    """Per-pose errors of a stack of designs (rows), as fractions; NaN where a design cannot
    be solved.

    Attributes
    ----------
    eigen_errors : ndarray, shape (B, m)
        Relative eigen error of each pose (Eq. 16, or the relative norm: the problem's).
    position_errors, displacement_errors : ndarray, shape (B, m'), or None
        Tip error under the load case for each distinct stiffness (m' = m for ``paper``, 1 for
        ``joint``), normalised by the truth tip position (Eq. 19) and by the truth tip
        displacement; None when the statics were not solved.
    """

    eigen_errors: np.ndarray
    position_errors: np.ndarray | None = None
    displacement_errors: np.ndarray | None = None

    @property
    def eigen_pct(self) -> np.ndarray:
        """Eigen loss of each design (Eq. 17), %."""
        return 100.0 * self.eigen_errors.mean(axis=1)

    @property
    def position_pct(self) -> np.ndarray:
        """Deflection loss of each design (Eqs. 18-19), %."""
        return 100.0 * self.position_errors.mean(axis=1)

    @property
    def displacement_pct(self) -> np.ndarray:
        """Tip-displacement loss of each design, %."""
        return 100.0 * self.displacement_errors.mean(axis=1)


def batch_losses(problem: FitProblem, lengths_m: np.ndarray, factors: np.ndarray,
                 deflection: bool = True) -> BatchLosses:
    """The losses of :func:`evaluate` for many designs at once, without Pinocchio.

    The population of a Pareto generation or a finite-difference stencil is evaluated in one
    pass: closed-form mass matrices (:func:`chain_mass_matrices`), one stacked eigensolve, and
    every static solve (one per design and pose for ``paper``, one per design for ``joint``) in
    one vectorised Newton (``dynamics.static_deflection_planar_batch``). Tests check it against
    :func:`evaluate`, which uses the Pinocchio model.

    Parameters
    ----------
    problem : FitProblem
    lengths_m : ndarray, shape (B, n+1)
        Valid link lengths (on the bounded simplex), m.
    factors : ndarray, shape (B, m) (paper) or (B, n) (joint)
        Stiffness factors.
    deflection : bool
        Also solve the statics (needs a target with a tip position).
    """
    L = np.atleast_2d(np.asarray(lengths_m, dtype=float))
    f = np.atleast_2d(np.asarray(factors, dtype=float))
    B, m, n = L.shape[0], problem.n_poses, problem.n_joints
    static = deflection and problem.target.has_static
    reps = m if problem.stiffness == "paper" else 1
    try:
        M, K0 = chain_mass_matrices(problem, L)
        K = f[:, :, None] * K0[:, None, :] if problem.stiffness == "paper" \
            else np.broadcast_to((f * K0)[:, None, :], (B, m, n))
        omega = eig_scaled(M.reshape(-1, n, n), 1.0 / np.sqrt(K.reshape(-1, n)))
    except (SolveError, BeamInputError, np.linalg.LinAlgError):
        if B == 1:
            nan = np.full((1, reps), np.nan)
            return BatchLosses(np.full((1, m), np.nan), nan if static else None,
                               nan.copy() if static else None)
        parts = [batch_losses(problem, L[i:i + 1], f[i:i + 1], deflection) for i in range(B)]
        def cat(name: str) -> np.ndarray | None:
            if getattr(parts[0], name) is None:
                return None
            return np.concatenate([getattr(p, name) for p in parts])

        return BatchLosses(cat("eigen_errors"), cat("position_errors"),
                           cat("displacement_errors"))
    eig = eigen_errors(omega[:, : problem.n_freq], problem.target.omega_truth_rad_s,
                       problem.squared, problem.eigen_norm).reshape(B, m)
    if not static:
        return BatchLosses(eig)
    rows = K.reshape(B * m, n) if problem.stiffness == "paper" else K[:, 0]
    Lr = np.repeat(L, reps, axis=0)
    pos = np.zeros((B, reps))
    disp = np.zeros((B, reps))
    cases = problem.target.load_cases
    for c in cases:
        q, ok = static_deflection_planar_batch(Lr, rows, c.tip_force_N)
        tips = planar_tips(Lr, np.where(ok[:, None], q, 0.0))
        miss = np.linalg.norm(tips - c.tip_position_m, axis=1)
        miss[~ok] = np.nan
        miss = miss.reshape(B, reps)
        pos += miss / np.linalg.norm(c.tip_position_m)
        disp += miss / np.linalg.norm(c.tip_displacement_m)
    return BatchLosses(eig, pos / len(cases), disp / len(cases))


# --- pymoo ---------------------------------------------------------------------------------
def _pymoo():
    from pymoo.core.problem import Problem
    from pymoo.core.repair import Repair

    return Problem, Repair


def LengthRepair(n_links: int, min_fraction: float = 0.02):
    """A pymoo Repair projecting the first ``n_links`` variables (length fractions gamma) onto
    the bounded simplex (Euclidean projection, ``layout.repair_lengths``)."""
    _, Repair = _pymoo()
    from .layout import repair_lengths

    class _LengthRepair(Repair):
        def _do(self, problem, X, **kwargs):
            X = np.array(X, dtype=float, copy=True)
            X[:, :n_links] = repair_lengths(X[:, :n_links], 1.0, min_fraction=min_fraction)
            return X

    return _LengthRepair()


def ParetoProblem(problem: FitProblem, log10_bounds: tuple[float, float], penalty: float = 1e3,
                  deflection_norm: str = "position"):
    """A pymoo Problem over x = [gamma (n+1), log10 factors]: F = (eigen %, deflection %).

    ``deflection_norm`` selects Eq. 19 (``"position"``) or the displacement normalisation.
    Designs whose static solve fails get ``penalty`` in both objectives.
    """
    Problem, _ = _pymoo()
    if not problem.target.has_static:
        raise BeamInputError("target has no truth tip position: a Pareto fit needs one")
    n1 = problem.n_joints + 1
    nf = problem.n_factors
    lo = np.r_[np.full(n1, problem.min_fraction), np.full(nf, log10_bounds[0])]
    hi = np.r_[np.full(n1, 1.0 - problem.min_fraction), np.full(nf, log10_bounds[1])]

    class _ParetoProblem(Problem):
        def __init__(self):
            super().__init__(n_var=n1 + nf, n_obj=2, xl=lo, xu=hi)
            self.fit_problem = problem

        map_rows = None  # optional parallel map over the rows of X (set by fit_pareto)

        def _evaluate(self, X, out, *args, **kwargs):
            if self.map_rows is not None:
                out["F"] = np.asarray(self.map_rows(X), dtype=float).reshape(-1, 2)
                return
            out["F"] = pareto_objectives_batch(problem, X, penalty, deflection_norm)

    return _ParetoProblem()


def pareto_objectives(problem: FitProblem, lengths_m, factors, penalty: float = 1e3,
                      deflection_norm: str = "position") -> np.ndarray:
    """(eigen loss %, deflection loss %) of a design; ``penalty`` for both if a solve fails."""
    try:
        ev = evaluate(problem, lengths_m, factors, deflection=True)
    except (SolveError, BeamInputError):
        return np.array([penalty, penalty])
    d = ev.deflection_loss_pct if deflection_norm == "position" else ev.displacement_loss_pct
    if not (math.isfinite(ev.eigen_loss_pct) and math.isfinite(d)):
        return np.array([penalty, penalty])
    return np.array([ev.eigen_loss_pct, d])


def pareto_objectives_batch(problem: FitProblem, X: np.ndarray, penalty: float = 1e3,
                            deflection_norm: str = "position") -> np.ndarray:
    """(eigen loss %, deflection loss %) of the rows x = [gamma (n+1), log10 factors] of X, in
    one batch (:func:`batch_losses`); ``penalty`` for both where a design cannot be solved."""
    X = np.atleast_2d(np.asarray(X, dtype=float))
    n1 = problem.n_joints + 1
    r = batch_losses(problem, X[:, :n1] * problem.length_m, 10.0 ** X[:, n1:])
    d = r.position_pct if deflection_norm == "position" else r.displacement_pct
    F = np.column_stack([r.eigen_pct, d])
    F[~np.all(np.isfinite(F), axis=1)] = penalty
    return F
