"""What truth a fit was measured against: the arguments of one ``compute_truth`` call.

A fit records its request (in ``fit.json``) so that a later command (``prbdm simulate
--compare-truth``) asks for the very same truth and finds it in the cache.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields
from typing import Any

from ..errors import BeamInputError
from .compute import compute_truth


@dataclass(frozen=True)
class TruthRequest:
    """Arguments of :func:`prbdm_pin.truth.compute_truth` besides the beam and the cache.

    Attributes
    ----------
    model : str
        ``"plate"``, ``"plate-morley"``, ``"solid"`` or ``"beam"``.
    modes : int
        Number of bending modes selected.
    mesh_level : int or None
        Mesh level as asked (None: the model's default level).
    selection : str
        ``"paper"`` or ``"shape"``.
    large_deflection : str
        ``"calibrated-elastica"`` (default), ``"elastica"``, ``"solid"`` or ``"none"``.
    error_tol_pct : float or None
        Largest accepted error estimate of a selected frequency, % (None: any).
    """

    model: str = "plate"
    modes: int = 5
    mesh_level: int | None = None
    selection: str = "paper"
    large_deflection: str = "calibrated-elastica"
    error_tol_pct: float | None = 0.5

    def compute(self, beam, cache_dir=None, static: bool = True):
        """Compute the ``TruthResult`` of this request for ``beam`` (cached in ``cache_dir``)."""
        return compute_truth(beam, model=self.model, modes=self.modes,
                             mesh_level=self.mesh_level, selection=self.selection,
                             static=static, cache_dir=cache_dir,
                             large_deflection=self.large_deflection,
                             error_tol_pct=self.error_tol_pct)

    def to_dict(self) -> dict[str, Any]:
        """Return the JSON form (a flat mapping of the attributes)."""
        return asdict(self)

    @classmethod
    def from_dict(cls, d: Any) -> TruthRequest:
        """Read the JSON form; BeamInputError naming ``truth_request`` when it is not one."""
        names = {f.name for f in fields(cls)}
        if not isinstance(d, dict) or not set(d) <= names:
            raise BeamInputError(f"truth_request = {d!r}: must be a mapping with keys from "
                                 f"{sorted(names)}")
        for key in ("model", "selection", "large_deflection"):
            if key in d and not isinstance(d[key], str):
                raise BeamInputError(f"truth_request.{key} = {d[key]!r}: must be a string")
        for key in ("modes", "mesh_level"):
            v = d.get(key, 0)
            if v is not None and (isinstance(v, bool) or not isinstance(v, int)):
                raise BeamInputError(f"truth_request.{key} = {v!r}: must be an integer")
        v = d.get("error_tol_pct")
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float))):
            raise BeamInputError(f"truth_request.error_tol_pct = {v!r}: must be a number or null")
        return cls(**d)
