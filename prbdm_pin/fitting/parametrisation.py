"""The spring parametrisations of a fit, as strategy objects.

A fit's parametrisation decides how a design [link lengths, stiffness factors] becomes the
springs of a model, over which poses its frequencies are compared, how it is solved from a
start and what the fitted model exports. Each one is an object with the interface of
:class:`Parametrisation` (as pymoo passes its operators), so the fit asks it instead of testing
a name:

- :class:`~prbdm_pin.fitting.paper_springs.PaperSprings` (``"paper"``, Eq. 14): one stiffness
  correction factor k_i per pose of the sweep, springs ``K_j(i) = k_i sqrt(E I_{j+1}/m_{j+1})``;
- :class:`~prbdm_pin.fitting.joint_springs.JointSprings` (``"joint"``): one pose-independent
  factor s_j per joint on the finite-segment springs, ``K_j = s_j E / integral(dx / I)``.

:func:`parametrisation` turns the ``stiffness`` option (a ``StiffnessKind``) into its object
where the options enter the fit (``problem.make_problem``); the object's ``name`` is what results
and files record. The objects hold no state: a problem pickles with its parametrisation to a
worker, where the copy is a new instance, so nothing tests an object's identity (two choices
compare as ``StiffnessKind`` members).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar, Protocol

import numpy as np

from ..options.checks import check_choice
from ..options.choices import StiffnessKind
from .joint_springs import JointSprings
from .paper_springs import PaperSprings

if TYPE_CHECKING:
    from ..member.geometry import Beam
    from .evaluate import Evaluation
    from .problem import FitProblem
    from .result import ExportedSprings
    from .spec import FitSpec, StartResult

__all__ = ["Parametrisation", "PaperSprings", "JointSprings", "PARAMETRISATIONS",
           "parametrisation"]


class Parametrisation(Protocol):
    """What a spring parametrisation answers; every method is pure (no state).

    Attributes
    ----------
    name : str
        ``"paper"`` or ``"joint"``: the ``stiffness`` of results and files.
    pose_independent : bool
        One spring set valid in every pose (``joint``): what the ``unique="nearest"`` rule,
        ``fit_derivative`` and a warm start from (lengths, springs) need.
    export_advice : str
        Appended to the note of an exported model that misses a truth mode ("" for none).
    """

    name: ClassVar[str]
    pose_independent: ClassVar[bool]
    export_advice: ClassVar[str]

    def poses(self, joints: int, options: Any) -> np.ndarray:
        """Return the poses where frequencies are compared, rad, shape (m, n).

        ``options`` (FitOptions or ParetoOptions) gives the sweep (``xi_rad``, ``eps_rad``,
        ``joint_sweep``).
        """

    def n_factors(self, n_poses: int, n_joints: int) -> int:
        """Return the number of stiffness factors of a design: m (per pose) or n (per joint)."""

    def chain_unit_springs(self, beam: Beam, lengths_m: np.ndarray, area_moment_m4: np.ndarray,
                           mass_kg: np.ndarray) -> np.ndarray:
        """Return the unit-factor springs of valid designs without checks, N m/rad, (..., n).

        The closed-form path (``evaluate.chain_mass_matrices``): ``lengths_m`` (..., n+1) in m,
        with the links' area moments (m^4) and masses (kg) of ``planar_sections``.
        """

    def build(self, problem: FitProblem, lengths_m: np.ndarray) -> tuple[Any, np.ndarray]:
        """Return the PrbdmModel of a design with unit-factor springs and those springs K0.

        ``lengths_m`` (n+1,) in m; K0 (n,) in N m/rad, checked: through the model's link
        sections (``paper``) or the finite-segment law (``joint``).
        """

    def frequencies(self, problem: FitProblem, model: Any, K0: np.ndarray,
                    factors: np.ndarray) -> np.ndarray:
        """Return a design's frequencies over the problem's poses, rad/s, shape (m, N).

        From its model with the unit springs K0 (N m/rad) and its factors (dimensionless).
        """

    def pose_springs(self, K0: np.ndarray, factors: np.ndarray, n_poses: int) -> np.ndarray:
        """Return the springs of every pose, N m/rad, shape (..., m, n), a new array.

        ``K0`` (..., n) unit springs (N m/rad) and ``factors`` (..., n_factors), for one design
        or a stack of designs.
        """

    def n_static_rows(self, n_poses: int) -> int:
        """Return how many distinct spring sets a design's statics solve: m or 1."""

    def static_rows(self, springs: np.ndarray) -> np.ndarray:
        """Return the spring rows the statics solve, N m/rad, shape (B n_static_rows, n).

        ``springs`` is :meth:`pose_springs`' (..., m, n); one design gives (n_static_rows, n)
        (or (n,) for a single row).
        """

    def export(self, problem: FitProblem, ev: Evaluation, K0: np.ndarray) -> ExportedSprings:
        """Return the springs (N m/rad) a fitted design exports, their pose and description."""

    def fit_notes(self, problem: FitProblem, objective: Any, eigen_loss_pct: float,
                  starts_run: int) -> list[str]:
        """Return the notes a result carries about what this fit should have reached."""

    def start_tasks(self, spec: FitSpec, tasks: list) -> list:
        """Return the multistart's start tasks (index, lengths m, factors) for this fit."""

    def explores(self, spec: FitSpec, options: Any, n_tasks: int) -> bool:
        """Whether the multistart explores every start and refines the best (``explore.py``)."""

    def polish(self, spec: FitSpec, runs: list[StartResult], order: list[int],
               options: Any) -> tuple[StartResult, list[StartResult]]:
        """Return the best start (polished where the parametrisation does) and the runs.

        ``order`` sorts ``runs`` by (loss, start index); the returned runs count the polish's
        evaluations.
        """

    def solve_start(self, spec: FitSpec, index: int, lengths0: np.ndarray,
                    factors0: np.ndarray) -> StartResult:
        """Run this parametrisation's local solver from one start (``local.solve_start``)."""

    def default_log10_bounds(self, problem: FitProblem) -> tuple[float, float]:
        """Return the Pareto fit's default bounds of the log10 factors (dimensionless)."""

    def start_factors(self, beam: Beam, lengths_m: np.ndarray, springs: np.ndarray | None,
                      factors: np.ndarray | None, min_fraction: float) -> np.ndarray:
        """Return a warm start's factors from a previous fit's springs or factors.

        ``springs`` (n,) in N m/rad, ``factors`` its factors (None for a (lengths, springs)
        pair), ``lengths_m`` (n+1,) in m on ``beam``.
        """


# one stateless instance each
PARAMETRISATIONS: dict[StiffnessKind, Parametrisation] = {
    StiffnessKind.PAPER: PaperSprings(),
    StiffnessKind.JOINT: JointSprings(),
}


def parametrisation(kind: StiffnessKind | str) -> Parametrisation:
    """Return the parametrisation object of a ``stiffness`` choice.

    Parameters
    ----------
    kind : StiffnessKind or str
        ``"paper"`` or ``"joint"`` (the ``stiffness`` option, or a result's record).

    Returns
    -------
    Parametrisation
        :class:`PaperSprings` or :class:`JointSprings`.

    Raises
    ------
    BeamInputError
        For any other value, naming it.
    """
    return PARAMETRISATIONS[check_choice("stiffness", kind, StiffnessKind)]
