"""A single-objective fit's result with provenance.

Its JSON form is in :mod:`prbdm_pin.io.records`, the file in :mod:`prbdm_pin.files.fit_file`, and a
Pareto front's result in :mod:`prbdm_pin.fitting.pareto_result`.

:class:`FitResult` is a frozen dataclass following the conventions of
``scipy.optimize.OptimizeResult`` (``success``, ``message``, ``x``, ``fun``, ``nfev``); use
:meth:`FitResult.to_optimize_result` for a real ``OptimizeResult``. Losses are in %.
"""

from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, field, fields
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from ..io.provenance import package_versions
from ..io.records import JsonRecord, readonly_array
from ..options.checks import check_choice
from ..options.choices import MIN_FRACTION, Objective, StiffnessKind

if TYPE_CHECKING:
    from ..options.objects import FitOptions, ParetoOptions
    from ..truth.request import TruthRequest

__all__ = ["ARRAY_FIELDS", "FitResult", "package_versions"]

# fields read back from JSON as float arrays
ARRAY_FIELDS = frozenset({
    "lengths_m", "stiffness_Nm_per_rad", "stiffness_per_pose_Nm_per_rad", "factors",
    "scf_deviation_pct", "poses_rad", "omega_truth_rad_s", "omega_model_rad_s",
    "eigen_errors_pct", "tip_position_model_m", "tip_position_truth_m",
    "tip_displacement_truth_m", "tip_force_N", "mac", "start_losses_pct",
    "F_pct", "X", "front_lengths_m", "front_factors", "extra_tip_force_N",
    "extra_tip_position_truth_m", "extra_tip_position_model_m", "omega_errors_pct",
    "export_pose_rad", "omega_export_rad_s", "omega_export_errors_pct", "gravity_m_s2",
})
# what an old fit.json (one without ``stiffness_pose``) exported, by its ``stiffness``
_OLD_EXPORTS = {
    StiffnessKind.PAPER: ("paper: SCF_mean times Eq. 14 (a fit.json written before fits "
                          "recorded their export pose; no pose was fitted with these springs)"),
    StiffnessKind.JOINT: "joint: pose-independent springs",
}


def result_readers() -> dict[str, Any]:
    """Return the readers of the nested fields of a fit's and a Pareto front's JSON form.

    ``truth_request`` reads back as a :class:`~prbdm_pin.truth.request.TruthRequest` and
    ``options`` as the options object it was (:func:`~prbdm_pin.options.objects.options_from_dict`).
    """
    from ..options.objects import options_from_dict
    from ..truth.request import TruthRequest

    return {"truth_request": TruthRequest.from_dict,
            "options": lambda v: options_from_dict(v, "options")}


