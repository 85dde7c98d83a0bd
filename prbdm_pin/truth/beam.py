"""1D Euler-Bernoulli truth: cubic Hermite elements with the planform's varying EI(x) and rho A(x).

Element edges sit on every planform vertex (a width step is an element edge, where EI and rho A
jump), so EI(x) = E 2 w(x) t^3 / 12 and rho A(x) = rho 2 w(x) t are linear inside each element;
the quadrature order below integrates both matrices exactly. A thickness law t(x), linear between
the same stations, makes E I quartic and rho A quadratic: the mass integrand then has degree
2 + 3 + 3 = 8 and a higher order (``_INTORDER_LAW``) keeps both exact. A round member's laws
(:func:`~prbdm_pin.member.section_law.section_properties`: D, d linear between stations, which
are element edges) are of the same degrees: E I quartic, rho A quadratic, exact at that order.
"""

from __future__ import annotations

import time

import numpy as np
import scipy.linalg
from skfem import Basis, BilinearForm, ElementLineHermite, MeshLine, asm
from skfem.helpers import dd

from ..errors import BeamInputError, SolveError
from ..member.geometry import Beam
from ..member.section_law import section_properties
from ..options.limits import check_cap
from .result import ModalSolution, Timings
from .settings import lanczos_start

__all__ = ["beam_stations", "beam_modal", "beam_modes", "beam_modal_solution",
           "beam_bending_modes"]

# w(x) linear, Hermite cubic: the mass integrand has degree 1 + 3 + 3 = 7, stiffness 1 + 1 + 1 = 3.
_INTORDER = 7
# t(x) linear: mass integrand 1 + 1 + 3 + 3 = 8, stiffness 1 + 3 + 1 + 1 = 6
_INTORDER_LAW = 8
# shortest element, relative to L: below it the stiffness loses more than ~1e-5 of the frequencies
# to rounding (an element of 1e-4 L next to ones of 5e-3 L: 6e-6)
MIN_ELEMENT_REL = 1e-4
# most elements along the span (uniform strip: 2e-8 at 200, 3e-6 at 1000)
MAX_ELEMENTS = 500
# above this many DOFs the dense eigensolver (cubic cost, 8 N^2 bytes per matrix) gives way to
# shift-invert Lanczos on the banded matrices
DENSE_MAX_DOFS = 2000


def _check_count(name: str, value: int, minimum: int = 1) -> int:
    if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value < minimum:
        raise BeamInputError(f"{name} = {value!r}: must be an integer >= {minimum}")
    return int(value)


def beam_stations(beam: Beam, n_elements: int = 200) -> np.ndarray:
    """Return the element edges (m): every planform vertex plus about ``n_elements`` elements.

    The elements are shared out in proportion to the vertex intervals' lengths (at least one
    per interval).

    A vertex closer than ``MIN_ELEMENT_REL`` L to the previous edge is not an edge (the element
    across it integrates the kink of w(x) by quadrature): an element that short makes the
    stiffness matrix singular in double precision (1e-7 m: LinAlgError; 1e-5 m: frequencies
    1-3 % off). Likewise a planform of more than ``MAX_ELEMENTS`` intervals gets edges at least
    L / MAX_ELEMENTS apart (rounding grows with the element count: 3e-6 at 1000 elements,
    1e-4 at 2000 on a uniform strip). The root, the tip and width steps always stay edges.
    """
    n_elements = _check_count("n_elements", n_elements)
    starts, ends = beam.intervals_m  # a width step is one edge, not a zero-length element
    counts = np.maximum(1, np.round(n_elements * (ends - starts) / beam.length_m).astype(int))
    check_cap("mesh DOFs (1D beam elements x 2)", 2 * int(counts.sum()), "max_mesh_dofs")
    # np.linspace(a, b, n + 1)[:-1] of every interval, vectorised (a + k (b - a) / n)
    idx = np.repeat(np.arange(counts.size), counts)
    k = np.arange(idx.size) - np.repeat(np.cumsum(counts) - counts, counts)
    xs = starts[idx] + k * ((ends - starts) / counts)[idx]
    return _merge_short(beam, np.concatenate([xs, beam.x_m[-1:]]))


def _merge_short(beam: Beam, xs: np.ndarray) -> np.ndarray:
    """``xs`` without the edges closer than MIN_ELEMENT_REL L to a kept neighbour."""
    L = beam.length_m
    dmin = MIN_ELEMENT_REL * L
    if xs.size > MAX_ELEMENTS + 1:
        dmin = L / MAX_ELEMENTS
    elif np.min(np.diff(xs)) >= dmin:
        return xs
    fixed = {0.0, float(L), *(float(v) for v in beam.x_m[beam.step_index])}
    keep = [float(xs[0])]
    for x in map(float, xs[1:]):
        if x - keep[-1] >= dmin:
            keep.append(x)
        elif x in fixed and keep[-1] not in fixed:
            keep[-1] = x
        elif x in fixed:
            i = int(np.searchsorted(beam.x_m, x))
            raise BeamInputError(
                f"x[{i}] = {x!r} m: a width step (or the tip) {x - keep[-1]:.3g} m from another "
                f"(or from the root), below {MIN_ELEMENT_REL:g} L = {dmin:.3g} m: the 1D beam "
                "cannot represent it in double precision (merge the two)")
    if keep[-1] != float(L):
        keep.append(float(L))
    return np.array(keep)


