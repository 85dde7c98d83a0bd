"""What truth is asked for: every argument of ``compute_truth`` that defines its result.

:class:`TruthRequest` is the one place the truth's defaults are written and its arguments
checked: frozen and checked when built, so a request that exists is one ``compute_truth``
accepts. A fit records its request (``truth_request`` in ``fit.json``) so that a later command
(``prbdm simulate --compare-truth``) asks for the very same truth and finds it in the cache.

Light on purpose (numpy and the truth's settings only): the command line builds a request before
the finite-element code loads.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from ..errors import BeamInputError
from .settings import (
    DEFAULT_COMPUTED_MODES,
    DEFAULT_LARGE_DEFLECTION,
    ERROR_TOL_PCT,
    LARGE_DEFLECTION,
    MODELS,
    SELECTIONS,
    check_mesh_level,
)

__all__ = ["TruthRequest", "RECORDED_FIELDS", "request_of"]

# The fields every recorded request carries (``truth_request`` of fit.json, ``request`` of the
# comparison files), in this order; the later fields are written only when they differ from
# their defaults, so every file written before they existed, and every one written with their
# defaults, keeps its keys.
RECORDED_FIELDS = ("model", "modes", "mesh_level", "selection", "large_deflection",
                   "error_tol_pct")


def _integer(name: str, value: object, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise BeamInputError(f"{name} = {value!r}: must be an integer >= {minimum}")
    return int(value)


def _flag(name: str, value: object) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise BeamInputError(f"{name} = {value!r}: must be true or false")
    return bool(value)


@dataclass(frozen=True)
class TruthRequest:
    """The arguments of :func:`prbdm_pin.compute_truth` besides the beam and the cache.

    Built once, checked once (BeamInputError naming the field); every field has its default
    here and only here. ``compute_truth(beam, model="beam", modes=3)`` builds one from its
    keywords.

    Attributes
    ----------
    model : {"plate", "plate-morley", "solid", "beam"}
        ``plate`` (default): Kirchhoff plate, Argyris elements in element-local coordinates.
        ``plate-morley``: cheap cross-check from below. ``solid``: 3D elasticity. ``beam``: 1D
        Euler-Bernoulli (exact for slender strips only, 2-15 % off for wide panels).
    modes : int
        Number N >= 1 of bending modes to select (default 5).
    mesh_level : int or None
        Mesh refinement in [0, 6]; None (default): the model's own level, the cheapest meeting
        0.1 %.
    selection : {"paper", "shape"}
        ``paper`` (default): the N modes of largest z mass participation, ascending; ``shape``:
        the lowest N symmetric modes with MAC >= 0.8 against a 1D beam mode.
    large_deflection : {"calibrated-elastica", "elastica", "solid", "none"}
        Geometrically nonlinear tip solve. ``calibrated-elastica`` (default): the 1D elastica
        with EI(x) scaled by u_1D / u_model, the ratio of the 1D beam's and the truth model's
        linear tip deflections, so that at small load it is the model the frequencies come from
        (its distance to the nonlinear solid is measured by scripts/target_consistency.py).
        ``elastica``: the plain 1D elastica (exact for slender strips). ``solid``: the nonlinear
        3D solid (the reference, and by far the costliest). ``none``: the linear tip only.
    error_tol_pct : float or None
        Refuse (``CoarseTruthError``) a truth whose error estimate for a selected mode exceeds
        this, in % (default 0.5); None accepts any. The estimate (twice the change to the next
        mesh level, see ``truth.estimate``) is computed and cached either way.
    static : bool
        Also solve the tip-load case under ``beam.tip_force_N`` (default True).
    n_computed : int
        Modes computed before the selection (default 25; at least 2 N are computed), so that
        the selection is complete.
    check_convergence : bool
        Also solve one mesh level finer and raise TruthError if a selected frequency moves by
        more than ``convergence_rtol`` or increases (Argyris converges from above); default
        False.
    convergence_rtol : float
        The relative change of a selected frequency between two mesh levels that
        ``check_convergence`` accepts (default 1e-3, i.e. 0.1 %).
    spatial : bool
        The 1D beam truth also computes its Saint-Venant torsion and in-plane bending modes
        (``n_computed`` of each family beside the bending modes, labelled ``"torsion"`` and
        ``"in-plane"``); default False: bending modes only. The selected bending modes are the
        same either way. The plate and solid truths compute every kind they model whatever it
        says (the plate has no in-plane modes).

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> request = pp.TruthRequest(model="beam", modes=2)
    >>> request.model, request.modes, request.selection, request.error_tol_pct
    ('beam', 2, 'paper', 0.5)
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> truth = pp.compute_truth(beam, request)
    >>> truth.omega_rad_s.round(2)  # rad/s
    array([ 51.87, 325.05])
    >>> pp.TruthRequest(model="fluid")
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: model = 'fluid': must be one of ('plate', ...
    """

    model: str = "plate"
    modes: int = 5
    mesh_level: int | None = None
    selection: str = "paper"
    large_deflection: str = DEFAULT_LARGE_DEFLECTION
    error_tol_pct: float | None = ERROR_TOL_PCT
    static: bool = True
    n_computed: int = DEFAULT_COMPUTED_MODES
    check_convergence: bool = False
    convergence_rtol: float = 1e-3
    spatial: bool = False

    def __post_init__(self) -> None:
        """Check every field (BeamInputError naming it); numpy scalars become Python ones."""
        def put(name: str, value: object) -> None:
            object.__setattr__(self, name, value)

        for name, choices in (("model", MODELS), ("selection", SELECTIONS),
                              ("large_deflection", LARGE_DEFLECTION)):
            value = getattr(self, name)
            if not isinstance(value, str) or value not in choices:
                raise BeamInputError(f"{name} = {value!r}: must be one of {choices}")
        put("modes", _integer("modes", self.modes, 1))
        if self.mesh_level is not None:
            put("mesh_level", check_mesh_level(self.mesh_level))
        tol = self.error_tol_pct
        if tol is not None:
            if (isinstance(tol, bool) or not isinstance(tol, (int, float, np.floating))
                    or not tol > 0.0):
                raise BeamInputError(f"error_tol_pct = {tol!r}: must be a number > 0 (%) "
                                     "or None")
            if isinstance(tol, np.floating):  # JSON-ready; an int stays as given
                put("error_tol_pct", float(tol))
        put("static", _flag("static", self.static))
        put("n_computed", _integer("n_computed", self.n_computed, 1))
        put("check_convergence", _flag("check_convergence", self.check_convergence))
        put("spatial", _flag("spatial", self.spatial))
        r = self.convergence_rtol
        if (isinstance(r, bool) or not isinstance(r, (int, float, np.floating))
                or not 0.0 < r < 1.0):
            raise BeamInputError(f"convergence_rtol = {r!r}: must be a number in (0, 1)")
        put("convergence_rtol", float(r))

    @property
    def computed_modes(self) -> int:
        """Modes the modal analysis computes: ``n_computed``, and at least ``2 modes``."""
        return max(self.n_computed, 2 * self.modes)

    def compute(self, beam, cache_dir=None):
        """Compute the ``TruthResult`` of this request for ``beam`` (cached in ``cache_dir``).

        The same as ``compute_truth(beam, self, cache_dir=cache_dir)``.
        """
        from .compute import compute_truth

        return compute_truth(beam, self, cache_dir=cache_dir)

    def to_dict(self) -> dict[str, Any]:
        """Return the JSON form: a flat mapping of the fields.

        The ``RECORDED_FIELDS`` always, the others only where they differ from their defaults.
        """
        out = {name: getattr(self, name) for name in RECORDED_FIELDS}
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name not in out and value != f.default:
                out[f.name] = value
        return out

    @classmethod
    def from_dict(cls, d: Any) -> TruthRequest:
        """Read the JSON form; BeamInputError naming ``truth_request`` when it is not one.

        Missing fields take their defaults (older files carry only some of them).
        """
        names = [f.name for f in fields(cls)]
        if not isinstance(d, dict) or not set(d) <= set(names):
            raise BeamInputError(f"truth_request = {d!r}: must be a mapping with keys from "
                                 f"{sorted(names)}")
        try:
            return cls(**d)
        except BeamInputError as exc:  # "field = value: ..." -> "truth_request.field = ..."
            raise BeamInputError(f"truth_request.{exc}") from None


def request_of(request: TruthRequest | None, given: dict[str, Any],
               caller: str) -> TruthRequest:
    """Return the request a call asks for: ``request``, or one built from its keyword fields.

    ``given`` holds the keywords of the call beside the request (``model="beam", modes=3``);
    ``caller`` names the function in the errors. TypeError for a keyword that is no field or
    for a request given with fields; BeamInputError for a ``request`` that is no TruthRequest.
    """
    if request is None:
        unknown = sorted(set(given) - {f.name for f in fields(TruthRequest)})
        if unknown:
            raise TypeError(f"{caller}() got unexpected keyword arguments {unknown}; the "
                            f"truth's are the TruthRequest fields "
                            f"{[f.name for f in fields(TruthRequest)]}")
        return TruthRequest(**given)
    if not isinstance(request, TruthRequest):
        hint = f" (the model is a keyword: model={request!r})" if isinstance(request, str) else ""
        raise BeamInputError(f"request = {request!r:.80}: must be a TruthRequest, or give its "
                             f"fields as keywords{hint}")
    if given:
        raise TypeError(f"{caller}(): give a TruthRequest or its fields ({sorted(given)}), not "
                        "both; dataclasses.replace(request, ...) changes a request")
    return request
