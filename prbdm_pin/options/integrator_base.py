"""The base of the integrator values: what every integrator declares, and shared checks.

The integrators themselves are in ``integrators`` (the exponential and fixed-step schemes, the
rule-picked default) and ``integrators_explicit`` (the error-controlled explicit ones).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, fields
from typing import Any, ClassVar

from ..errors import BeamInputError
from .checks import check_float as _float

__all__ = ["Integrator", "INTEGRATOR_SPELLINGS", "RTOL_RANGE", "step_fields"]

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



def step_fields(self) -> None:
    """Check ``dt_s`` and ``steps_per_period`` of a scheme with a nominal step."""
    s = object.__setattr__
    s(self, "dt_s", _float("dt_s", self.dt_s, low=0.0, low_open=True, optional=True, unit="s"))
    s(self, "steps_per_period", _float("steps_per_period", self.steps_per_period, low=1.0,
                                       optional=True))



# the relative tolerances a tolerance-controlled scheme takes: below 1e-14 the error estimate is
# rounding (scipy raises anything under 100 EPS to that), above 0.1 it no longer estimates
RTOL_RANGE = (1e-14, 1e-1)
