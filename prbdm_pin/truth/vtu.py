"""Mode shapes as VTU (ParaView) through meshio: the nodal displacement of every mode.

Each mode k writes ``uz_mode_<k>`` (the z displacement, unit maximum) and, for the plate and the
1D beam, whose z displacement is their whole displacement (Kirchhoff's mid-surface and
Euler-Bernoulli's axis do not stretch), ``displacement_mode_<k>``: the vector (0, 0, uz), which
ParaView's Warp By Vector draws. The solid writes its whole nodal displacement (x, y, z) as that
vector, at the scale of ``uz_mode_<k>``: torsion and in-plane modes move its nodes sideways too.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..io.atomic import atomic_path
from .result import ModalSolution

__all__ = ["write_modes_vtu"]


def write_modes_vtu(modal: ModalSolution, path, index=None) -> Path:
    """Write the mesh with point fields ``uz_mode_<k>`` (k 1-based, unit maximum), atomically.

    Argyris/Morley DOF vectors are not nodal fields: the nodal values of u are exported. Every
    model adds ``displacement_mode_<k>``: (0, 0, uz) for the plate and the 1D beam, the whole
    nodal displacement for the solid (the module's note), at the scale of ``uz_mode_<k>``.
    """
    import meshio

    if modal.nodes_m is None or modal.node_uz is None or modal.cells is None:
        raise ValueError(f"{modal.model} modal solution carries no mesh to export")
    idx = range(modal.node_uz.shape[0]) if index is None else index
    data = {}
    for k in idx:
        u = np.asarray(modal.node_uz[k], dtype=float)
        peak = max(np.max(np.abs(u)), 1e-300)
        uz = u / peak
        data[f"uz_mode_{k + 1}"] = uz
        if modal.node_u is not None:
            data[f"displacement_mode_{k + 1}"] = np.asarray(modal.node_u[k], dtype=float) / peak
        else:
            data[f"displacement_mode_{k + 1}"] = np.column_stack(
                [np.zeros_like(uz), np.zeros_like(uz), uz])
    mesh = meshio.Mesh(np.asarray(modal.nodes_m, dtype=float),
                       [(modal.cell_type, np.asarray(modal.cells))], point_data=data)
    path = Path(path)
    with atomic_path(path) as tmp:
        meshio.write(tmp, mesh, file_format="vtu")
    return path