@dataclass(frozen=True, eq=False)
class FitResult(JsonRecord):
    """The best design of a single-objective fit, evaluated against its target.

    Attributes
    ----------
    beam_name, beam_fingerprint : str
    joints, frequencies : int
        n (joints) and N (frequencies matched).
    objective : str
        ``"eigen"``, ``"deflection"`` or ``"combined"``.
    stiffness : str
        ``"paper"`` (one SCF per pose, Eq. 14) or ``"joint"`` (one factor per joint).
    lengths_m : ndarray, shape (n+1,)
    stiffness_Nm_per_rad : ndarray, shape (n,)
        The exported springs (model.urdf and every export): the fitted springs (joint), or the
        springs fitted at one pose of the sweep, ``export_pose_rad`` (paper: pose 0, the one
        nearest straight). Never SCF_mean springs, which no pose was fitted with.
    stiffness_per_pose_Nm_per_rad : ndarray, shape (m, n)
        The springs of every pose of the sweep (:meth:`stiffness_schedule`).
    factors : ndarray
        SCFs k_i, shape (m,) (paper), or joint factors s_j, shape (n,) (joint).
    scf_mean : float
        Eq. 25 (paper; a diagnostic, not an exported spring set); mean joint factor (joint).
    scf_deviation_pct : ndarray, shape (m,)
        P_i of Eq. 26 (paper; zeros for joint).
    poses_rad : ndarray, shape (m, n)
    omega_truth_rad_s : ndarray, shape (N,)
    omega_model_rad_s : ndarray, shape (m, N)
    eigen_errors_pct : ndarray, shape (m,)
        Per-pose eigen error in the fit's ``eigen_norm`` (Eq. 16 for ``"paper"``), %.
    eigen_loss_pct, deflection_loss_pct, displacement_loss_pct, combined_loss_pct : float
        Eq. 17, Eq. 19 (normalised by the truth tip position), the same normalised by the truth
        tip displacement, Eq. 27 (eigen and position); NaN when no static truth. With extra
        load cases the tip errors are averaged over all cases.
    tip_position_model_m : ndarray, shape (m', 3) or None
    tip_position_truth_m, tip_displacement_truth_m, tip_force_N : ndarray, shape (3,)
    mac : ndarray, shape (N,) or None
        MAC of every mapped truth mode with a beam bending mode.
    truth_source : str
    truth_request : TruthRequest or None
        The ``compute_truth`` call the target came from (None for a truth file or a hand-made
        target): ``prbdm simulate --compare-truth`` asks for the same truth.
    min_fraction : float
        The fit's lower bound on every link, a fraction of L (Eq. 15; ``--min-link``).
    static_theory_gap_pct : float
        The gap between the truth model and 1D beam theory at small load, 100 (u_1D / u_truth
        - 1), % (the frequencies and the default large-deflection tip are both the truth
        model's; NaN when unknown).
    squared : bool
    xi, eps : float
    seed, starts, starts_run, nfev : int
    start_losses_pct : ndarray, shape (starts_run,)
        The local optimum's loss of every start run (in start order), %.
    wall_time_s : float
    success : bool
    message : str
    extra_tip_force_N, extra_tip_position_truth_m : ndarray, shape (k, 3), or None
        The target's extra load cases (N) and the truth tip under each (m).
    extra_tip_position_model_m : ndarray, shape (k, m', 3), or None
        The model's tip under each extra load case, per distinct stiffness, m.
    warnings : tuple of str
        What makes the model less than it looks: truth modes that are not beam-like, or n
        frequencies a ``joint`` fit should match and did not.
    eigen_norm : str
        ``"paper"`` (Eq. 16's l2 norm) or ``"relative"`` (rms of the per-mode relative errors):
        the norm of ``eigen_errors_pct`` and ``eigen_loss_pct``.
    omega_errors_pct : ndarray, shape (m, N)
        Signed per-mode errors 100 (omega_model / omega_truth - 1) at every fitted pose, %.
    worst_mode_error_pct : float
        ``max |omega_errors_pct|`` over the fitted poses and modes, %.
    export_pose_rad : ndarray, shape (n,), or None
        The pose whose springs are exported (paper: sweep pose 0; joint: the straight pose;
        None in a fit.json written before it was recorded).
    stiffness_pose : str
        What the exported springs are, in words.
    omega_export_rad_s, omega_export_errors_pct : ndarray, shape (N,), or None
        The exported model's own frequencies at the straight pose q = 0 (rad/s) and their signed
        errors against the truth (%).
    worst_export_error_pct : float
        ``max |omega_export_errors_pct|``, %.
    options : FitOptions or ParetoOptions or None
        Every option the fit was run with (a Pareto knee: the Pareto fit's); None in a
        fit.json written before options were recorded.
    axes : str
        The joint axes at each node (``"y"`` planar; ``"xy"``, ``"yz"``, ``"xyz"`` spatial).
        A spatial fit's springs, factors and poses run over every spring coordinate,
        node-major (``PrbdmModel.spring_axes``), and ``frequencies`` counts the matched truth
        modes of every kind.
    modes : tuple of dict
        One record per truth mode the fit matched, in ``omega_truth_rad_s``'s order, with the
        keys ``kind`` (the truth mode's label: ``bending``, ``torsion``, ``in-plane``, ...),
        ``omega_truth_rad_s``, ``omega_model_rad_s`` (the exported model's mode of that kind,
        rad/s) and ``error_pct`` (signed, %); a spatial fit adds the truth modes in its band
        that no chain mode represents (``chordwise``...), with null model frequency and error.
    gains : tuple of dict
        A fit with ``gain_points`` (spatial, or planar ``tip``): one record per matched mode and
        point, with the keys ``point``, ``kind``, ``omega_truth_rad_s``, ``truth_per_sqrt_kg`` and
        ``model_per_sqrt_kg`` (mass-normalised z amplitudes, 1/sqrt(kg)) and ``error_pct``
        (relative to the mode's largest truth amplitude over the points, %).
    versions : tuple of (name, version)
    gravity_m_s2 : ndarray (3,) or None
        The gravity the fit was made in, m/s^2, world (``prbdm fit --gravity``): the model's
        frequencies (``omega_model_rad_s``, ``omega_export_rad_s``) are about its own sag in
        it and its tips under the load plus it; None (no ``gravity_m_s2`` key in fit.json):
        a fit without gravity.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> EI = beam.material.E_Pa * 0.05 * 0.01**3 / 12  # N m^2
    >>> rho_A = beam.material.rho_kg_m3 * 0.05 * 0.01  # kg/m
    >>> w = np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)  # rad/s, L = 1 m
    >>> target = pp.FitTarget(omega_truth_rad_s=w, tip_force_N=[0.0, 0.0, -1.0])
    >>> result = pp.fit(beam, target, 2, objective="eigen", stiffness="joint", starts=1,
    ...                 progress=False)
    >>> isinstance(result, pp.FitResult), result.joints, result.objective
    (True, 2, 'eigen')
    >>> bool(result.worst_mode_error_pct < 1e-6)
    True
    """

    array_fields: ClassVar[frozenset[str]] = ARRAY_FIELDS

    @classmethod
    def nested_readers(cls) -> dict[str, Any]:
        """Return the readers of ``truth_request`` and ``options`` (see :func:`result_readers`)."""
        return result_readers()

    beam_name: str
    beam_fingerprint: str
    joints: int
    frequencies: int
    objective: str
    stiffness: str
    lengths_m: np.ndarray
    stiffness_Nm_per_rad: np.ndarray
    stiffness_per_pose_Nm_per_rad: np.ndarray
    factors: np.ndarray
    scf_mean: float
    scf_deviation_pct: np.ndarray
    poses_rad: np.ndarray
    omega_truth_rad_s: np.ndarray
    omega_model_rad_s: np.ndarray
    eigen_errors_pct: np.ndarray
    eigen_loss_pct: float
    deflection_loss_pct: float
    displacement_loss_pct: float
    combined_loss_pct: float
    tip_position_model_m: np.ndarray | None
    tip_position_truth_m: np.ndarray | None
    tip_displacement_truth_m: np.ndarray | None
    tip_force_N: np.ndarray
    mac: np.ndarray | None
    truth_source: str
    squared: bool
    xi: float
    eps: float
    seed: int
    starts: int
    starts_run: int
    nfev: int
    start_losses_pct: np.ndarray
    wall_time_s: float
    success: bool
    message: str
    extra_tip_force_N: np.ndarray | None = None
    extra_tip_position_truth_m: np.ndarray | None = None
    extra_tip_position_model_m: np.ndarray | None = None
    warnings: tuple = ()
    truth_request: TruthRequest | None = None
    eigen_norm: str = "paper"
    omega_errors_pct: np.ndarray | None = None
    worst_mode_error_pct: float = math.nan
    export_pose_rad: np.ndarray | None = None
    stiffness_pose: str = ""
    omega_export_rad_s: np.ndarray | None = None
    omega_export_errors_pct: np.ndarray | None = None
    worst_export_error_pct: float = math.nan
    static_theory_gap_pct: float = math.nan
    min_fraction: float = MIN_FRACTION
    options: FitOptions | ParetoOptions | None = None
    axes: str = "y"
    modes: tuple = ()
    gains: tuple = ()
    versions: tuple = field(default_factory=package_versions)
    gravity_m_s2: np.ndarray | None = None

    def to_dict(self) -> dict[str, Any]:
        """Return the JSON form; ``gravity_m_s2`` only for a fit made in gravity.

        A fit without gravity keeps the keys fit.json had before gravity was recorded.
        """
        d = super().to_dict()
        if d.get("gravity_m_s2") is None:
            d.pop("gravity_m_s2", None)
        return d

    def __post_init__(self) -> None:
        """Freeze the arrays; derive what an older fit.json did not record."""
        for name in self.array_fields & {f.name for f in fields(self)}:
            object.__setattr__(self, name, readonly_array(getattr(self, name)))
        # a fit.json written before the per-mode errors were recorded: derive them
        if self.omega_errors_pct is None and self.omega_model_rad_s is not None:
            from .objectives import mode_errors_pct

            object.__setattr__(self, "omega_errors_pct", readonly_array(mode_errors_pct(
                self.omega_model_rad_s, self.omega_truth_rad_s)))
        if not math.isfinite(self.worst_mode_error_pct) and self.omega_errors_pct is not None:
            object.__setattr__(self, "worst_mode_error_pct",
                               float(np.max(np.abs(self.omega_errors_pct))))
        if not self.stiffness_pose:
            object.__setattr__(self, "stiffness_pose", _OLD_EXPORTS[
                check_choice("stiffness", self.stiffness, StiffnessKind)])

    @classmethod
    def from_dict(cls, d: Any, beam=None, what: str = "fit.json") -> FitResult:
        """Rebuild from the JSON form, validated (:func:`prbdm_pin.io.record_checks.fit_kwargs`).

        With ``beam`` the link lengths must sum to its length (m). BeamInputError names the
        field.
        """
        from ..errors import BeamInputError
        from ..io.jsonfile import require_mapping
        from ..io.record_checks import fit_kwargs

        d = require_mapping(d, what)
        missing = [f.name for f in fields(cls) if f.name not in d
                   and f.default is MISSING and f.default_factory is MISSING]
        if missing:
            raise BeamInputError(f"{what}: missing field(s) {missing}: not a fit.json")
        fit_kwargs(d, what, None if beam is None else beam.length_m)
        return super().from_dict(d)

    def stiffness_schedule(self):
        """Return the per-pose springs as a ``simulation.StiffnessSchedule`` for ``simulate``.

        Row i of ``stiffness_per_pose_Nm_per_rad`` belongs to the sweep angle
        ``poses_rad[i, 0]`` (every joint at the same angle); a pose q is mapped to the mean
        ``|q_j|`` and the springs are interpolated linearly between the sweep poses, held at the
        first (last) pose's below (above) the sweep. At the straight pose it gives pose 0's
        springs, the exported ones.
        """
        from ..simulation import StiffnessSchedule

        return StiffnessSchedule(self.poses_rad[:, 0], self.stiffness_per_pose_Nm_per_rad)

    @property
    def loss_pct(self) -> float:
        """The loss of the fitted objective, %."""
        return {Objective.EIGEN: self.eigen_loss_pct,
                Objective.DEFLECTION: self.deflection_loss_pct,
                Objective.COMBINED: self.combined_loss_pct,
                }[check_choice("objective", self.objective, Objective)]

    @property
    def x(self) -> np.ndarray:
        """Design vector [gamma (n+1), factors], as the optimiser saw it."""
        return np.r_[self.lengths_m / np.sum(self.lengths_m), self.factors]

    @property
    def fun(self) -> float:
        """The loss of the fitted objective, %, under ``OptimizeResult``'s name."""
        return self.loss_pct

    def to_optimize_result(self):
        """Return a ``scipy.optimize.OptimizeResult`` view (x, fun, success, message, nfev, ...)."""
        from scipy.optimize import OptimizeResult

        return OptimizeResult(x=self.x, fun=self.fun, success=self.success,
                              message=self.message, nfev=self.nfev, result=self)