@BilinearForm
def _stiffness(u, v, w):
    return w["EI"] * dd(u)[0, 0] * dd(v)[0, 0]


@BilinearForm
def _mass(u, v, w):
    return w["rhoA"] * u * v


def _assemble(beam: Beam, n_elements: int, stations_m: np.ndarray | None = None,
              in_plane: bool = False):
    # given stations: a mesh that moved with the planform (shape sensitivities keep its topology)
    xs = beam_stations(beam, n_elements) if stations_m is None else np.asarray(stations_m, float)
    mesh = MeshLine(xs)
    law = beam.thickness_law_m is not None or beam.section is not None
    basis = Basis(mesh, ElementLineHermite(), intorder=_INTORDER_LAW if law else _INTORDER)
    xq = basis.global_coordinates()[0]
    if beam.section is not None:
        sp = section_properties(beam, xq)
        K = asm(_stiffness, basis, EI=sp.EI_z_Nm2 if in_plane else sp.EI_y_Nm2)
        M = asm(_mass, basis, rhoA=sp.rhoA_kg_m)
        return _clamped(mesh, basis, K, M)
    t = beam.thickness_at(xq) if law else beam.thickness_m
    width = 2.0 * beam.half_width_at(xq)
    # in-plane bending: E I_z = E t (2 w)^3 / 12, cubic in x: stiffness integrand of degree 5
    E = beam.material.E_Pa
    EI = E * t * width**3 / 12.0 if in_plane else E * width * t**3 / 12.0
    K = asm(_stiffness, basis, EI=EI)
    M = asm(_mass, basis, rhoA=beam.material.rho_kg_m3 * width * t)
    return _clamped(mesh, basis, K, M)


def _clamped(mesh, basis, K, M):
    # DOF order: nodal [u, u_x] per node; clamp u and u_x at the root node.
    u_dofs = basis.nodal_dofs[0]
    root = int(np.argmin(mesh.p[0]))
    fixed = basis.nodal_dofs[:, root]
    free = np.setdiff1d(np.arange(basis.N), fixed)
    return mesh, basis, K, M, u_dofs, free


def _eigh(K, M, free, n_modes, dense_max_dofs: int = DENSE_MAX_DOFS):
    N = free.size
    n = min(n_modes, N)
    if N > dense_max_dofs:
        return _eigsh(K[free][:, free], M[free][:, free], n)
    Kf = K[free][:, free].toarray()
    Mf = M[free][:, free].toarray()
    # Solve M phi = mu K phi for the largest mu = 1 / omega^2: the low modes of K phi = lam M phi
    # lose ~eps * lam_max / lam_1 (1e-6 at 200 elements) to rounding, the inverse problem does not.
    mu, vec = scipy.linalg.eigh(Mf, Kf, subset_by_index=[N - n, N - 1])
    lam, vec = 1.0 / mu[::-1], vec[:, ::-1]
    if np.any(lam <= 0.0) or not np.all(np.isfinite(lam)):
        raise SolveError(f"beam eigenvalues not positive: min = {lam.min():.3e} (rad/s)^2")
    return lam, vec


def _eigsh(Kf, Mf, n):
    """Return the n lowest modes by shift-invert Lanczos about 0 (banded K: linear cost)."""
    from scipy.sparse.linalg import eigsh

    lam, vec = eigsh(Kf.tocsc(), k=n, M=Mf.tocsc(), sigma=0.0, which="LM", tol=0.0,
                     v0=lanczos_start(Kf.shape[0]))
    order = np.argsort(lam)
    lam, vec = lam[order], vec[:, order]
    if np.any(lam <= 0.0) or not np.all(np.isfinite(lam)):
        raise SolveError(f"beam eigenvalues not positive: min = {lam.min():.3e} (rad/s)^2")
    return lam, vec


def beam_modal(beam: Beam, n_modes: int = 10, n_elements: int = 200,
               stations_m: np.ndarray | None = None,
               dense_max_dofs: int = DENSE_MAX_DOFS) -> ModalSolution:
    """Bending modes of the 1D Euler-Bernoulli beam with varying section.

    Parameters
    ----------
    beam : Beam
    n_modes : int
        Number of modes (lowest first).
    n_elements : int
        About this many Hermite elements along the span (vertices are always element edges).
    stations_m : array_like, optional
        Ready element edges (m, ascending, from 0 to L, every vertex among them) instead of
        ``beam_stations(beam, n_elements)``.
    dense_max_dofs : int
        Above this many free DOFs the eigenproblem is solved sparse (shift-invert ARPACK),
        below it dense (LAPACK); default ``DENSE_MAX_DOFS``.

    Returns
    -------
    ModalSolution
        ``omega_rad_s`` ascending; ``mpf_z`` in kg from the consistent mass matrix and the rigid
        z translation; every mode symmetric with MAC 1 against itself; ``centerline_uz`` are the
        nodal deflections scaled to unit maximum with a positive tip.
    """
    n_modes = _check_count("n_modes", n_modes)
    return beam_modal_solution(beam, *beam_modes(beam, n_modes, n_elements, stations_m,
                                                 dense_max_dofs))


