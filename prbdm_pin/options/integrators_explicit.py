"""The error-controlled explicit integrators: scipy's solvers and the compiled DOP853.

Public through ``prbdm_pin.options.integrators`` (and ``prbdm_pin``), like the other
integrators.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ..errors import BeamInputError
from .checks import check_float as _float
from .choices import IVP_METHODS
from .integrator_base import RTOL_RANGE, Integrator

__all__ = ["ScipyIVP", "Compiled"]


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

