"""The result of a two-objective fit: the NSGA-II front and its knee (equation 27), with provenance.

A frozen dataclass in the conventions of :class:`prbdm_pin.fitting.results.FitResult` (``success``,
``message``); its JSON form drops the knee, which is written as its own fit.json. Losses in %.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from ..io.records import JsonRecord, readonly_array
from .results import ARRAY_FIELDS, FitResult, package_versions, result_readers

if TYPE_CHECKING:
    from ..options.objects import ParetoOptions

__all__ = ["ParetoResult"]


@dataclass(frozen=True, eq=False)
class ParetoResult(JsonRecord):
    """The whole NSGA-II front and its knee (equation 27).

    Attributes
    ----------
    F_pct : ndarray, shape (p, 2)
        (eigen loss %, deflection loss %) of each non-dominated design, sorted by eigen loss.
    X : ndarray, shape (p, n+1+f)
        Their design vectors [gamma, log10 factors].
    front_lengths_m : ndarray, shape (p, n+1)
    front_factors : ndarray, shape (p, f)
    knee_index : int
        Row of the knee in ``F_pct``.
    knee : FitResult or None
        The knee evaluated in full (not serialised here; written as its own fit.json).
    deflection_norm : str
        ``"position"`` (Eq. 19) or ``"displacement"``.
    eigen_norm : str
        ``"paper"`` (Eq. 16) or ``"relative"``: the norm of the front's eigen losses.
    pop, generations, n_evals, seed : int
    options : ParetoOptions or None
        Every option the front was computed with (None in a file written before they were
        recorded).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -100.0])
    >>> truth = pp.compute_truth(beam, model="beam", modes=2)
    >>> target = pp.target_from_truth(truth, beam.tip_force_N)
    >>> options = pp.ParetoOptions(pop=12, generations=3, stiffness="joint", seed_starts=1)
    >>> front = pp.fit_pareto(beam, target, 2, options, progress=False)
    >>> isinstance(front, pp.ParetoResult), front.joints, front.pop
    (True, 2, 12)
    """

    array_fields: ClassVar[frozenset[str]] = ARRAY_FIELDS

    @classmethod
    def nested_readers(cls) -> dict[str, Any]:
        """Return the readers of ``truth_request`` and ``options`` (as a fit's)."""
        return result_readers()

    beam_name: str
    joints: int
    frequencies: int
    stiffness: str
    deflection_norm: str
    F_pct: np.ndarray
    X: np.ndarray
    front_lengths_m: np.ndarray
    front_factors: np.ndarray
    knee_index: int
    pop: int
    generations: int
    n_evals: int
    seed: int
    xi: float
    eps: float
    wall_time_s: float
    success: bool
    message: str
    knee: FitResult | None = None
    eigen_norm: str = "paper"
    options: ParetoOptions | None = None
    versions: tuple = field(default_factory=package_versions)

    def __post_init__(self) -> None:
        """Freeze the arrays."""
        for name in self.array_fields & {f.name for f in fields(self)}:
            object.__setattr__(self, name, readonly_array(getattr(self, name)))

    def to_dict(self) -> dict[str, Any]:
        """Return a JSON-ready mapping without the knee (written as its own fit.json)."""
        d = super().to_dict()
        d.pop("knee", None)
        return d

    def to_csv(self) -> str:
        """Return the front as CSV: eigen %, deflection %, combined %, lengths (m), factors."""
        n1 = self.front_lengths_m.shape[1]
        nf = self.front_factors.shape[1]
        head = (["eigen_loss_pct", "deflection_loss_pct", "combined_loss_pct", "knee"]
                + [f"L{j}_m" for j in range(n1)] + [f"factor{j}" for j in range(nf)])
        lines = [",".join(head)]
        for r in range(self.F_pct.shape[0]):
            e, d = self.F_pct[r]
            row = [repr(float(e)), repr(float(d)), repr(float(math.hypot(e, d))),
                   str(int(r == self.knee_index))]
            row += [repr(float(v)) for v in self.front_lengths_m[r]]
            row += [repr(float(v)) for v in self.front_factors[r]]
            lines.append(",".join(row))
        return "\n".join(lines) + "\n"