def beam_modes(beam: Beam, n_modes: int, n_elements: int = 200,
               stations_m: np.ndarray | None = None, dense_max_dofs: int = DENSE_MAX_DOFS):
    """Return the raw modes of ``beam_modal``.

    (mesh, basis, K, M, u_dofs, free, lam, phi, timings), ``phi`` (N, k) the full DOF vectors
    (clamped DOFs zero; not mass-normalised: the dense solve gives phi^T K phi = 1), ``lam`` in
    (rad/s)^2.
    """
    t0 = time.perf_counter()
    mesh, basis, K, M, u_dofs, free = _assemble(beam, n_elements, stations_m)
    t1 = time.perf_counter()
    lam, vec = _eigh(K, M, free, n_modes, dense_max_dofs)
    t2 = time.perf_counter()
    phi = np.zeros((basis.N, lam.size))
    phi[free] = vec
    timings = Timings(assembly_s=t1 - t0, solve_s=t2 - t1)
    return mesh, basis, K, M, u_dofs, free, lam, phi, timings


def beam_modal_solution(beam, mesh, basis, K, M, u_dofs, free, lam, phi,
                        timings) -> ModalSolution:
    """Return the ``ModalSolution`` of the raw modes ``beam_modes`` returns."""
    k = lam.size
    r_z = np.zeros(basis.N)
    r_z[u_dofs] = 1.0  # the rigid z translation: u = 1, u_x = 0
    Mphi = M @ phi
    mpf = (r_z @ Mphi) ** 2 / np.einsum("ij,ij->j", phi, Mphi)
    uz = phi[u_dofs].T
    uz = uz / uz[:, -1:] * np.abs(uz[:, -1:]) / np.max(np.abs(uz), axis=1, keepdims=True)
    xs = mesh.p[0]
    nodes = np.column_stack([xs, np.zeros_like(xs), np.zeros_like(xs)])
    return ModalSolution(
        model="beam",
        omega_rad_s=np.sqrt(lam),
        mpf_z=mpf,
        mpf_z_fraction=mpf / beam.mass_kg,
        symmetric=np.ones(k, dtype=bool),
        mac_beam=np.ones(k),
        beam_mode_index=np.arange(k),
        centerline_x_m=xs.copy(),
        centerline_uz=uz,
        dofs=int(free.size),
        mesh_level=int(mesh.t.shape[1]),
        timings=timings,
        nodes_m=nodes,
        cells=mesh.t.T.copy(),
        cell_type="line",
        node_uz=uz.copy(),
    )


def _hermite_sample(xs: np.ndarray, u: np.ndarray, ux: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Evaluate the cubic Hermite field with nodal values u, slopes ux (rows: fields) at x."""
    e = np.clip(np.searchsorted(xs, x, side="right") - 1, 0, xs.size - 2)
    h = xs[e + 1] - xs[e]
    s = (x - xs[e]) / h
    h00 = 2 * s**3 - 3 * s**2 + 1
    h10 = s**3 - 2 * s**2 + s
    h01 = -2 * s**3 + 3 * s**2
    h11 = s**3 - s**2
    return h00 * u[:, e] + h10 * h * ux[:, e] + h01 * u[:, e + 1] + h11 * h * ux[:, e + 1]


def beam_bending_modes(
    beam: Beam, x_m: np.ndarray, n_modes: int, n_elements: int = 200
) -> tuple[np.ndarray, np.ndarray]:
    """Beam bending frequencies and mode shapes sampled at stations ``x_m``.

    Parameters
    ----------
    beam : Beam
    x_m : array_like, shape (s,)
        Stations along the axis in m, within [0, L].
    n_modes : int
    n_elements : int

    Returns
    -------
    omega_rad_s : ndarray, shape (n_modes,)
    shapes : ndarray, shape (n_modes, s)
        z deflection of each mode at ``x_m`` (interpolated with the element's own cubic),
        arbitrary scale.
    """
    n_modes = _check_count("n_modes", n_modes)
    x = np.asarray(x_m, dtype=float).ravel()
    L = beam.length_m
    if x.size and (not np.all(np.isfinite(x)) or x.min() < -1e-12 * L or x.max() > L * (1 + 1e-12)):
        raise BeamInputError(f"x_m spans [{x.min()}, {x.max()}] m: must lie within [0, {L}] m")
    mesh, basis, K, M, u_dofs, free = _assemble(beam, n_elements)
    lam, vec = _eigh(K, M, free, n_modes)
    phi = np.zeros((basis.N, lam.size))
    phi[free] = vec
    xs = mesh.p[0]
    order = np.argsort(xs)
    u = phi[basis.nodal_dofs[0][order]].T
    ux = phi[basis.nodal_dofs[1][order]].T
    return np.sqrt(lam), _hermite_sample(xs[order], u, ux, np.clip(x, 0.0, L))
