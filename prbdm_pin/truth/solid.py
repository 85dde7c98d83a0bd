"""3D solid truth: the modal and the tip-load solves.

Quadratic hexahedra (27 nodes), one element through the thickness.

The discretisation and linear assembly are in ``solid_fe``; the geometrically nonlinear solve
(total-Lagrangian Saint Venant-Kirchhoff, Newton with load steps) in ``solid_nonlinear``.
"""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse.linalg as spla

from ..errors import BeamInputError, SolveError
from ..member.geometry import Beam
from .modes import beam_mac
from .result import ModalSolution, StaticSolution, Timings
from .settings import lanczos_start
from .solid_fe import (
    ROOT_THICKNESSES,
    VTK_HEX,
    SpdFactor,
    assemble,
    default_solid_level,
    discretise,
    mirror_index,
    solid_mesh,
    tip_dofs,
    tip_load,
)
from .solid_nonlinear import solve_nonlinear

__all__ = ["ROOT_THICKNESSES", "default_solid_level", "solid_mesh", "solid_modal", "solid_static"]


def solid_modal(beam: Beam, level: int | None = None, n_modes: int = 30) -> ModalSolution:
    """Lowest modes of the 3D solid by shift-invert Lanczos about 0.

    Parameters
    ----------
    beam : Beam
    level : int, optional
        Planform mesh level (element size about L / (10 2^level) where the planform is wide,
        smaller at its features); default: closest to 2.5 t.
    n_modes : int
        Number of modes (all types: bending, torsion, chordwise, in-plane, axial).

    Returns
    -------
    ModalSolution
        ``mpf_z`` in kg from M and the rigid z translation; ``symmetric`` from the z displacement
        mirrored about y = 0; ``centerline_uz`` the mid-surface z displacement on y = 0 (scaled
        to unit maximum, positive at the tip) and ``node_uz`` at the same scale; ``mac_beam``
        against the 1D beam's bending modes; ``z_energy_fraction`` and ``x_energy_fraction``
        the shares of each mode's kinetic energy in z and in x motion (in-plane modes: z near
        0; of them the extension modes x near 1).
    """
    if not isinstance(n_modes, (int, np.integer)) or isinstance(n_modes, bool) or n_modes < 1:
        raise BeamInputError(f"n_modes = {n_modes!r}: must be an integer >= 1")
    t0 = time.perf_counter()
    d = discretise(beam, level)
    t1 = time.perf_counter()
    K, M = assemble(beam, d)
    Kff = K[d.free][:, d.free]
    Mff = M[d.free][:, d.free]
    t2 = time.perf_counter()
    k = min(n_modes, d.free.size - 2)
    lu = SpdFactor(Kff, d.order)
    OPinv = spla.LinearOperator(Kff.shape, matvec=lu.solve, dtype=float)
    lam, vec = spla.eigsh(Kff, k=k, M=Mff, sigma=0.0, which="LM", OPinv=OPinv, tol=1e-12,
                          v0=lanczos_start(Kff.shape[0]))
    t3 = time.perf_counter()
    if np.any(lam <= 0.0) or not np.all(np.isfinite(lam)):
        raise SolveError(f"solid eigenvalues not positive: min = {lam.min():.3e} (rad/s)^2")
    order = np.argsort(lam)
    lam, vec = lam[order], vec[:, order]
    phi = np.zeros((d.n_vec, k))
    phi[d.free] = vec
    r_z = np.zeros(d.n_vec)
    r_z[2::3] = 1.0  # Lagrange element: the rigid z translation interpolates to 1 at every DOF
    Mphi = M @ phi
    mpf = (r_z @ Mphi) ** 2 / np.einsum("ij,ij->j", phi, Mphi)

    locs = d.basis.doflocs.T
    uz = phi[2::3].T  # (k, N)
    # kinetic-energy share of the z motion: near 1 for bending and torsion, near 0 in plane
    energy = np.einsum("ij,ij->j", phi, Mphi)
    ez = np.einsum("ij,ij->j", phi[2::3], Mphi[2::3]) / energy
    # and of the x motion: near 1 for the extension modes, (b / L)^2 for in-plane bending
    ex = np.einsum("ij,ij->j", phi[0::3], Mphi[0::3]) / energy
    mirror = mirror_index(locs, beam.length_m)
    sym = np.linalg.norm(uz - uz[:, mirror], axis=1) < np.linalg.norm(uz + uz[:, mirror], axis=1)
    tol = 1e-9 * beam.length_m
    line = np.flatnonzero((np.abs(locs[:, 1]) < tol) & (np.abs(locs[:, 2]) < tol))
    line = line[np.argsort(locs[line, 0])]
    cl = uz[:, line]
    # scale every mode to a unit centreline peak, positive at the tip (a mode whose centreline
    # does not move, torsion or in-plane, to a unit peak of z displacement instead)
    peak = np.max(np.abs(cl), axis=1)
    top = np.max(np.abs(uz), axis=1)
    peak = np.where(peak > 1e-6 * top, peak, top)
    scale = np.where(cl[:, -1] < 0, -1.0, 1.0) / peak
    cl = cl * scale[:, None]
    mac, best = beam_mac(beam, locs[line, 0], cl)
    verts = d.basis.nodal_dofs[0]
    return ModalSolution(
        model="solid",
        omega_rad_s=np.sqrt(lam),
        mpf_z=mpf,
        mpf_z_fraction=mpf / beam.mass_kg,
        symmetric=sym,
        mac_beam=mac,
        beam_mode_index=best,
        centerline_x_m=locs[line, 0].copy(),
        centerline_uz=cl,
        dofs=int(d.free.size),
        mesh_level=d.level,
        timings=Timings(mesh_s=t1 - t0, assembly_s=t2 - t1, solve_s=t3 - t2),
        nodes_m=d.mesh.p.T.copy(),
        cells=d.mesh.t[VTK_HEX].T.copy(),
        cell_type="hexahedron",
        node_uz=uz[:, verts] * scale[:, None],
        # the whole displacement at the vertices (k, N, 3), interleaved x, y, z per node
        node_u=np.stack([phi[c::3][verts].T for c in range(3)], axis=-1) * scale[:, None, None],
        modal_mass_kg=scale**2,  # the eigenvectors are mass-normalised before scaling
        z_energy_fraction=ez,
        x_energy_fraction=ex,
    )


