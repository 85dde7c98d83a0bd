"""The integrators of a simulation as values: the scheme, its step and its tolerances.

``simulate(model, 1.0, integrator=Gauss(dt_s=1e-3))`` picks one; ``method="gauss"`` (with
``dt_s``, ``rtol`` ... beside it) is the older spelling of the same object, and
:class:`~prbdm_pin.options.simulation.SimulationOptions` carries it whole. Each is frozen and
validated at construction (a bad value is a BeamInputError naming the field) and free of numpy,
like the other options; the stepping itself is in ``prbdm_pin.simulation``, one stepper per
class, all driven by one loop (``prbdm_pin.simulation.loop``).

When to use which, and the accuracy of each, is in ``prbdm_pin.simulation``'s docstring and the
integrator modules' (``exponential``, ``gauss``, ``newmark``, ``ivp``).
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from dataclasses import dataclass, fields
from typing import Any, ClassVar

from ..errors import BeamInputError
from .checks import check_float as _float
from .checks import check_int as _int
from .choices import FIXED_STEP_METHODS, IVP_METHODS

__all__ = ["Integrator", "Exponential", "Gauss", "Trapezoidal", "ScipyIVP", "Compiled",
           "integrator_for", "INTEGRATOR_SPELLINGS"]

# The SimulationOptions fields that spell an integrator (``method="gauss", dt_s=1e-3``); each
# integrator reads the ones it has and ignores the others, as the options always did.
INTEGRATOR_SPELLINGS = ("method", "dt_s", "rtol", "atol", "steps_per_period", "refresh_rad")


@dataclass(frozen=True)
class Integrator:
    """What every integrator declares; use one of its subclasses.

    Class attributes
    ----------------
    method : str
        The name ``simulate(method=...)`` spells it by (``ScipyIVP``: a field).
    default_steps_per_period : float or None
        Default step rule of a scheme with a nominal step: the lowest natural period at the
        initial pose divided by this (None: the scheme has no nominal step).
    takes_inputs : bool
        Whether it integrates plant inputs (``simulate(inputs=...)``) besides a tip force.
    """

    method: ClassVar[str] = ""
    default_steps_per_period: ClassVar[float | None] = None
    takes_inputs: ClassVar[bool] = True
    # the INTEGRATOR_SPELLINGS this class has as fields (method apart)
    _spelled: ClassVar[tuple[str, ...]] = ()

    def spellings(self) -> dict[str, Any]:
        """Return the SimulationOptions fields that spell this integrator, by name."""
        return {"method": self.method, **{name: getattr(self, name) for name in self._spelled}}

    def extra(self) -> dict[str, Any]:
        """Return the fields no SimulationOptions field spells, where they differ from default.

        ``SimulationOptions.to_dict`` adds them, so a record keeps them and a default run writes
        the same keys as before integrators were objects.
        """
        return {f.name: getattr(self, f.name) for f in fields(self)
                if f.name not in INTEGRATOR_SPELLINGS and getattr(self, f.name) != f.default}

    def replace(self, **changes: Any) -> Integrator:
        """Return a copy with ``changes`` applied and validated (an unknown name is refused)."""
        names = {f.name for f in fields(self)}
        unknown = sorted(set(changes) - names)
        if unknown:
            raise BeamInputError(f"{unknown[0]} = {changes[unknown[0]]!r}: not a field of "
                                 f"{type(self).__name__} (fields: {', '.join(sorted(names))})")
        return dataclasses.replace(self, **changes)


def _step_fields(self) -> None:
    """Check ``dt_s`` and ``steps_per_period`` of a scheme with a nominal step."""
    s = object.__setattr__
    s(self, "dt_s", _float("dt_s", self.dt_s, low=0.0, low_open=True, optional=True, unit="s"))
    s(self, "steps_per_period", _float("steps_per_period", self.steps_per_period, low=1.0,
                                       optional=True))


@dataclass(frozen=True)
class Exponential(Integrator):
    """The exponential Rosenbrock method exprb32 with step-size control (the default).

    Attributes
    ----------
    dt_s : float or None
        Nominal, largest step, s (default: the lowest natural period at the initial pose over
        ``steps_per_period``).
    steps_per_period : float or None
        Default-step rule, >= 1 (None: 10).
    refresh_rad : float
        Rebuild the eigen-decomposition of the Jacobian when a joint angle has moved by more
        than this since the last one, rad (0: every step).
    step_rtol : float
        Step control: the correction's modal joint-angle amplitude is kept near this fraction
        of the motion's scale (the largest joint angle so far).
    reject_factor : float
        A step whose correction exceeds ``reject_factor`` times ``step_rtol`` of the scale is
        redone shorter; >= 1, ``inf`` never redoes one.
    max_halvings : int
        Divergence guard: a step whose correction exceeds ``divergence_tol`` of the scale (or
        is not finite) is halved, at most this many times in a row (then SolveError).
    divergence_tol : float
        The divergence guard's fraction of the larger of the motion's scale and the step's
        travel.
    min_step_ratio : float
        The step control never shortens a step below this fraction of the nominal step, in
        (0, 1].
    order : int
        3: exprb32 (two dynamics evaluations per step); 4: exprb43 (three), whose error falls
        faster as ``step_rtol`` tightens: the cheaper one at 0.01 % of the peak and below.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> run = pp.simulate(model, 0.05, q0=[0.01, 0.0], integrator=pp.Exponential(step_rtol=1e-4))
    >>> run.method, float(run.t_s[-1])
    ('exponential', 0.05)
    >>> ref = pp.simulate(model, 0.05, q0=[0.01, 0.0], method="DOP853", rtol=1e-11)
    >>> rb43 = pp.simulate(model, 0.05, q0=[0.01, 0.0], integrator=pp.Exponential(order=4))
    >>> bool(abs(rb43.tip_position_m[-1, 2] - ref.tip_position_m[-1, 2]) < 1e-9)  # m
    True
    """

    method: ClassVar[str] = "exponential"
    default_steps_per_period: ClassVar[float] = 10.0
    _spelled: ClassVar[tuple[str, ...]] = ("dt_s", "steps_per_period", "refresh_rad")

    dt_s: float | None = None
    steps_per_period: float | None = None
    refresh_rad: float = 0.01
    # 3e-4 keeps releases within 0.1 % of the peak over 1 s; rejecting only above 3x (the next
    # step shrinks anyway) saves the rejected steps' evaluations on step loads
    step_rtol: float = 3e-4
    reject_factor: float = 3.0
    max_halvings: int = 6
    divergence_tol: float = 0.05
    min_step_ratio: float = 1e-3
    order: int = 3

    def __post_init__(self) -> None:
        """Validate every field; an error names the field and the value."""
        s = object.__setattr__
        _step_fields(self)
        if isinstance(self.order, bool) or self.order not in (3, 4):
            raise BeamInputError(f"order = {self.order!r}: must be 3 (exprb32) or 4 (exprb43)")
        s(self, "order", int(self.order))
        s(self, "refresh_rad", _float("refresh_rad", self.refresh_rad, low=0.0, unit="rad"))
        s(self, "step_rtol", _float("step_rtol", self.step_rtol, low=0.0, low_open=True))
        r = self.reject_factor
        if isinstance(r, bool) or not isinstance(r, numbers.Real) or math.isnan(r) or r < 1.0:
            raise BeamInputError(f"reject_factor = {r!r}: must be a number >= 1 (inf: never "
                                 "redo a step)")
        s(self, "reject_factor", float(r))
        s(self, "max_halvings", _int("max_halvings", self.max_halvings, 0))
        s(self, "divergence_tol", _float("divergence_tol", self.divergence_tol, low=0.0,
                                         low_open=True))
        m = _float("min_step_ratio", self.min_step_ratio, low=0.0, low_open=True)
        if m > 1.0:
            raise BeamInputError(f"min_step_ratio = {m!r}: must be in (0, 1]")
        s(self, "min_step_ratio", m)


@dataclass(frozen=True)
class Gauss(Integrator):
    """2-stage Gauss-Legendre, fixed step, symplectic: long undamped runs at large amplitude.

    Attributes
    ----------
    dt_s : float or None
        Step, s (default: the lowest natural period at the initial pose over
        ``steps_per_period``).
    steps_per_period : float or None
        Default-step rule, >= 1 (None: 40).
    max_halvings : int
        A step whose Newton iteration fails is redone as two half steps, recursively, at most
        this many times over (then SolveError).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> run = pp.simulate(model, 0.05, q0=[0.01, 0.0], integrator=pp.Gauss(dt_s=1e-4),
    ...                   damping_ratio=0.0)
    >>> run.steps  # 0.05 s / 1e-4 s
    500
    >>> pp.Gauss(dt_s=-1.0)
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: dt_s = -1.0: must be a finite number > 0 (s)
    """

    method: ClassVar[str] = "gauss"
    default_steps_per_period: ClassVar[float] = 40.0
    takes_inputs: ClassVar[bool] = False
    _spelled: ClassVar[tuple[str, ...]] = ("dt_s", "steps_per_period")

    dt_s: float | None = None
    steps_per_period: float | None = None
    max_halvings: int = 3

    def __post_init__(self) -> None:
        """Validate every field; an error names the field and the value."""
        _step_fields(self)
        object.__setattr__(self, "max_halvings", _int("max_halvings", self.max_halvings, 0))


@dataclass(frozen=True)
class Trapezoidal(Integrator):
    """Newmark's average-acceleration (trapezoidal) rule, fixed step, second order.

    Attributes
    ----------
    dt_s : float or None
        Step, s, shortened to divide the output interval (default: the lowest natural period
        at the initial pose over ``steps_per_period``).
    steps_per_period : float or None
        Default-step rule, >= 1 (None: 100).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> run = pp.simulate(model, 0.05, q0=[0.01, 0.0], integrator=pp.Trapezoidal(dt_s=1e-4))
    >>> run.method
    'trapezoidal'
    """

    method: ClassVar[str] = "trapezoidal"
    default_steps_per_period: ClassVar[float] = 100.0
    _spelled: ClassVar[tuple[str, ...]] = ("dt_s", "steps_per_period")

    dt_s: float | None = None
    steps_per_period: float | None = None

    def __post_init__(self) -> None:
        """Validate every field; an error names the field and the value."""
        _step_fields(self)


@dataclass(frozen=True)
class ScipyIVP(Integrator):
    """A ``scipy.integrate`` solver (``RK45``, ``RK23``, ``DOP853``, ``Radau``, ``BDF``, ``LSODA``).

    Attributes
    ----------
    method : str
        The solver, as ``scipy.integrate.solve_ivp`` names it.
    rtol : float
        Relative tolerance.
    atol : float or None
        Absolute tolerance (None: ``rtol`` times the largest initial joint angle, at least
        1e-6 rad).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> method = pp.ScipyIVP("DOP853", rtol=1e-8)
    >>> pp.simulate(model, 0.05, q0=[0.01, 0.0], integrator=method).method
    'DOP853'
    >>> pp.ScipyIVP("Euler")
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: method = 'Euler': must be one of RK45, RK23, DOP853, ...
    """

    _spelled: ClassVar[tuple[str, ...]] = ("rtol", "atol")

    method: str = "DOP853"  # type: ignore[misc]  # a field here, a class attribute elsewhere
    rtol: float = 1e-9
    atol: float | None = None

    def __post_init__(self) -> None:
        """Validate every field; an error names the field and the value."""
        s = object.__setattr__
        if self.method not in IVP_METHODS:
            raise BeamInputError(f"method = {self.method!r}: must be one of "
                                 f"{', '.join(IVP_METHODS)}")
        s(self, "rtol", _float("rtol", self.rtol, low=0.0, low_open=True))
        s(self, "atol", _float("atol", self.atol, low=0.0, low_open=True, optional=True))


# the relative tolerances a tolerance-controlled scheme takes: below 1e-14 the error estimate is
# rounding (scipy raises anything under 100 EPS to that), above 0.1 it no longer estimates
RTOL_RANGE = (1e-14, 1e-1)


@dataclass(frozen=True)
class Compiled(Integrator):
    """scipy's DOP853 (Dormand-Prince 8(5,3)) compiled with the chain's dynamics (numba).

    The same coefficients, error norm, step control, initial step and 7th-order dense output as
    ``ScipyIVP("DOP853")`` (so the same steps and accuracy for the same ``rtol``/``atol``), with
    the whole run in one compiled call on the kernel (:mod:`prbdm_pin.kernel`): no Python per
    step. It serves constant springs, a frozen damping matrix, a constant tip force (a step
    load), gravity, releases and initial velocities (a spinning hub) on planar, spatial, hub and
    free-bus chains; a callable tip force, plant inputs, a stiffness schedule or a base motion
    is refused (``simulate`` names the option).

    Attributes
    ----------
    rtol : float
        Relative tolerance, in (1e-14, 0.1) (under 100 EPS it is raised to that, as scipy does).
    atol : float or None
        Absolute tolerance (None: ``rtol`` times the largest initial joint angle, at least
        1e-6 rad, as ``ScipyIVP``).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> run = pp.simulate(model, 0.05, q0=[0.01, 0.0], integrator=pp.Compiled(rtol=1e-8))
    >>> run.method, float(run.t_s[-1])
    ('compiled', 0.05)
    >>> pp.Compiled(rtol=0.5)
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: rtol = 0.5: must be in (1e-14, 0.1)
    """

    method: ClassVar[str] = "compiled"
    takes_inputs: ClassVar[bool] = False
    _spelled: ClassVar[tuple[str, ...]] = ("rtol", "atol")

    rtol: float = 1e-9
    atol: float | None = None

    def __post_init__(self) -> None:
        """Validate every field; an error names the field and the value."""
        s = object.__setattr__
        r = _float("rtol", self.rtol, low=0.0, low_open=True)
        if not RTOL_RANGE[0] < r < RTOL_RANGE[1]:
            raise BeamInputError(f"rtol = {r!r}: must be in ({RTOL_RANGE[0]:g}, "
                                 f"{RTOL_RANGE[1]:g})")
        s(self, "rtol", r)
        s(self, "atol", _float("atol", self.atol, low=0.0, low_open=True, optional=True))


_BY_NAME = {cls.method: cls for cls in (Exponential, Gauss, Trapezoidal, Compiled)}


def integrator_for(method: str, **spellings: Any) -> Integrator:
    """Return the integrator ``method`` names, built from the spellings it has.

    ``spellings`` are SimulationOptions fields (``dt_s``, ``rtol``, ...); those the integrator
    does not have are ignored (``rtol`` means nothing to ``"gauss"``).
    """
    if method in IVP_METHODS:
        cls, kw = ScipyIVP, {"method": method}
    elif method in FIXED_STEP_METHODS:
        cls, kw = _BY_NAME[method], {}
    else:
        raise BeamInputError(f"method = {method!r}: must be one of "
                             f"{FIXED_STEP_METHODS + IVP_METHODS}")
    kw.update((k, v) for k, v in spellings.items() if k in cls._spelled)
    return cls(**kw)
