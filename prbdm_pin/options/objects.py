"""The options of a fit and of a Pareto fit (and, from ``simulation``, of a simulation).

Frozen, validated once, carried whole from the API or the command line into the result and its
JSON file, and read back from there.

Like ``scipy.optimize.minimize``'s ``options``, they hold what determines a result; how it is
computed (worker processes, a progress bar) is passed beside them. Free of numpy, so the command
line builds them before it loads the numerics. Every error names the field and the value.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, fields
from typing import Any, ClassVar

from ..errors import BeamInputError
from .checks import check_bool as _bool
from .checks import check_choice as _choice
from .checks import check_float as _float
from .checks import check_int as _int
from .choices import (
    EPS_RAD,
    MIN_FRACTION,
    PARETO_EPS_RAD,
    XI_RAD,
    Axes,
    Choice,
    DeflectionNorm,
    EigenNorm,
    Objective,
    StiffnessKind,
    UniqueRule,
)
from .simulation import SimulationOptions
from .spatial import check_planar_gains, check_spatial_fit, gain_points
from .validate import (
    MAX_GENERATIONS,
    MAX_NFEV,
    MAX_POP,
    MAX_SEED,
    MAX_STARTS,
    MAX_SWEEP_RAD,
    MIN_POP,
    check_axes,
)

__all__ = ["FitOptions", "ParetoOptions", "SimulationOptions", "options_from_dict",
           "UNIQUE_RULES"]

# ``FitOptions.unique``: "none" (a multistart's best) or "nearest" (fitting/unique.py)
UNIQUE_RULES = UniqueRule.values()


@dataclass(frozen=True)
class _ProblemOptions:
    """The options that define a fit problem.

    Shared by :class:`FitOptions` and :class:`ParetoOptions`.
    """

    kind: ClassVar[str] = ""

    frequencies: int | None = None
    stiffness: StiffnessKind = StiffnessKind.PAPER
    seed: int = 0
    xi_rad: float = XI_RAD
    eps_rad: float = EPS_RAD
    squared: bool = False
    deflection_norm: DeflectionNorm = DeflectionNorm.POSITION
    eigen_norm: EigenNorm = EigenNorm.RELATIVE
    min_fraction: float = MIN_FRACTION
    axes: Axes = Axes.Y

    def __post_init__(self) -> None:
        """Validate every field; an error names the field and the value."""
        s = object.__setattr__
        s(self, "axes", check_axes(self.axes))
        s(self, "frequencies", _int("frequencies", self.frequencies, 1, optional=True))
        s(self, "stiffness", _choice("stiffness", self.stiffness, StiffnessKind))
        s(self, "seed", _int("seed", self.seed, 0, high=MAX_SEED))
        s(self, "xi_rad", _float("xi_rad", self.xi_rad, low=0.0, high=MAX_SWEEP_RAD,
                                 unit="rad"))
        s(self, "eps_rad", _float("eps_rad", self.eps_rad, low=0.0, low_open=True,
                                  high=MAX_SWEEP_RAD, unit="rad"))
        s(self, "squared", _bool("squared", self.squared))
        s(self, "deflection_norm", _choice("deflection_norm", self.deflection_norm,
                                           DeflectionNorm))
        s(self, "eigen_norm", _choice("eigen_norm", self.eigen_norm, EigenNorm))
        f = _float("min_fraction", self.min_fraction, low=0.0, low_open=True)
        if f >= 0.5:
            raise BeamInputError(f"min_fraction = {f!r}: must be in (0, 1/(n+1)) for n joints")
        s(self, "min_fraction", f)

    def replace(self, **changes: Any):
        """Return a copy with ``changes`` applied and validated.

        An unknown name is a BeamInputError.
        """
        names = {f.name for f in fields(self)}
        unknown = sorted(set(changes) - names)
        if unknown:
            raise BeamInputError(f"{unknown[0]} = {changes[unknown[0]]!r}: not an option of "
                                 f"{type(self).__name__} (options: {', '.join(sorted(names))})")
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """Return the JSON form: every option by name, with ``kind`` saying which these are."""
        d: dict[str, Any] = {"kind": self.kind}
        for f in fields(self):
            v = getattr(self, f.name)
            d[f.name] = v.value if isinstance(v, Choice) else list(v) if isinstance(v, tuple) \
                else v
        return d

    @classmethod
    def from_dict(cls, d: Any, what: str = "options"):
        """Options from :meth:`to_dict`'s form, validated; BeamInputError names the field."""
        if not isinstance(d, dict):
            raise BeamInputError(f"{what} = {d!r:.60}: must be a mapping of options")
        d = dict(d)
        kind = d.pop("kind", cls.kind)
        if kind != cls.kind:
            raise BeamInputError(f"{what}: kind = {kind!r:.60}: must be {cls.kind!r}")
        try:
            return cls().replace(**{k: tuple(v) if isinstance(v, list) else v
                                    for k, v in d.items()})
        except BeamInputError as exc:
            raise BeamInputError(f"{what}: {exc}") from None


