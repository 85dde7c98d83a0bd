"""The 1D Euler-Bernoulli truth's linear tip deflection under a tip force.

The Hermite beam of :mod:`.beam`, solved once for the load instead of for its modes.
"""

from __future__ import annotations

import time

import numpy as np
import scipy.linalg

from ..errors import BeamInputError
from ..member.geometry import Beam
from .beam import DENSE_MAX_DOFS, _assemble
from .result import StaticSolution, Timings

__all__ = ["beam_static"]


def beam_static(
    beam: Beam, tip_force_N: np.ndarray | None = None, n_elements: int = 200,
    stations_m: np.ndarray | None = None, dense_max_dofs: int = DENSE_MAX_DOFS,
) -> StaticSolution:
    """Linear tip deflection of the 1D beam under the z component of a tip force.

    Parameters
    ----------
    beam : Beam
    tip_force_N : array_like, shape (3,), optional
        Tip force in N (default: ``beam.tip_force_N``); only F_z bends the beam here.
    n_elements : int
    stations_m : array_like, optional
        Ready element edges (m), as in ``beam_modal``.
    dense_max_dofs : int
        Above this many free DOFs the solve is sparse, below it dense (as in ``beam_modal``).

    Returns
    -------
    StaticSolution
        Tip position (L, 0, w_tip) and displacement (0, 0, w_tip) in m.
    """
    F = np.asarray(beam.tip_force_N if tip_force_N is None else tip_force_N, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force_N = {F.tolist()}: must be 3 finite numbers in N")
    t0 = time.perf_counter()
    mesh, basis, K, M, u_dofs, free = _assemble(beam, n_elements, stations_m)
    tip = int(np.argmax(mesh.p[0]))
    f = np.zeros(basis.N)
    f[basis.nodal_dofs[0, tip]] = F[2]
    t1 = time.perf_counter()
    u = np.zeros(basis.N)
    if free.size > dense_max_dofs:
        from scipy.sparse.linalg import spsolve

        u[free] = spsolve(K[free][:, free].tocsc(), f[free])
    else:
        u[free] = scipy.linalg.solve(K[free][:, free].toarray(), f[free], assume_a="pos")
    t2 = time.perf_counter()
    disp = np.array([0.0, 0.0, u[basis.nodal_dofs[0, tip]]])
    return StaticSolution(
        model="beam",
        nonlinear=False,
        tip_force_N=F.copy(),
        tip_position_m=np.array([beam.length_m, 0.0, 0.0]) + disp,
        tip_displacement_m=disp,
        dofs=int(free.size),
        mesh_level=int(mesh.t.shape[1]),
        timings=Timings(assembly_s=t1 - t0, solve_s=t2 - t1),
    )
