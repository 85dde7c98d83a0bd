"""1D Timoshenko truth: clamped-free bending in a plane with shear deformation and rotary inertia.

Two locking-free elements (DOFs per node: deflection w, m, and section rotation theta, rad):

- ``"quadratic"`` (default): three-node Lagrange w and theta, bending and mass at 6 Gauss points,
  shear at the 2 reduced points, where the quadratic theta is replaced by its linear projection,
  the space of dw/dx: pure bending costs no shear energy at any slenderness (Prathap & Bhashyam
  1982). Its frequencies converge like h^4 (the ratio of errors at h and h/2 is 16, measured on
  the uniform cantilever at L / r_g = 10 ... 1000), so 40 elements give mode 4 to 1.2e-5 and
  mode 1 to 1.5e-8 (scripts/bench_timoshenko.py).
- ``"interdependent"``: the two-node element of Friedman & Kosmatka (1993, Computers & Structures
  47, 473-481), cubic w and quadratic theta tied by phi = 12 E I / (kappa G A h^2) so that they
  solve the static equations of a uniform element: its stiffness is exact (the tip under a tip
  force to rounding with one element) and it reduces to the Hermite element of ``beam.py`` as
  phi -> 0, but its consistent mass only gives h^2 convergence of the frequencies of a thick
  beam (the tie between the third derivative of w and theta holds statically, not under inertia
  loading: 3.7e-4 on mode 4 at L / r_g = 10 with 80 elements). It is kept as the cross-check.

Why not linear elements with reduced integration: they converge like h^2 too (one order of the
interpolation less), so the quadratic element reaches a given accuracy with far fewer DOFs.
The price of the quadratic element is rounding on slender members: the shear stiffness
kappa G A is (kappa G / E) (L / r_g)^2 times the bending one, and it costs about 2e-8 of mode 1
at L / r_g = 1000 with 80 elements (where Timoshenko differs from Euler-Bernoulli by 2e-4 % on
mode 1, and the Euler-Bernoulli truth is the one to use).

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
from .timoshenko_elements import ELEMENTS, assemble
from .timoshenko_sections import SectionLaws, member_section_laws

__all__ = ["TimoshenkoModes", "TimoshenkoStatic", "timoshenko_modal", "timoshenko_static",
           "beam_timoshenko_modal", "beam_timoshenko_static"]

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
        Deflection w of each mode at the nodes (element ends and, for the quadratic element,
        middles), scaled so that phi^T M phi = 1 with M the consistent mass matrix, sign such
        that the tip deflection is >= 0.
    rotation_rad : ndarray, shape (k, n)
        Section rotation theta of each mode at the nodes, same scale.
    dofs : int
        Free DOFs.
    timings : Timings

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> modes = pp.beam_timoshenko_modal(beam, n_modes=2, n_elements=10)
    >>> isinstance(modes, pp.TimoshenkoModes), modes.x_m.shape, modes.deflection_m.shape
    (True, (21,), (2, 21))
    >>> modes.dofs, bool(np.all(modes.deflection_m[:, -1] >= 0))  # 2 per node but the clamp's
    (40, True)
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

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> tip = pp.beam_timoshenko_static(beam, [0.0, 0.0, -10.0], n_elements=20)
    >>> isinstance(tip, pp.TimoshenkoStatic), tip.tip_force_N  # N
    (True, -10.0)
    >>> EI = 205e9 * 0.05 * 0.01**3 / 12  # N m^2
    >>> round(tip.tip_rotation_rad, 5), round(-10.0 * 1.0**2 / (2 * EI), 5)  # rad: F L^2 / (2 EI)
    (-0.00585, -0.00585)
    """

    tip_force_N: float
    tip_deflection_m: float
    tip_rotation_rad: float


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


def timoshenko_modal(sections: SectionLaws, length_m: float, n_modes: int = 5,
                     n_elements: int = 100, stations_m: np.ndarray | None = None,
                     element: str = "quadratic") -> TimoshenkoModes:
    """Bending modes of the clamped-free Timoshenko beam with section laws along x.

    Parameters
    ----------
    sections : SectionLaws
        Bending stiffness (N m^2), shear stiffness (N), mass per length (kg/m) and rotary
        inertia per length (kg m) along x.
    length_m : float
        Length L, m (ignored when ``stations_m`` is given: its last entry is L).
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

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> EI, rho_A = 854.17, 3.925  # N m^2, kg/m: a slender steel strip, L = 1 m
    >>> stiff = pp.SectionLaws(EI_Nm2=EI, kappaGA_N=1e12, rhoA_kg_m=rho_A, rhoI_kg_m=1e-12)
    >>> modes = pp.timoshenko_modal(stiff, 1.0, n_modes=2, n_elements=40)
    >>> modes.omega_rad_s.round(2)  # rad/s: no shear, no rotary inertia: Euler-Bernoulli
    array([ 51.87, 325.05])
    >>> (np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)).round(2)
    array([ 51.87, 325.05])
    >>> soft = pp.SectionLaws(EI_Nm2=EI, kappaGA_N=1e5, rhoA_kg_m=rho_A, rhoI_kg_m=1e-12)
    >>> bool(np.all(pp.timoshenko_modal(soft, 1.0, 2, 40).omega_rad_s < modes.omega_rad_s))
    True
    """
    return _modal(_stations(length_m, n_elements, stations_m), _check_sections(sections),
                  _check_count("n_modes", n_modes), _check_element(element))