@dataclass(frozen=True)
class FitOptions(_ProblemOptions):
    """What determines a multistart fit (:func:`prbdm_pin.fit`).

    Attributes
    ----------
    frequencies : int or None
        N <= n truth frequencies to match (default min(n, available)).
    objective : Objective or str
        ``"eigen"`` (Eq. 17), ``"deflection"`` (Eq. 19) or ``"combined"`` (Eq. 27).
    stiffness : StiffnessKind or str
        ``"paper"``: one SCF per pose on Eq. 14; ``"joint"``: one factor per joint on the
        finite-segment stiffness.
    starts, seed : int
        Number of start points and the seed of their generator.
    xi_rad, eps_rad : float
        Pose sweep offset and step, rad (Eqs. 10-11).
    squared : bool
        Compare omega^2 instead of omega.
    deflection_norm : DeflectionNorm or str
        Tip errors divided by the truth tip position (``"position"``, Eq. 19) or by its
        displacement (``"displacement"``).
    eigen_norm : EigenNorm or str
        Per-pose eigen error: rms of the per-mode relative errors (``"relative"``, default) or
        Eq. 16's l2 norm (``"paper"``, dominated by the highest mode).
    min_fraction : float
        Lower bound of every link length as a fraction of L (Eq. 15c); < 1/(n+1).
    loss_tol_pct : float or None
        Stop at the first start (in start order) whose loss is at or below this, %.
    joint_sweep : bool
        ``joint`` only: compare frequencies over the pose sweep instead of the straight pose.
    polish : int
        ``paper`` eigen: polish up to this many distinct best starts on the paper's loss.
    max_nfev : int
        Evaluation cap of each least-squares start (residual evaluations; the analytic
        Jacobians apart).
    explore_nfev : int
        ``joint`` deflection and combined fits: residual evaluations every start runs before
        the best continue (``fitting/explore.py``).
    refine_starts : int
        ``joint`` deflection and combined fits: how many of the best explored starts continue
        to convergence; 0 runs every start to convergence.
    unique : UniqueRule or str
        ``"none"``: the best of the starts; ``"nearest"``: one model per design, smooth in it
        (``joint`` eigen fits of n frequencies; ``fitting/unique.py`` states the rule).
    start_lengths_m, start_factors : tuple of float or None
        A warm start (``fit(..., start=previous)``): the local solver runs from these link
        lengths (m) and stiffness factors only, instead of random starts.
    gain_points : tuple of str
        Points of the tip link (``tip``, ``tip_corner_left``, ``tip_corner_right``;
        ``--gain-points``) whose modal amplitudes the fit matches beside the frequencies
        (``fitting/spatial_gains.py``): how much each mode moves the points a controller sees.
        The planar chain takes ``tip`` alone with the ``joint`` springs
        (``fitting/planar_gains.py``). Default none.
    gain_weight : float
        The weight of those amplitude errors against the frequency errors (> 0, default 1).
    gain_modes : int or None
        How many of the lowest matched modes of each kind have their amplitudes matched
        (default None: every matched mode, each weighted by its share of the FRF,
        ``fitting/spatial_gains.py``).
    axes : Axes or str
        The joint axes at each node (``--axes``): ``"y"`` the planar chain; ``"xy"``,
        ``"yz"``, ``"xyz"`` a spatial chain (``fitting/spatial_fit.py``), fitted with the
        ``joint`` springs to the truth's modes of each kind (``frequencies`` of each kind,
        default n) with the ``eigen`` objective, to the tip in 3D and its twist under a tip
        load with ``deflection``, to both with ``combined`` (``fitting/spatial_deflection.py``).

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> options = pp.FitOptions(stiffness="joint", objective="eigen", starts=2)
    >>> str(options.stiffness), str(options.objective), options.starts
    ('joint', 'eigen', 2)
    >>> pp.FitOptions(starts=0)
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: starts = 0: must be an integer in 1..100000
    """

    kind: ClassVar[str] = "fit"

    objective: Objective = Objective.EIGEN
    starts: int = 64
    loss_tol_pct: float | None = None
    joint_sweep: bool = False
    polish: int = 4
    max_nfev: int = 400
    explore_nfev: int = 64
    refine_starts: int = 3
    unique: UniqueRule = UniqueRule.NONE
    start_lengths_m: tuple[float, ...] | None = None
    start_factors: tuple[float, ...] | None = None
    gain_points: tuple[str, ...] = ()
    gain_weight: float = 1.0
    gain_modes: int | None = None

    def __post_init__(self) -> None:
        """Validate every field; an error names the field and the value."""
        super().__post_init__()
        s = object.__setattr__
        s(self, "objective", _choice("objective", self.objective, Objective))
        s(self, "starts", _int("starts", self.starts, 1, high=MAX_STARTS))
        s(self, "loss_tol_pct", _float("loss_tol_pct", self.loss_tol_pct, low=0.0,
                                       optional=True, unit="%"))
        s(self, "joint_sweep", _bool("joint_sweep", self.joint_sweep))
        s(self, "polish", _int("polish", self.polish, 0, high=MAX_STARTS))
        s(self, "max_nfev", _int("max_nfev", self.max_nfev, 1, high=MAX_NFEV))
        s(self, "explore_nfev", _int("explore_nfev", self.explore_nfev, 1, high=MAX_NFEV))
        s(self, "refine_starts", _int("refine_starts", self.refine_starts, 0, high=MAX_STARTS))
        s(self, "unique", _choice("unique", self.unique, UniqueRule))
        for name in ("start_lengths_m", "start_factors"):
            v = getattr(self, name)
            if v is not None:
                if isinstance(v, (str, bytes)) or not hasattr(v, "__len__") or len(v) == 0:
                    raise BeamInputError(f"{name} = {v!r:.60}: must be a list of numbers > 0")
                s(self, name, tuple(_float(f"{name}[{i}]", e, low=0.0, low_open=True)
                                    for i, e in enumerate(v)))
        if (self.start_lengths_m is None) != (self.start_factors is None):
            raise BeamInputError("start_lengths_m, start_factors: give both (a warm start) or "
                                 "neither")
        if self.start_lengths_m is not None and self.unique is not UniqueRule.NONE:
            raise BeamInputError(f"unique = {self.unique.value!r}: the rule chooses the model "
                                 "itself; a warm start (start_lengths_m) needs unique = 'none'")
        s(self, "gain_points", gain_points(self.gain_points))
        s(self, "gain_weight", _float("gain_weight", self.gain_weight, low=0.0, low_open=True))
        s(self, "gain_modes", _int("gain_modes", self.gain_modes, 1, high=MAX_STARTS,
                                   optional=True))
        if self.axes.spatial:
            check_spatial_fit(self)
        else:
            check_planar_gains(self)


