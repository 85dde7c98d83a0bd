"""The modal solve of one truth model: every computed mode, classified, eigenvalues checked."""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError, TruthError
from ..member.geometry import Beam
from .result import ModalSolution
from .settings import DEFAULT_COMPUTED_MODES, DEFAULT_PLATE_LEVEL, MODELS, check_mesh_level

__all__ = ["compute_modal"]


def compute_modal(beam: Beam, model: str = "plate", mesh_level: int | None = None,
                  n_modes: int = DEFAULT_COMPUTED_MODES, spatial: bool = False) -> ModalSolution:
    """All computed modes of one model, classified (MPF_z, symmetry, beam MAC).

    Parameters
    ----------
    beam : Beam
    model : {"plate", "plate-morley", "solid", "beam"}
    mesh_level : int, optional
        Refinement level; default the cheapest level meeting 0.1 % for the model.
    n_modes : int
        Number of lowest modes computed (the 1D beam with ``spatial``: of each family).
    spatial : bool
        The 1D beam also solves its torsion and in-plane bending modes
        (:func:`~prbdm_pin.truth.beam_spatial.beam_spatial_modal`); the other models ignore it.

    Raises
    ------
    TruthError
        A negative, zero or non-finite eigenvalue.
    """
    if model not in MODELS:
        raise BeamInputError(f"model = {model!r}: must be one of {MODELS}")
    # the solvers load scikit-fem: imported here, so that a cached truth never pays for them
    if model in ("plate", "plate-morley"):
        from .plate import plate_modal

        level = DEFAULT_PLATE_LEVEL if mesh_level is None else check_mesh_level(mesh_level)
        element = "argyris" if model == "plate" else "morley"
        modal = plate_modal(beam, level, n_modes, element)
    elif model == "solid":
        from .solid import solid_modal

        level = None if mesh_level is None else check_mesh_level(mesh_level)
        modal = solid_modal(beam, level=level, n_modes=n_modes)
    elif spatial:
        from .beam_spatial import beam_spatial_modal

        modal = beam_spatial_modal(beam, n_modes=n_modes)
    else:
        from .beam import beam_modal

        modal = beam_modal(beam, n_modes=n_modes)
    w = np.asarray(modal.omega_rad_s)
    if not np.all(np.isfinite(w)) or np.any(w <= 0.0):
        bad = np.flatnonzero(~np.isfinite(w) | (w <= 0.0))
        raise TruthError(
            f"{modal.model} model of {beam.name!r} (level {modal.mesh_level}) has "
            f"{bad.size} non-positive or non-finite eigenvalue(s), first at mode {bad[0] + 1} "
            f"({w[bad[0]]:.6g} rad/s): the mesh or the solve cannot be trusted"
        )
    return modal