def _check_sections(sections) -> SectionLaws:
    if not isinstance(sections, SectionLaws):
        raise InputTypeError(f"sections = {sections!r}: must be a prbdm_pin.SectionLaws")
    return sections


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
    K, M, free = assemble(xs, laws, element)
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


def timoshenko_static(sections: SectionLaws, length_m: float, tip_force_N: float,
                      n_elements: int = 100, stations_m: np.ndarray | None = None,
                      element: str = "quadratic") -> TimoshenkoStatic:
    """Linear tip deflection and rotation of the clamped-free Timoshenko beam under a tip force.

    Parameters
    ----------
    sections : SectionLaws
        Only the stiffness laws enter.
    length_m : float
        Length L, m.
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

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> laws = pp.SectionLaws(EI_Nm2=1e4, kappaGA_N=1e5, rhoA_kg_m=10.0, rhoI_kg_m=0.01)
    >>> tip = pp.timoshenko_static(laws, 1.0, tip_force_N=100.0, n_elements=20)
    >>> F, L = 100.0, 1.0  # N, m
    >>> round(tip.tip_deflection_m * 1e3, 4), round((F * L**3 / (3 * 1e4) + F * L / 1e5) * 1e3, 4)
    (4.3333, 4.3333)
    >>> round(tip.tip_rotation_rad * 1e3, 4), round(F * L**2 / (2 * 1e4) * 1e3, 4)  # mrad
    (5.0, 5.0)
    """
    import scipy.linalg

    if not isinstance(tip_force_N, (int, float, np.floating)) or isinstance(tip_force_N, bool):
        raise InputTypeError(f"tip_force_N = {tip_force_N!r}: must be a number in N")
    if not np.isfinite(tip_force_N):
        raise BeamInputError(f"tip_force_N = {tip_force_N!r}: must be finite")
    laws = _check_sections(sections)
    xs = _stations(length_m, n_elements, stations_m)
    K, _, free = assemble(xs, laws, _check_element(element))
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

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> modes = pp.beam_timoshenko_modal(beam, n_modes=2, n_elements=40)
    >>> EI, rho_A = 205e9 * 0.05 * 0.01**3 / 12, 7850.0 * 0.05 * 0.01  # N m^2, kg/m
    >>> eb = np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)  # rad/s, Euler-Bernoulli
    >>> modes.omega_rad_s.round(1), eb.round(1)
    (array([ 51.9, 324.9]), array([ 51.9, 325.1]))
    >>> (100 * (modes.omega_rad_s / eb - 1)).round(3)  # %: shear and rotary inertia lower them
    array([-0.008, -0.054])
    """
    laws = member_section_laws(beam)
    return _modal(beam_stations(beam, n_elements), laws, _check_count("n_modes", n_modes),
                  _check_element(element))


def beam_timoshenko_static(beam: Beam, tip_force_N: np.ndarray | None = None,
                           n_elements: int = 200) -> TimoshenkoStatic:
    """Linear Timoshenko tip deflection of a planform beam under the z component of a tip force.

    Parameters
    ----------
    beam : Beam
    tip_force_N : array_like, shape (3,), optional
        Tip force in N (default: ``beam.tip_force_N``); only F_z bends the beam here, as in
        :func:`~prbdm_pin.truth.beam_static.beam_static`.
    n_elements : int
        About this many elements along the span (the planform's vertices are edges).

    Returns
    -------
    TimoshenkoStatic
        The tip's z deflection (m) and rotation about y (rad, positive with a positive slope).

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> tip = pp.beam_timoshenko_static(beam, [0.0, 0.0, -10.0], n_elements=20)
    >>> EI = 205e9 * 0.05 * 0.01**3 / 12  # N m^2
    >>> kGA = 10 * 1.28 / (12 + 11 * 0.28) * 205e9 / 2.56 * 0.05 * 0.01  # N: Cowper's rectangle
    >>> round(tip.tip_deflection_m * 1e3, 3), round(-10.0 * (1 / (3 * EI) + 1 / kGA) * 1e3, 3)  # mm
    (-3.903, -3.903)
    """
    laws = member_section_laws(beam)
    F = np.asarray(beam.tip_force_N if tip_force_N is None else tip_force_N, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force_N = {F.tolist()}: must be 3 finite numbers in N")
    return timoshenko_static(laws, beam.length_m, float(F[2]),
                             stations_m=beam_stations(beam, n_elements))