@dataclass(frozen=True)
class ParetoOptions(_ProblemOptions):
    """What determines an NSGA-II Pareto fit (:func:`prbdm_pin.fit_pareto`).

    Attributes
    ----------
    frequencies, stiffness, seed, xi_rad, squared, deflection_norm, eigen_norm, min_fraction
        As in :class:`FitOptions`.
    eps_rad : float
        Pose sweep step, rad; the paper's Pareto step 0.01 by default.
    pop, generations : int
        NSGA-II population and number of generations (the termination).
    log10_bounds : tuple of float or None
        Bounds of the log10 stiffness factors (default: joint factors in [-1, 1]; SCFs within
        1.5 decades of the projected eigen optimum at equal link lengths).
    seed_with_fits : bool
        Seed the initial population with the single-objective optima and designs between them.
    seed_starts : int
        Starts of each seeding fit.
    polish_knee : bool
        Polish the NSGA-II knee with the Eq. 27 local solver.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> options = pp.ParetoOptions(pop=20, generations=5)
    >>> options.pop, options.generations
    (20, 5)
    """

    kind: ClassVar[str] = "pareto"
    # not an option: a Pareto fit compares a ``joint`` model's frequencies at the straight pose
    joint_sweep: ClassVar[bool] = False

    eps_rad: float = PARETO_EPS_RAD
    pop: int = 100
    generations: int = 200
    log10_bounds: tuple[float, float] | None = None
    seed_with_fits: bool = True
    seed_starts: int = 4
    polish_knee: bool = True

    def __post_init__(self) -> None:
        """Validate every field; an error names the field and the value."""
        super().__post_init__()
        s = object.__setattr__
        s(self, "pop", _int("pop", self.pop, MIN_POP, high=MAX_POP))
        s(self, "generations", _int("generations", self.generations, 1, high=MAX_GENERATIONS))
        b = self.log10_bounds
        if b is not None:
            if isinstance(b, (str, bytes)) or not hasattr(b, "__len__") or len(b) != 2:
                raise BeamInputError(f"log10_bounds = {b!r}: must be (low, high) or None")
            lo = _float("log10_bounds[0]", b[0])
            hi = _float("log10_bounds[1]", b[1])
            if not lo < hi:
                raise BeamInputError(f"log10_bounds = {b!r}: needs low < high")
            s(self, "log10_bounds", (lo, hi))
        s(self, "seed_with_fits", _bool("seed_with_fits", self.seed_with_fits))
        s(self, "seed_starts", _int("seed_starts", self.seed_starts, 1, high=MAX_STARTS))
        s(self, "polish_knee", _bool("polish_knee", self.polish_knee))
        if self.axes.spatial and self.squared:
            raise BeamInputError(f"squared = True: not an option of a spatial fit (axes = "
                                 f"{self.axes.value!r}); leave it at its default")


def options_from_dict(d: Any, what: str = "options") -> FitOptions | ParetoOptions:
    """Read the options a result file recorded (``kind`` says which)."""
    kind = d.get("kind") if isinstance(d, dict) else None
    cls = ParetoOptions if kind == ParetoOptions.kind else FitOptions
    return cls.from_dict(d, what)
