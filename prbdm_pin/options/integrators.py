"""The integrators of a simulation as values: the scheme, its step and its tolerances.

``simulate(model, 1.0, integrator=Gauss(dt_s=1e-3))`` picks one; ``method="gauss"`` (with
``dt_s``, ``rtol`` ... beside it) is the older spelling of the same object, and
:class:`~prbdm_pin.options.simulation.SimulationOptions` carries it whole. Each is frozen and
validated at construction (a bad value is a BeamInputError naming the field) and free of numpy,
like the other options; the stepping itself is in ``prbdm_pin.simulation``, one stepper per
class, all driven by one loop (``prbdm_pin.simulation.loop``).

When to use which, and the accuracy of each, is in ``prbdm_pin.simulation``'s docstring and the
integrator modules' (``exponential``, ``gauss``, ``newmark``, ``ivp``, ``compiled``);
``Auto()``, the default, lets ``simulate`` pick one per problem by the rule of
``prbdm_pin.simulation.default_rule``.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import Any, ClassVar

from ..errors import BeamInputError
from .checks import check_float as _float
from .checks import check_int as _int
from .choices import FIXED_STEP_METHODS, IVP_METHODS
from .integrator_base import INTEGRATOR_SPELLINGS, RTOL_RANGE, Integrator
from .integrator_base import step_fields as _step_fields
from .integrators_explicit import Compiled, ScipyIVP

__all__ = ["Integrator", "Exponential", "Gauss", "Trapezoidal", "ScipyIVP", "Compiled", "Auto",
           "integrator_for", "INTEGRATOR_SPELLINGS"]


@dataclass(frozen=True)
class Exponential(Integrator):
    """The exponential Rosenbrock method exprb32 with step-size control (stiff chains from rest).

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
class Auto(Integrator):
    """The default: ``simulate`` picks the integrator per problem by a stated rule.

    After assembling the system ``simulate`` replaces it by what
    :func:`prbdm_pin.simulation.default_rule.default_integrator` picks for the scene's
    stiffness, damping, start and ``tolerance`` (``Compiled(rtol=tolerance / 100)`` or
    ``Exponential()``; ``Exponential()`` wherever the compiled kernel cannot serve the scene);
    the trajectory records the one used (``run.method``, ``run.integrator``).

    Attributes
    ----------
    tolerance : float
        The accuracy asked: the largest tip error as a fraction of the peak tip motion, in
        (1e-14, 0.1) (default 1e-4, 0.01 %).

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> run = pp.simulate(model, 0.05, q0=[0.01, 0.0], integrator=pp.Auto())
    >>> run.method, run.integrator
    ('compiled', Compiled(rtol=1e-06, atol=None))
    >>> pp.Auto(tolerance=0.5)
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: tolerance = 0.5: must be in (1e-14, 0.1)
    """

    method: ClassVar[str] = "auto"

    tolerance: float = 1e-4

    def __post_init__(self) -> None:
        """Validate ``tolerance``; an error names the field and the value."""
        r = _float("tolerance", self.tolerance, low=0.0, low_open=True)
        if not RTOL_RANGE[0] < r < RTOL_RANGE[1]:
            raise BeamInputError(f"tolerance = {r!r}: must be in ({RTOL_RANGE[0]:g}, "
                                 f"{RTOL_RANGE[1]:g})")
        object.__setattr__(self, "tolerance", r)


_BY_NAME = {cls.method: cls for cls in (Exponential, Gauss, Trapezoidal, Compiled, Auto)}


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
