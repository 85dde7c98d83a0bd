"""1D Timoshenko truth: clamped-free bending in a plane with shear deformation and rotary inertia.

Two locking-free elements (DOFs per node: deflection w, m, and section rotation theta, rad):

- ``"quadratic"`` (default): three-node Lagrange w and theta, bending and mass at 6 Gauss points,
  shear at the 2 reduced points, where the quadratic theta is replaced by its linear projection,
  the space of dw/dx: pure bending costs no shear energy at any slenderness (Prathap & Bhashyam
  1982). Its frequencies converge like h^4 (the ratio of errors at h and h/2 is 16, measured on
  the uniform cantilever at L / r_g = 10 ... 1000), so 40 elements give mode 4 to 4e-6.
- ``"interdependent"``: the two-node element of Friedman & Kosmatka (1993, Computers & Structures
  47, 473-481), cubic w and quadratic theta tied by phi = 12 E I / (kappa G A h^2) so that they
  solve the static equations of a uniform element: its stiffness is exact (the tip under a tip
  force to rounding with one element) and it reduces to the Hermite element of ``beam.py`` as
  phi -> 0, but its consistent mass only gives h^2 convergence of the frequencies of a thick
  beam (the tie between the third derivative of w and theta holds statically, not under inertia
  loading: 3.7e-4 on mode 4 at L / r_g = 10 with 80 elements). It is kept as the cross-check.

Why not linear elements with reduced integration: h^2 as well, so about 50 times the elements of
the quadratic one for 1e-6. The price of the quadratic element is rounding on slender members:
the shear stiffness kappa G A is (kappa G / E) (L / r_g)^2 times the bending one, and it costs
about 1e-7 of the frequency at L / r_g = 1000 with 160 elements (where Timoshenko differs from
Euler-Bernoulli by 1e-5 %, and the Euler-Bernoulli truth is the one to use).

On an element whose section varies, the laws are sampled at the Gauss points; put every kink or
jump of a law on an element edge (``beam_timoshenko_modal`` uses the planform's vertices).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..member.geometry import Beam
from .beam import _check_count, _eigh, beam_stations
from .result import Timings
from .timoshenko_sections import SectionLaws, rectangle_section_laws

__all__ = ["TimoshenkoModes", "TimoshenkoStatic", "timoshenko_modal", "timoshenko_static",
           "beam_timoshenko_modal", "element_matrices"]

_GX, _GW = np.polynomial.legendre.leggauss(6)
_GX = 0.5 * (_GX + 1.0)  # on [0, 1]
_GW = 0.5 * _GW
# 2-point Gauss for the quadratic element's shear (reduced integration)
_RX, _RW = np.polynomial.legendre.leggauss(2)
_RX = 0.5 * (_RX + 1.0)
_RW = 0.5 * _RW
ELEMENTS = ("quadratic", "interdependent")


@dataclass(frozen=True, eq=False)
class TimoshenkoModes:
    """Modes of the clamped-free Timoshenko beam, lowest first.

    Attributes
    ----------
    omega_rad_s : ndarray, shape (k,)
        Natural frequencies, rad/s.
    x_m : ndarray, shape (n,)
        Nodes along the axis, m (root first).
    deflection_m : ndarray, shape (k, n)
        Deflection w of each mode at the nodes, mass-normalised (phi^T M phi = 1 kg... in the
        units of the DOFs), sign such that the tip deflection is >= 0.
    rotation_rad : ndarray, shape (k, n)
        Section rotation theta of each mode at the nodes, same scale.
    dofs : int
        Free DOFs.
    timings : Timings
    """

    omega_rad_s: np.ndarray
    x_m: np.ndarray
    deflection_m: np.ndarray
    rotation_rad: np.ndarray
    dofs: int
    timings: Timings


@dataclass(frozen=True)
class TimoshenkoStatic:
    """Linear tip response of the clamped-free Timoshenko beam to a transverse tip force.

    Attributes
    ----------
    tip_force_N : float
    tip_deflection_m : float
    tip_rotation_rad : float
    """

    tip_force_N: float
    tip_deflection_m: float
    tip_rotation_rad: float


def _shape(s: np.ndarray, h: np.ndarray, phi: np.ndarray):
    """Friedman-Kosmatka shape functions at fractions ``s`` (q,) of elements (e,) of length h.

    Returns Nw, dNw/dx, Nt, dNt/dx, each (e, q, 4), DOF order (w1, theta1, w2, theta2).
    """
    s = s[None, :]
    h = h[:, None]
    c = 1.0 / (1.0 + phi[:, None])
    p = phi[:, None]
    s2, s3 = s * s, s * s * s
    Nw = np.stack([c * (2 * s3 - 3 * s2 - p * s + 1 + p),
                   c * h * (s3 - (2 + p / 2) * s2 + (1 + p / 2) * s),
                   -c * (2 * s3 - 3 * s2 - p * s),
                   c * h * (s3 - (1 - p / 2) * s2 - (p / 2) * s)], axis=-1)
    dNw = np.stack([c * (6 * s2 - 6 * s - p) / h,
                    c * (3 * s2 - (4 + p) * s + 1 + p / 2),
                    -c * (6 * s2 - 6 * s - p) / h,
                    c * (3 * s2 - (2 - p) * s - p / 2)], axis=-1)
    Nt = np.stack([6 * c / h * (s2 - s),
                   c * (3 * s2 - (4 + p) * s + 1 + p),
                   -6 * c / h * (s2 - s),
                   c * (3 * s2 - (2 - p) * s)], axis=-1)
    dNt = np.stack([6 * c / h * (2 * s - 1) / h,
                    c * (6 * s - (4 + p)) / h,
                    -6 * c / h * (2 * s - 1) / h,
                    c * (6 * s - (2 - p)) / h], axis=-1)
    return Nw, dNw, Nt, dNt


def _fk_matrices(xs: np.ndarray, laws: SectionLaws):
    """Friedman-Kosmatka element matrices (e, 4, 4), DOFs (w1, theta1, w2, theta2)."""
    a, h = xs[:-1], np.diff(xs)
    mid = a + 0.5 * h
    phi = 12.0 * laws.EI_Nm2(mid) / (laws.kappaGA_N(mid) * h * h)
    Nw, dNw, Nt, dNt = _shape(_GX, h, phi)
    xq = a[:, None] + h[:, None] * _GX[None, :]
    wq = h[:, None] * _GW[None, :]
    gam = dNw - Nt
    K = (_gram(laws.EI_Nm2(xq) * wq, dNt, dNt) + _gram(laws.kappaGA_N(xq) * wq, gam, gam))
    M = _gram(laws.rhoA_kg_m(xq) * wq, Nw, Nw) + _gram(laws.rhoI_kg_m(xq) * wq, Nt, Nt)
    return K, M


def _quadratic_matrices(xs: np.ndarray, laws: SectionLaws):
    """Three-node Lagrange element matrices (e, 6, 6), DOFs (w, theta) at the ends and middle.

    Shear at the 2 reduced Gauss points: there the quadratic theta is replaced by its linear
    projection, the space of w', so a pure bending state has zero shear energy (no locking).
    """
    a, h = xs[:-1], np.diff(xs)

    def lagrange(s):
        N = np.stack([2 * (s - 0.5) * (s - 1), -4 * s * (s - 1), 2 * s * (s - 0.5)], -1)
        dN = np.stack([4 * s - 3, 4 - 8 * s, 4 * s - 1], -1)
        return N, dN

    def fields(s):
        N, dN = lagrange(s)
        z = np.zeros(N.shape[:-1] + (6,))
        Nw, Nt = z.copy(), z.copy()
        Nw[..., 0::2], Nt[..., 1::2] = N, N
        dNw, dNt = z.copy(), z.copy()
        dNw[..., 0::2], dNt[..., 1::2] = dN, dN
        # d/dx = d/ds / h per element
        return (np.broadcast_to(Nw, (h.size,) + Nw.shape), dNw[None] / h[:, None, None],
                np.broadcast_to(Nt, (h.size,) + Nt.shape), dNt[None] / h[:, None, None])

    Nw, dNw, Nt, dNt = fields(_GX)
    xq = a[:, None] + h[:, None] * _GX[None, :]
    wq = h[:, None] * _GW[None, :]
    K = _gram(laws.EI_Nm2(xq) * wq, dNt, dNt)
    M = _gram(laws.rhoA_kg_m(xq) * wq, Nw, Nw) + _gram(laws.rhoI_kg_m(xq) * wq, Nt, Nt)
    _, dNw2, Nt2, _ = fields(_RX)
    xr = a[:, None] + h[:, None] * _RX[None, :]
    gam = dNw2 - Nt2
    K = K + _gram(laws.kappaGA_N(xr) * h[:, None] * _RW[None, :], gam, gam)
    return K, M


def _gram(wq: np.ndarray, A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """sum_q wq A_qi B_qj per element: (e, q), (e, q, i), (e, q, j) -> (e, i, j)."""
    return np.einsum("eq,eqi,eqj->eij", wq, A, B)


def element_matrices(stations_m: np.ndarray, laws: SectionLaws, element: str = "quadratic"):
    """Stiffness and mass matrices of the elements between ``stations_m`` (m).

    K = int E I theta'^2 + kappa G A (w' - theta)^2 dx, M = int rho A w^2 + rho I theta^2 dx
    over the element's shape functions: (e, 6, 6) for ``"quadratic"`` (DOFs w, theta at the
    ends and the middle, in order along x), (e, 4, 4) for ``"interdependent"``.
    """
    xs = np.asarray(stations_m, dtype=float)
    if element == "quadratic":
        return _quadratic_matrices(xs, laws)
    if element == "interdependent":
        return _fk_matrices(xs, laws)
    raise BeamInputError(f"element = {element!r}: must be one of {ELEMENTS}")


def _assemble(stations_m: np.ndarray, laws: SectionLaws, element: str):
    import scipy.sparse as sp

    Ke, Me = element_matrices(stations_m, laws, element)
    e = np.arange(Ke.shape[0])
    per = Ke.shape[1]  # 4: nodes 0, 1 of each element; 6: nodes 0, 1, 2 (the middle one inside)
    step = per // 2 - 1
    first = 2 * step * e
    dofs = first[:, None] + np.arange(per)[None, :]
    rows = np.repeat(dofs, per, axis=1).ravel()
    cols = np.tile(dofs, (1, per)).ravel()
    n = 2 * (step * e.size + 1)
    K = sp.csr_matrix((Ke.ravel(), (rows, cols)), shape=(n, n))
    M = sp.csr_matrix((Me.ravel(), (rows, cols)), shape=(n, n))
    return K, M, np.arange(2, n)  # the root node's w and theta clamped


def _stations(length_m: float, n_elements: int, stations_m) -> np.ndarray:
    if stations_m is None:
        L = _check_length(length_m)
        return np.linspace(0.0, L, _check_count("n_elements", n_elements) + 1)
    xs = np.asarray(stations_m, dtype=float)
    if (xs.ndim != 1 or xs.size < 2 or not np.all(np.isfinite(xs)) or xs[0] != 0.0
            or np.any(np.diff(xs) <= 0.0)):
        raise BeamInputError(f"stations_m = {np.ravel(xs)[:6].tolist()}...: must be finite, "
                             "strictly ascending from 0 m, at least 2 entries")
    return xs


def _check_length(length_m) -> float:
    if not isinstance(length_m, (int, float, np.floating)) or isinstance(length_m, bool):
        raise InputTypeError(f"length_m = {length_m!r}: must be a number in m")
    if not (np.isfinite(length_m) and length_m > 0.0):
        raise BeamInputError(f"length_m = {length_m!r}: must be finite and > 0 m")
    return float(length_m)


def timoshenko_modal(length_m: float, EI_Nm2, kappaGA_N, rhoA_kg_m, rhoI_kg_m,
                     n_modes: int = 5, n_elements: int = 100,
                     stations_m: np.ndarray | None = None,
                     element: str = "quadratic") -> TimoshenkoModes:
    """Bending modes of the clamped-free Timoshenko beam with section laws along x.

    Parameters
    ----------
    length_m : float
        Length L, m (ignored when ``stations_m`` is given: its last entry is L).
    EI_Nm2, kappaGA_N, rhoA_kg_m, rhoI_kg_m
        Bending stiffness (N m^2), shear stiffness (N), mass per length (kg/m) and rotary
        inertia per length (kg m): each a number, a callable of x (m) or a pair
        (stations_m, values) linear between stations (:func:`section_law`).
    n_modes : int
        Number of modes, lowest first.
    n_elements : int
        Equal elements along the span (without ``stations_m``).
    stations_m : array_like, optional
        Element edges, m, strictly ascending from 0 to L; put every kink or jump of a law on an
        edge.
    element : {"quadratic", "interdependent"}
        The three-node element with reduced shear integration (default), or Friedman &
        Kosmatka's two-node element (a cross-check: its frequencies converge like h^2 only).

    Returns
    -------
    TimoshenkoModes
    """
    laws = SectionLaws.of(EI_Nm2, kappaGA_N, rhoA_kg_m, rhoI_kg_m)
    return _modal(_stations(length_m, n_elements, stations_m), laws,
                  _check_count("n_modes", n_modes), _check_element(element))


def _check_element(element) -> str:
    if element not in ELEMENTS:
        raise BeamInputError(f"element = {element!r}: must be one of {ELEMENTS}")
    return element


def _nodes(xs: np.ndarray, element: str) -> np.ndarray:
    if element == "interdependent":
        return xs.copy()
    out = np.empty(2 * xs.size - 1)
    out[0::2] = xs
    out[1::2] = 0.5 * (xs[:-1] + xs[1:])
    return out


def _modal(xs: np.ndarray, laws: SectionLaws, n_modes: int, element: str) -> TimoshenkoModes:
    t0 = time.perf_counter()
    K, M, free = _assemble(xs, laws, element)
    t1 = time.perf_counter()
    lam, vec = _eigh(K, M, free, n_modes)
    t2 = time.perf_counter()
    phi = np.zeros((K.shape[0], lam.size))
    phi[free] = vec
    phi /= np.sqrt(np.einsum("ij,ij->j", phi, M @ phi))
    phi *= np.where(phi[-2] < 0.0, -1.0, 1.0)
    w, th = phi[0::2].T.copy(), phi[1::2].T.copy()
    for a in (w, th):
        a.setflags(write=False)
    om = np.sqrt(lam)
    om.setflags(write=False)
    x = _nodes(xs, element)
    x.setflags(write=False)
    return TimoshenkoModes(om, x, w, th, int(free.size), Timings(assembly_s=t1 - t0,
                                                                  solve_s=t2 - t1))


def timoshenko_static(length_m: float, EI_Nm2, kappaGA_N, tip_force_N: float,
                      n_elements: int = 100, stations_m: np.ndarray | None = None,
                      element: str = "quadratic") -> TimoshenkoStatic:
    """Linear tip deflection and rotation of the clamped-free Timoshenko beam under a tip force.

    Parameters
    ----------
    length_m : float
        Length L, m.
    EI_Nm2, kappaGA_N
        Bending (N m^2) and shear (N) stiffness laws, as in :func:`timoshenko_modal`.
    tip_force_N : float
        Transverse force at the tip, N.
    n_elements : int
    stations_m : array_like, optional
    element : {"quadratic", "interdependent"}

    Returns
    -------
    TimoshenkoStatic
        For a uniform section w_tip = F L^3 / (3 E I) + F L / (kappa G A): to rounding with the
        interdependent element (its shape functions solve the static equations), to the
        discretisation error (h^2) with the quadratic one.
    """
    import scipy.linalg

    if not isinstance(tip_force_N, (int, float, np.floating)) or isinstance(tip_force_N, bool):
        raise InputTypeError(f"tip_force_N = {tip_force_N!r}: must be a number in N")
    if not np.isfinite(tip_force_N):
        raise BeamInputError(f"tip_force_N = {tip_force_N!r}: must be finite")
    # the mass laws do not enter the statics: unit placeholders
    laws = SectionLaws.of(EI_Nm2, kappaGA_N, 1.0, 1.0)
    xs = _stations(length_m, n_elements, stations_m)
    K, _, free = _assemble(xs, laws, _check_element(element))
    f = np.zeros(K.shape[0])
    f[-2] = float(tip_force_N)
    u = np.zeros(K.shape[0])
    u[free] = scipy.linalg.solve(K[free][:, free].toarray(), f[free], assume_a="pos")
    return TimoshenkoStatic(float(tip_force_N), float(u[-2]), float(u[-1]))


def beam_timoshenko_modal(beam: Beam, n_modes: int = 5, n_elements: int = 200,
                          element: str = "quadratic") -> TimoshenkoModes:
    """Timoshenko modes of a planform beam (rectangle b(x) = 2 w(x) by t(x), bending about y).

    The element edges are those of the Euler-Bernoulli truth (:func:`beam_stations`: every
    planform vertex an edge), so the two theories are compared on the same mesh.

    Parameters
    ----------
    beam : Beam
    n_modes : int
    n_elements : int
        About this many elements along the span.
    element : {"quadratic", "interdependent"}

    Returns
    -------
    TimoshenkoModes
    """
    laws = rectangle_section_laws(beam)
    return _modal(beam_stations(beam, n_elements), laws, _check_count("n_modes", n_modes),
                  _check_element(element))
