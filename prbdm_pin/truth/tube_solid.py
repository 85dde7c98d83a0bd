"""3D solid truth of a round tube or rod with diameters linear between stations.

The member is clamped at its first station x_m[0] (every displacement zero there), the mesh is
``tube_mesh``'s quadratic hexahedra with curved faces, the stiffness and mass those of the plate
member's solid (``solid_fe.assemble_elastic``), the modes the lowest of shift-invert Lanczos.

Each mode is labelled by where its kinetic energy goes: ``"axial"`` (x motion), ``"torsion"``
(circumferential motion about the axis), ``"bending-y"`` / ``"bending-z"`` (y or z motion),
``"section"`` (none dominant: the wall's own shell modes). A round member bends alike in every
plane, so each bending frequency is a degenerate pair whose eigensolver vectors are any two
orthogonal combinations: within every cluster of frequencies equal to 1e-6 the vectors are
rotated (an orthogonal transformation of the cluster, which keeps them mass-orthonormal) to
the eigenvectors of their y kinetic energy, so that one of the pair moves in y, the other in z.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as spla
from skfem import Basis, ElementHex2, MeshHex2

from ..errors import BeamInputError, InputTypeError, SolveError
from ..member.checks import float_array
from ..member.material import Material
from .settings import lanczos_start
from .solid_fe import INTORDER, SpdFactor, assemble_elastic, lame_of
from .tube_mesh import tube_hex_mesh

__all__ = ["TubeModes", "tube_solid_modes", "round_solid_modes", "MODE_KINDS"]

MODE_KINDS = ("bending-y", "bending-z", "torsion", "axial", "section")
# frequencies closer than this (relative) are one degenerate cluster: the structured mesh keeps
# the two bending planes equal to the eigensolver's precision (~1e-12), section modes of
# distinct order are far apart
_DEGENERATE_RTOL = 1e-6
# energy share that names a kind (a slender member's bending mode puts >99 % of its energy in
# its plane, torsion all of it in circumferential motion; what remains is the sections' rotation
# and Poisson contraction)
_KIND_SHARE = 0.8


@dataclass(frozen=True, eq=False)
class TubeModes:
    """Modes of the round member's 3D solid.

    Attributes
    ----------
    omega_rad_s : ndarray, shape (k,)
        Natural frequencies, rad/s, ascending.
    kinds : tuple of str
        The label of each mode (``MODE_KINDS``).
    energy_fractions : ndarray, shape (k, 4)
        Each mode's kinetic-energy shares of x, y, z and circumferential motion.
    phi : ndarray, shape (3 n, k)
        Mass-normalised mode shapes, DOF 3 a + i component i at node a of ``mesh``.
    mesh : MeshHex2
        Nodes in m.
    dofs : int
        Free DOFs.
    timings_s : tuple of float
        (mesh, assembly, solve) wall times, s.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.round_beam([0.0, 1.0], [0.02, 0.02], [0.016, 0.016])
    >>> modes = pp.round_solid_modes(beam, n_modes=2, n_around=8, n_radial=1, n_along=4)
    >>> isinstance(modes, pp.TubeModes), modes.phi.shape == (modes.mesh.p.size, 2)
    (True, True)
    >>> modes.energy_fractions.shape  # shares of x, y, z and circumferential motion
    (2, 4)
    >>> modes.energy_fractions[:, 1:3].argmax(axis=1)  # mode 1 moves in y, mode 2 in z
    array([0, 1])
    """

    omega_rad_s: np.ndarray
    kinds: tuple[str, ...]
    energy_fractions: np.ndarray
    phi: np.ndarray
    mesh: MeshHex2
    dofs: int
    timings_s: tuple[float, float, float]

    def of_kind(self, kind: str) -> np.ndarray:
        """Frequencies (rad/s) of the modes labelled ``kind``, ascending."""
        if kind not in MODE_KINDS:
            raise BeamInputError(f"kind = {kind!r}: must be one of {MODE_KINDS}")
        return self.omega_rad_s[[k == kind for k in self.kinds]]


def _count(name: str, value: object, minimum: int, multiple: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InputTypeError(f"{name} = {value!r}: must be an integer")
    if value < minimum or value % multiple:
        extra = f" and a multiple of {multiple}" if multiple > 1 else ""
        raise BeamInputError(f"{name} = {value!r}: must be >= {minimum}{extra}")
    return int(value)


def check_round_section(x_m, outer_diameter_m, inner_diameter_m):
    """Return the stations and diameters as float arrays; BeamInputError naming the argument.

    ``x_m`` increasing (at least two stations), ``outer_diameter_m`` > 0, ``inner_diameter_m``
    (None: a rod) in [0, outer) and all zero or all positive, all aligned with ``x_m``.
    """
    x = float_array("x_m", x_m, "m")
    D = float_array("outer_diameter_m", outer_diameter_m, "m")
    d = np.zeros_like(D) if inner_diameter_m is None else float_array(
        "inner_diameter_m", inner_diameter_m, "m")
    if x.size < 2:
        raise BeamInputError(f"x_m = {x.tolist()}: needs at least two stations")
    bad = np.flatnonzero(np.diff(x) <= 0.0)
    if bad.size:
        i = int(bad[0]) + 1
        raise BeamInputError(f"x_m[{i}] = {x[i]} m: must exceed x_m[{i - 1}] = {x[i - 1]} m")
    for name, arr in (("outer_diameter_m", D), ("inner_diameter_m", d)):
        if arr.size != x.size:
            raise BeamInputError(f"{name} has {arr.size} entries: must be aligned with x_m "
                                 f"({x.size} stations)")
    for i in np.flatnonzero(D <= 0.0)[:1]:
        raise BeamInputError(f"outer_diameter_m[{i}] = {D[i]} m: must be > 0")
    for i in np.flatnonzero(d < 0.0)[:1]:
        raise BeamInputError(f"inner_diameter_m[{i}] = {d[i]} m: must be >= 0")
    for i in np.flatnonzero(d >= D)[:1]:
        raise BeamInputError(f"inner_diameter_m[{i}] = {d[i]} m at x = {x[i]} m: must be below "
                             f"outer_diameter_m[{i}] = {D[i]} m")
    if np.any(d > 0.0) and np.any(d == 0.0):
        i = int(np.flatnonzero(d == 0.0)[0])
        raise BeamInputError(f"inner_diameter_m[{i}] = 0 m: a tube's bore must stay open (all "
                             "entries > 0) or be absent (all 0, a rod)")
    return x, D, d


def tube_solid_modes(
    x_m, outer_diameter_m, inner_diameter_m, material: Material, n_modes: int = 12,
    n_around: int = 16, n_radial: int = 2, n_along: int = 20,
) -> TubeModes:
    """Lowest modes of the clamped-free 3D solid of a round tube or rod.

    Parameters
    ----------
    x_m : array_like, shape (k,)
        Stations along the axis, m, increasing; clamped at ``x_m[0]``, free at ``x_m[-1]``.
    outer_diameter_m : array_like, shape (k,)
        Outer diameter D at each station, m (> 0), linear between stations.
    inner_diameter_m : array_like, shape (k,), or None
        Inner diameter d at each station, m, in [0, D): all zero or None for a solid rod.
    material : Material
        Isotropic elastic material (E, rho, nu).
    n_modes : int
        Number of lowest modes.
    n_around : int
        Elements around the circumference (a multiple of 4, >= 8).
    n_radial : int
        Elements through a tube's wall (>= 1; unused by a rod).
    n_along : int
        About this many elements along the axis (>= 1; every station an element edge).

    Returns
    -------
    TubeModes
        Frequencies in rad/s with their kinds; a degenerate bending pair as one y and one z mode.

    Raises
    ------
    BeamInputError
        Bad stations or diameters (naming the argument and the station), bad counts.
    InputTypeError
        ``material`` not a Material, a count not an integer.
    SolveError
        A non-positive eigenvalue.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> modes = pp.tube_solid_modes([0.0, 1.0], [0.02, 0.02], [0.016, 0.016], pp.Material(),
    ...                             n_modes=2, n_around=8, n_radial=1, n_along=8)
    >>> modes.kinds  # the degenerate bending pair, one y and one z
    ('bending-y', 'bending-z')
    >>> EI = 205e9 * np.pi / 64 * (0.02**4 - 0.016**4)  # N m^2
    >>> rho_A = 7850.0 * np.pi / 4 * (0.02**2 - 0.016**2)  # kg/m
    >>> # rad/s: the coarse solid (8 elements around and along) against Euler-Bernoulli
    >>> round(float(modes.omega_rad_s[0]), 1), round(1.8751041**2 * float(np.sqrt(EI / rho_A)), 1)
    (116.0, 115.0)
    >>> finer = pp.tube_solid_modes([0.0, 1.0], [0.02, 0.02], [0.016, 0.016], pp.Material(),
    ...                             n_modes=2, n_around=8, n_radial=1, n_along=16)
    >>> round(float(finer.omega_rad_s[0]), 1)  # twice the elements along: closer to 115.0
    115.4
    """
    if not isinstance(material, Material):
        raise InputTypeError(f"material = {material!r}: must be a prbdm_pin Material")
    x, D, d = check_round_section(x_m, outer_diameter_m, inner_diameter_m)
    n_modes = _count("n_modes", n_modes, 1)
    n_around = _count("n_around", n_around, 8, 4)
    n_radial = _count("n_radial", n_radial, 1)
    n_along = _count("n_along", n_along, 1)
    t0 = time.perf_counter()
    mesh = tube_hex_mesh(x, D, d, n_around, n_radial, n_along)
    basis = Basis(mesh, ElementHex2(), intorder=INTORDER)
    t1 = time.perf_counter()
    lam_Pa, mu_Pa = lame_of(material)
    K, M = assemble_elastic(basis, lam_Pa, mu_Pa, material.rho_kg_m3)
    root = basis.get_dofs(lambda p: np.isclose(p[0], x[0], atol=1e-12 * (x[-1] - x[0]))).all()
    fixed = (3 * root[:, None] + np.arange(3)).ravel()
    free = np.setdiff1d(np.arange(3 * basis.N), fixed)
    Kff, Mff = K[free][:, free], M[free][:, free]
    t2 = time.perf_counter()
    # one mode more than asked, so that a degenerate pair cut by n_modes is complete when it is
    # rotated (``_labelled``); the extra mode is dropped after
    k = min(n_modes + 1, free.size - 2)
    lu = SpdFactor(Kff)
    OPinv = spla.LinearOperator(Kff.shape, matvec=lu.solve, dtype=float)
    lam, vec = spla.eigsh(Kff, k=k, M=Mff, sigma=0.0, which="LM", OPinv=OPinv, tol=1e-12,
                          v0=lanczos_start(Kff.shape[0]))
    t3 = time.perf_counter()
    if np.any(lam <= 0.0) or not np.all(np.isfinite(lam)):
        raise SolveError(f"tube eigenvalues not positive: min = {lam.min():.3e} (rad/s)^2")
    order = np.argsort(lam)
    lam, vec = lam[order], vec[:, order]
    phi = np.zeros((3 * basis.N, k))
    phi[free] = vec
    phi = phi / np.sqrt(np.einsum("ij,ij->j", phi, M @ phi))
    phi, shares = _labelled(basis.doflocs, M, lam, phi)
    keep = min(n_modes, k)
    lam, phi, shares = lam[:keep], phi[:, :keep], shares[:keep]
    kinds = tuple(_kind(s) for s in shares)
    return TubeModes(np.sqrt(lam), kinds, shares, phi, mesh, int(free.size),
                     (t1 - t0, t2 - t1, t3 - t2))


def _energy_shares(locs: np.ndarray, M, phi: np.ndarray) -> np.ndarray:
    """Kinetic-energy shares (k, 4) of x, y, z and circumferential motion of mass-normal ``phi``.

    The consistent mass is the scalar mass times the identity per node (``assemble_elastic``),
    so the x, y and z shares add up to 1; the circumferential share is that of the motion along
    e_theta = (0, -z, y) / r (zero on the axis).
    """
    Mphi = M @ phi
    out = np.empty((phi.shape[1], 4))
    for i in range(3):
        out[:, i] = np.einsum("ij,ij->j", phi[i::3], Mphi[i::3])
    r = np.hypot(locs[1], locs[2])
    safe = np.where(r > 0.0, r, 1.0)
    sin, cos = np.where(r > 0.0, locs[2] / safe, 0.0), np.where(r > 0.0, locs[1] / safe, 0.0)
    circ = np.zeros_like(phi)
    u_t = -sin[:, None] * phi[1::3] + cos[:, None] * phi[2::3]
    circ[1::3], circ[2::3] = -sin[:, None] * u_t, cos[:, None] * u_t
    out[:, 3] = np.einsum("ij,ij->j", circ, M @ circ)
    return out


def _labelled(locs: np.ndarray, M, lam: np.ndarray, phi: np.ndarray):
    """Rotate every degenerate cluster to y and z motion; return (phi, energy shares)."""
    phi = phi.copy()
    start = 0
    while start < lam.size:
        stop = start + 1
        while stop < lam.size and lam[stop] - lam[start] < 2.0 * _DEGENERATE_RTOL * lam[start]:
            stop += 1
        if stop - start > 1:
            block = phi[:, start:stop]
            ey = block[1::3].T @ (M[1::3][:, 1::3] @ block[1::3])
            w, R = np.linalg.eigh(0.5 * (ey + ey.T))
            phi[:, start:stop] = block @ R[:, ::-1]  # most y motion first
        start = stop
    return phi, _energy_shares(locs, M, phi)


def _kind(share: np.ndarray) -> str:
    ex, ey, ez, et = share
    if ex > _KIND_SHARE:
        return "axial"
    if et > _KIND_SHARE:
        return "torsion"
    if ey > _KIND_SHARE:
        return "bending-y"
    if ez > _KIND_SHARE:
        return "bending-z"
    return "section"


def round_solid_modes(beam, n_modes: int = 12, n_around: int = 16, n_radial: int = 2,
                      n_along: int = 20) -> TubeModes:
    """Lowest modes of the 3D solid of a round member given as a Beam (``beam.section`` round).

    :func:`tube_solid_modes` on the member's stations, diameters and material.

    Parameters
    ----------
    beam : Beam
        A round member (:func:`~prbdm_pin.member.section_member.round_beam`, or beam JSON with
        ``"section": {"kind": "round", ...}``).
    n_modes, n_around, n_radial, n_along : int
        As :func:`tube_solid_modes`.

    Returns
    -------
    TubeModes

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.round_beam([0.0, 1.0], [0.02, 0.02])  # a steel rod, m
    >>> modes = pp.round_solid_modes(beam, n_modes=2, n_around=8, n_along=8)
    >>> EI, rho_A = 205e9 * np.pi * 0.02**4 / 64, 7850.0 * np.pi * 0.02**2 / 4  # N m^2, kg/m
    >>> modes.omega_rad_s.round(1), round(1.8751041**2 * float(np.sqrt(EI / rho_A)), 1)  # rad/s
    (array([90.8, 90.8]), 89.8)
    >>> # the bending pair; the coarse solid is about 1 % stiffer than Euler-Bernoulli
    """
    from ..member.geometry import Beam
    from ..member.round_section import RoundSection

    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r:.60}: must be a prbdm_pin.Beam")
    if not isinstance(beam.section, RoundSection):
        raise BeamInputError("beam.section: round_solid_modes takes a round member; a planform "
                             "goes to compute_truth(..., model='solid')")
    sec = beam.section
    return tube_solid_modes(beam.x_m, sec.outer_diameter_m, sec.inner_diameter_m, beam.material,
                            n_modes, n_around, n_radial, n_along)
