"""The options of a simulation: the integrator, the sampling, the step cap and the damping.

Frozen, validated once, carried whole from the API or the command line into the trajectory and
any record of the run. Free of numpy, so the command line builds them before it loads the
numerics. Every error names the field and the value.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, fields
from typing import Any, ClassVar

from ..errors import BeamInputError
from .checks import check_float as _float
from .checks import check_int as _int
from .choices import DAMPING_FORMS, FIXED_STEP_METHODS, IVP_METHODS
from .integrators import INTEGRATOR_SPELLINGS, Integrator, integrator_for
from .validate import check_damping_ratio

__all__ = ["SimulationOptions"]


@dataclass(frozen=True)
class SimulationOptions:
    """How :func:`prbdm_pin.simulate` integrates and damps a run.

    What it integrates (the model, the initial state and the load) is passed beside them.

    The integrator is one object, ``integrator`` (``Auto``, the default, ``Exponential``,
    ``Gauss``, ``Trapezoidal``, ``ScipyIVP`` or ``Compiled``, from
    :mod:`prbdm_pin.options.integrators`). ``method``, ``dt_s``,
    ``rtol``, ``atol``, ``steps_per_period`` and ``refresh_rad`` are its other spelling: given
    without ``integrator`` they build it (each integrator reads the ones it has), given with it
    they must agree with it, and they always hold its values, so a record of the options
    (``to_dict``) keeps the keys it had before integrators were objects.

    Attributes
    ----------
    method : str
        ``"auto"`` (default: picked per problem by the rule of
        ``prbdm_pin.simulation.default_rule``), ``"exponential"``, ``"gauss"`` (symplectic;
        long undamped runs),
        ``"trapezoidal"``, ``"compiled"`` (DOP853 compiled with the chain's dynamics: ``rtol``,
        ``atol``), or a ``solve_ivp`` method (``rtol``, ``atol``).
    dt_s : float or None
        Step of the fixed-step schemes, s (default: the lowest natural period at the initial
        pose divided by ``steps_per_period``); for ``"exponential"`` the nominal, largest step.
    output_dt_s : float or None
        Sample interval of the trajectory, s (None: every step).
    rtol, atol : float
        ``solve_ivp`` and ``"compiled"`` tolerances (``atol`` None: rtol times a joint-angle
        scale).
    max_steps : int
        Refuse runs that would take more steps.
    steps_per_period : float or None
        Default-step rule: steps per lowest natural period (``"exponential"`` 10,
        ``"gauss"`` 40, ``"trapezoidal"`` 100).
    refresh_rad : float
        ``"exponential"``: rebuild the linearisation when a joint angle has moved by more than
        this since the last one, rad (0: every step).
    damping_ratio : float or tuple of float
        Modal ratios (``"modal"``, ``"modal_fit"``), per-joint factors (``"eq5c"``) or mode 1's
        ratio (``"stiffness"``), each in [0, 1) as ``prbdm simulate --damping`` (an over-damped
        ratio is refused); 0 disables damping.
    damping : str
        Damping form: ``"modal"``, ``"eq5c"``, ``"stiffness"`` or ``"modal_fit"`` (the diagonal
        joint damping fitted to the per-mode ratios; ``prbdm_pin.simulation.damping``).
    integrator : Integrator or None
        The integrator whole, with the fields no other option spells (its step control's
        tolerances and caps); None: built from ``method`` and the fields beside it.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> options = pp.SimulationOptions(damping_ratio=0.05)
    >>> options.method, options.damping_ratio
    ('auto', 0.05)
    """

    kind: ClassVar[str] = "simulation"

    method: str = "auto"
    dt_s: float | None = None
    output_dt_s: float | None = None
    rtol: float = 1e-9
    atol: float | None = None
    max_steps: int = 10_000_000
    steps_per_period: float | None = None
    refresh_rad: float = 0.01
    damping_ratio: float | tuple[float, ...] = 0.02
    damping: str = "modal"
    integrator: Integrator | None = None

    def __post_init__(self) -> None:
        """Validate every field; an error names the field and the value."""
        s = object.__setattr__
        if self.method not in FIXED_STEP_METHODS + IVP_METHODS:
            raise BeamInputError(f"method = {self.method!r}: must be one of "
                                 f"{FIXED_STEP_METHODS + IVP_METHODS}")
        s(self, "dt_s", _float("dt_s", self.dt_s, low=0.0, low_open=True, optional=True,
                               unit="s"))
        s(self, "output_dt_s", _float("output_dt_s", self.output_dt_s, low=0.0, low_open=True,
                                      optional=True, unit="s"))
        s(self, "rtol", _float("rtol", self.rtol, low=0.0, low_open=True))
        s(self, "atol", _float("atol", self.atol, low=0.0, low_open=True, optional=True))
        s(self, "max_steps", _int("max_steps", self.max_steps, 1))
        s(self, "steps_per_period", _float("steps_per_period", self.steps_per_period, low=1.0,
                                           optional=True))
        s(self, "refresh_rad", _float("refresh_rad", self.refresh_rad, low=0.0, unit="rad"))
        if self.damping not in DAMPING_FORMS:
            raise BeamInputError(f"damping = {self.damping!r}: must be one of "
                                 f"{', '.join(DAMPING_FORMS)}")
        r = self.damping_ratio
        if hasattr(r, "__len__") and not isinstance(r, (str, bytes, dict)):
            if len(r) == 0:
                raise BeamInputError("damping_ratio = (): give one ratio, or one per mode "
                                     "(joint)")
            s(self, "damping_ratio", tuple(check_damping_ratio(f"damping_ratio[{i}]", v)
                                           for i, v in enumerate(r)))
        else:
            s(self, "damping_ratio", check_damping_ratio("damping_ratio", r))
        integ = self.integrator
        if integ is None:
            s(self, "integrator", integrator_for(
                self.method, **{k: getattr(self, k) for k in INTEGRATOR_SPELLINGS[1:]}))
            return
        if not isinstance(integ, Integrator) or type(integ) is Integrator:
            raise BeamInputError(f"integrator = {integ!r:.80}: must be an Auto, Exponential, "
                                 "Gauss, Trapezoidal, ScipyIVP or Compiled")
        # the spelling follows the integrator; a field given apart from its default must agree
        defaults = {f.name: f.default for f in fields(self)}
        for name, value in integ.spellings().items():
            given = getattr(self, name)
            if given != defaults[name] and given != value:
                raise BeamInputError(f"{name} = {given!r}: differs from integrator = "
                                     f"{integ!r}; give one of them")
            s(self, name, value)

    def replace(self, **changes: Any) -> SimulationOptions:
        """Return a copy with ``changes`` applied and validated.

        A change of ``method``, ``dt_s``, ``rtol`` ... rebuilds the integrator from the
        spelling (the same class keeps its other fields); a new ``integrator`` resets the
        spelling to it. An unknown name is a BeamInputError.
        """
        names = {f.name for f in fields(self)}
        unknown = sorted(set(changes) - names)
        if unknown:
            raise BeamInputError(f"{unknown[0]} = {changes[unknown[0]]!r}: not an option of "
                                 f"SimulationOptions (options: {', '.join(sorted(names))})")
        if changes.get("integrator") is not None:
            # the spelling of the new integrator is its own: the old one's fields are dropped
            defaults = {f.name: f.default for f in fields(self)}
            reset = {k: defaults[k] for k in INTEGRATOR_SPELLINGS}
            return dataclasses.replace(self, **{**reset, **changes})
        if not any(k in changes for k in INTEGRATOR_SPELLINGS):
            return dataclasses.replace(self, **changes)
        # the spelling checked (errors name its fields) and the integrator built from it
        fresh = dataclasses.replace(self, **{**changes, "integrator": None})
        new, old = fresh.integrator, self.integrator
        if type(new) is type(old) and new.method == old.method:
            # the same scheme keeps the fields no option spells (its step control's caps)
            new = old.replace(**{k: v for k, v in new.spellings().items() if k != "method"})
        return dataclasses.replace(fresh, integrator=new)

    def to_dict(self) -> dict[str, Any]:
        """Return the JSON form: every option by name, with ``kind`` saying which these are.

        The integrator is written as its spelling (``method``, ``dt_s``, ...) plus the fields
        of it that differ from their defaults (``max_halvings``, ...).
        """
        d: dict[str, Any] = {"kind": self.kind}
        for f in fields(self):
            if f.name != "integrator":
                v = getattr(self, f.name)
                d[f.name] = list(v) if isinstance(v, tuple) else v
        d.update(self.integrator.extra())
        return d
