"""Resource caps: the largest problem the package will start without being told to.

A cap turns a request that would exhaust memory or run for hours (a 1000-link chain, a
picosecond output step, a plate mesh with nanometre features) into a clear
:class:`~prbdm_pin.errors.BeamInputError` before any work starts. Every cap can be raised
explicitly, for one call (``limits().replace(...)`` passed where a function takes ``limits=``)
or for a whole run through its environment variable (read at each check, so workers started
by a batch inherit it).
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass

from ..errors import BeamInputError

__all__ = ["Limits", "limits", "check_cap", "ENV_VARS"]

# Field of Limits -> environment variable that overrides its default.
ENV_VARS = {
    "max_joints": "PRBDM_MAX_JOINTS",
    "max_vertices": "PRBDM_MAX_VERTICES",
    "max_output_samples": "PRBDM_MAX_SAMPLES",
    "max_mesh_dofs": "PRBDM_MAX_MESH_DOFS",
    "max_file_bytes": "PRBDM_MAX_FILE_BYTES",
    "max_estimate_dofs": "PRBDM_MAX_ESTIMATE_DOFS",
}


@dataclass(frozen=True)
class Limits:
    """Caps on problem size; each is an inclusive maximum.

    Attributes
    ----------
    max_joints : int
        Revolute joints n of a PRBDM (fit, model file, simulate, export).
    max_vertices : int
        Planform stations of a beam file.
    max_output_samples : int
        Time samples of one simulated response (``duration / output_dt + 1``).
    max_mesh_dofs : int
        Degrees of freedom of one finite-element truth mesh (plate, solid, 1D beam); a plate
        solve needs about 21 kB per DOF (``scripts/bench_mesh_dofs.py``), so the default
        keeps one truth near 10 GB.
    max_file_bytes : int
        Size of any JSON or URDF file the package reads.
    max_estimate_dofs : int
        Degrees of freedom of the next, finer plate mesh that a truth's error estimate may
        solve: refined once a plate mesh has about four times the DOFs and its factorisation
        grows faster than that (on jagged random panels the next level took minutes and more
        than 12 GB per process), so above this the estimate is skipped and the truth says so.
    """

    max_joints: int = 64
    max_vertices: int = 10_000
    max_output_samples: int = 2_000_000
    max_mesh_dofs: int = 500_000
    max_file_bytes: int = 64 * 2**20
    max_estimate_dofs: int = 120_000

    def __post_init__(self) -> None:
        """Check every cap is a positive integer; an error names the cap."""
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise BeamInputError(f"{f.name} = {v!r}: a cap must be a positive integer")

    def replace(self, **changes: int) -> Limits:
        """Return a copy with some caps changed."""
        return dataclasses.replace(self, **changes)


def limits() -> Limits:
    """Return the caps in force: the defaults, overridden by ``PRBDM_MAX_*`` variables."""
    changes = {}
    for field, var in ENV_VARS.items():
        text = os.environ.get(var)
        if text is None or text.strip() == "":
            continue
        try:
            value = int(text.strip())
        except ValueError:
            raise BeamInputError(f"{var} = {text!r}: must be a positive integer") from None
        if value < 1:
            raise BeamInputError(f"{var} = {text!r}: must be a positive integer")
        changes[field] = value
    return Limits(**changes)


def check_cap(what: str, value: int | float, cap: str, caps: Limits | None = None) -> None:
    """Raise :class:`BeamInputError` when ``value`` exceeds the cap named ``cap``.

    ``what`` names the field (``"joints"``, ``"--output-dt"`` ...) in the message, which also
    says how to raise the cap.
    """
    caps = limits() if caps is None else caps
    limit = getattr(caps, cap)
    if value > limit:
        raise BeamInputError(
            f"{what} = {value:.6g}: exceeds the cap {cap} = {limit} "
            f"(raise it with {ENV_VARS[cap]}=N if this is intended)"
        )