def solid_static(
    beam: Beam,
    level: int | None = None,
    tip_force_N: np.ndarray | None = None,
    nonlinear: bool = False,
    load_steps: int | None = None,
    tol: float = 1e-7,
    max_iter: int = 25,
) -> StaticSolution:
    """Tip response of the 3D solid under a tip force spread uniformly over the face x = L.

    Parameters
    ----------
    beam : Beam
    level : int, optional
        Planform mesh level; default: in-plane element size closest to 2.5 t.
    tip_force_N : array_like, shape (3,), optional
        Total tip force in N (default: ``beam.tip_force_N``); a dead load in the nonlinear solve.
    nonlinear : bool
        Geometrically nonlinear (total-Lagrangian Saint Venant-Kirchhoff) if True.
    load_steps : int, optional
        Initial load increments (default: about 3 per unit of P L^2 / EI_root); an increment whose
        Newton iteration fails is halved.
    tol : float
        Newton tolerance on the free residual relative to the load vector norm.
    max_iter : int
        Newton iterations per increment.

    Returns
    -------
    StaticSolution
        Displacement of the mid-surface tip point (L, 0, 0): the mean of the three DOFs on the
        tip edge's centreline (z = -t/2, 0, t/2), m.
    """
    F = np.asarray(beam.tip_force_N if tip_force_N is None else tip_force_N, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force_N = {F.tolist()}: must be 3 finite numbers in N")
    if load_steps is None:
        load_steps = int(np.clip(np.ceil(3 * beam.load_index(float(np.linalg.norm(F)))), 1, 100))
    if not isinstance(load_steps, (int, np.integer)) or load_steps < 1:
        raise BeamInputError(f"load_steps = {load_steps!r}: must be an integer >= 1")
    t0 = time.perf_counter()
    d = discretise(beam, level)
    f = tip_load(beam, d, F)
    t1 = time.perf_counter()
    if nonlinear:
        u, steps = solve_nonlinear(beam, d, f, load_steps, tol, max_iter)
        t2 = t3 = time.perf_counter()
    else:
        K, _ = assemble(beam, d)
        Kff = K[d.free][:, d.free]
        t2 = time.perf_counter()
        u = np.zeros(d.n_vec)
        u[d.free] = SpdFactor(Kff, d.order).solve(f[d.free])
        steps = 1
        t3 = time.perf_counter()
    tip = tip_dofs(beam, d)
    disp = np.array([u[3 * tip + i].mean() for i in range(3)])
    return StaticSolution(
        model="solid",
        nonlinear=bool(nonlinear),
        tip_force_N=F.copy(),
        tip_position_m=np.array([beam.length_m, 0.0, 0.0]) + disp,
        tip_displacement_m=disp,
        dofs=int(d.free.size),
        mesh_level=d.level,
        load_steps=steps,
        timings=Timings(mesh_s=t1 - t0, assembly_s=t2 - t1, solve_s=t3 - t2),
    )
