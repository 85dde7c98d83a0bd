"""Mode shapes as VTU (ParaView) through meshio: nodal z displacement of every mode."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..io.atomic import atomic_path
from .result import ModalSolution

__all__ = ["write_modes_vtu"]


def write_modes_vtu(modal: ModalSolution, path, index=None) -> Path:
    """Write the mesh with point fields ``uz_mode_<k>`` (k 1-based, unit maximum), atomically.

    Argyris/Morley DOF vectors are not nodal fields: the nodal values of u are exported.
    """
    import meshio

    if modal.nodes_m is None or modal.node_uz is None or modal.cells is None:
        raise ValueError(f"{modal.model} modal solution carries no mesh to export")
    idx = range(modal.node_uz.shape[0]) if index is None else index
    data = {}
    for k in idx:
        u = np.asarray(modal.node_uz[k], dtype=float)
        data[f"uz_mode_{k + 1}"] = u / max(np.max(np.abs(u)), 1e-300)
    mesh = meshio.Mesh(np.asarray(modal.nodes_m, dtype=float),
                       [(modal.cell_type, np.asarray(modal.cells))], point_data=data)
    path = Path(path)
    with atomic_path(path) as tmp:
        meshio.write(tmp, mesh, file_format="vtu")
    return path
