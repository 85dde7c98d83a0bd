"""The 1D beam truth in gravity: self-weight prestress, the small sag, and the modes about it.

The Hermite beam of :mod:`prbdm_pin.truth.beam` with the member's own weight (module notes of
:mod:`prbdm_pin.truth.self_weight` for the axes):

* the axial component g_x prestresses the member, N(x) = g_x m_out(x) (+ a tip force F_x):
  tension when it hangs from its root (g_x > 0), compression when it stands on it (g_x < 0).
  The geometric stiffness ``K_g = int N w' v' dx`` joins the bending stiffness, so

      EI w'''' - (N(x) w')' + rho A w_tt = 0;

  a standing member buckles under its own weight when the lowest eigenvalue of K + K_g reaches
  zero (a uniform column at rho A g L^3 / EI = 7.837, Greenhill);
* the transverse component g_z loads it with q = rho A g_z: the consistent load vector is
  g_z M r_z, M the mass matrix and r_z the rigid z translation (which the Hermite basis holds
  exactly), so no second mass formula is written here.

The sag is the linear one, (K + K_g) u = f; the frequencies are those of K + K_g and M about the
straight member: to first order in the sag they are the frequencies about it. A large sag's tip
is the elastica's (:mod:`prbdm_pin.truth.elastica` with ``gravity_m_s2``) and the frequencies
about it :mod:`prbdm_pin.truth.elastica_modes`'.
"""

from __future__ import annotations

import time

import numpy as np
import scipy.linalg
from skfem import BilinearForm, asm
from skfem.helpers import d

from ..errors import BeamInputError, InputTypeError, SolveError
from ..member.geometry import Beam
from .beam import DENSE_MAX_DOFS, _assemble, _check_count, _eigh, beam_modal_solution
from .result import ModalSolution, StaticSolution, Timings
from .self_weight import check_gravity, outboard_mass_kg

__all__ = ["beam_gravity_modal", "beam_gravity_static", "beam_self_weight_buckling"]


@BilinearForm
def _geometric(u, v, w):
    return w["N"] * d(u)[0] * d(v)[0]


def _gravity_system(beam: Beam, g: np.ndarray, F: np.ndarray, n_elements: int):
    """Assemble the Hermite system with the prestress and load of gravity ``g``, tip force ``F``.

    Returns (mesh, basis, K, K_g, M, u_dofs, free, f), ``f`` the load vector (N; N m on the
    slope DOFs); K_g apart, as K + K_g - K would lose it to rounding when it is small.
    """
    mesh, basis, K, M, u_dofs, free = _assemble(beam, n_elements)
    xq = basis.global_coordinates()[0]
    # N(x) at the quadrature points: quadratic on a tapered element, within the quadrature's
    # exact degree with the two slopes (2 + 2 + 2 <= 7)
    N = g[0] * outboard_mass_kg(beam, xq) + F[0]
    Kg = asm(_geometric, basis, N=N)
    r_z = np.zeros(basis.N)
    r_z[u_dofs] = 1.0
    f = g[2] * (M @ r_z)
    tip = int(np.argmax(mesh.p[0]))
    f[basis.nodal_dofs[0, tip]] += F[2]
    return mesh, basis, K, Kg, M, u_dofs, free, f


def _check_beam(beam) -> None:
    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r:.60}: must be a prbdm_pin.Beam")


def _tip_force(beam: Beam, tip_force_N) -> np.ndarray:
    F = np.asarray(np.zeros(3) if tip_force_N is None else tip_force_N, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force_N = {np.asarray(F).tolist()}: must be 3 finite "
                             "numbers in N")
    return F


def beam_gravity_modal(beam: Beam, gravity_m_s2, n_modes: int = 10, n_elements: int = 200,
                       tip_force_N=None) -> ModalSolution:
    """Bending modes of the 1D beam prestressed by its own weight (and a dead tip force).

    Parameters
    ----------
    beam : Beam
    gravity_m_s2 : array_like, shape (3,)
        Gravity, m/s^2, member axes (g_y must be 0); g_x > 0 hangs the member, g_x < 0 stands
        it on its root.
    n_modes : int
        Number of modes (lowest first).
    n_elements : int
        About this many Hermite elements along the span.
    tip_force_N : array_like, shape (3,), optional
        A dead tip force, N (default none): F_x adds to the prestress.

    Returns
    -------
    ModalSolution
        As :func:`prbdm_pin.truth.beam.beam_modal`'s, of K + K_g; frequencies in rad/s.

    Raises
    ------
    BeamInputError
        A bad gravity or force (naming it), or a member that buckles under the prestress.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> still = pp.beam_gravity_modal(beam, [0.0, 0.0, 0.0], n_modes=2, n_elements=50)
    >>> EI, rho_A = 205e9 * 0.05 * 0.01**3 / 12, 7850.0 * 0.05 * 0.01  # N m^2, kg/m
    >>> eb = np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)  # rad/s, Euler-Bernoulli
    >>> still.omega_rad_s.round(2), eb.round(2)
    (array([ 51.87, 325.05]), array([ 51.87, 325.05]))
    >>> hanging = pp.beam_gravity_modal(beam, [9.81, 0.0, 0.0], n_modes=2, n_elements=50)
    >>> standing = pp.beam_gravity_modal(beam, [-9.81, 0.0, 0.0], n_modes=2, n_elements=50)
    >>> bool(np.all(hanging.omega_rad_s > still.omega_rad_s))  # tension stiffens
    True
    >>> bool(np.all(standing.omega_rad_s < still.omega_rad_s))  # compression softens
    True
    >>> round(float(hanging.omega_rad_s[0] / still.omega_rad_s[0] - 1) * 100, 2)  # %, hanging
    0.29
    >>> # first order in g (Rayleigh): omega^2 grows by g int (L - x) phi'^2 / int phi^2, phi the
    >>> # Euler-Bernoulli mode; the tension rho A g (L - x) divided by rho A
    >>> x, b = np.linspace(0.0, 1.0, 2001), 1.8751041
    >>> s = (np.sinh(b) - np.sin(b)) / (np.cosh(b) + np.cos(b))
    >>> phi = np.cosh(b * x) - np.cos(b * x) - s * (np.sinh(b * x) - np.sin(b * x))
    >>> def integral(f):  # the trapezoid rule on x
    ...     return float(np.sum(f[1:] + f[:-1]) / 2 * (x[1] - x[0]))
    >>> d_w2 = 9.81 * integral((1 - x) * np.gradient(phi, x)**2) / integral(phi**2)  # rad^2/s^2
    >>> round(100 * float(np.sqrt(eb[0]**2 + d_w2) / eb[0] - 1), 2)  # %
    0.29
    """
    _check_beam(beam)
    g = check_gravity(gravity_m_s2)
    F = _tip_force(beam, tip_force_N)
    n_modes = _check_count("n_modes", n_modes)
    t0 = time.perf_counter()
    mesh, basis, K, Kg, M, u_dofs, free, _ = _gravity_system(beam, g, F, n_elements)
    K = K + Kg
    t1 = time.perf_counter()
    try:
        lam, vec = _eigh(K, M, free, n_modes, DENSE_MAX_DOFS)
    except (SolveError, np.linalg.LinAlgError):
        raise BeamInputError(_buckled_text(beam, g, n_elements)) from None
    phi = np.zeros((basis.N, lam.size))
    phi[free] = vec
    timings = Timings(assembly_s=t1 - t0, solve_s=time.perf_counter() - t1)
    return beam_modal_solution(beam, mesh, basis, K, M, u_dofs, free, lam, phi, timings)


def beam_gravity_static(beam: Beam, gravity_m_s2, tip_force_N=None,
                        n_elements: int = 200) -> StaticSolution:
    """Linear sag of the 1D beam under its own weight (and a dead tip force).

    Parameters
    ----------
    beam : Beam
    gravity_m_s2 : array_like, shape (3,)
        Gravity, m/s^2, member axes (g_y must be 0).
    tip_force_N : array_like, shape (3,), optional
        A dead tip force, N (default none).
    n_elements : int

    Returns
    -------
    StaticSolution
        Tip position (L, 0, w_tip) and displacement (0, 0, w_tip), m: a uniform cantilever
        sags q L^4 / (8 EI) under q = rho A g_z; g_x stiffens (hanging) or softens (standing)
        it through the prestress.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> sag = pp.beam_gravity_static(beam, [0.0, 0.0, -9.81], n_elements=20)
    >>> q, EI = 7850.0 * 0.05 * 0.01 * 9.81, 205e9 * 0.05 * 0.01**3 / 12  # N/m, N m^2
    >>> round(float(sag.tip_displacement_m[2]) * 1e3, 4), round(-q / (8 * EI) * 1e3, 4)  # mm, L = 1
    (-5.6348, -5.6348)
    """
    _check_beam(beam)
    g = check_gravity(gravity_m_s2)
    F = _tip_force(beam, tip_force_N)
    t0 = time.perf_counter()
    mesh, basis, K, Kg, M, u_dofs, free, f = _gravity_system(beam, g, F, n_elements)
    K = K + Kg
    t1 = time.perf_counter()
    u = np.zeros(basis.N)
    try:
        u[free] = scipy.linalg.solve(K[free][:, free].toarray(), f[free], assume_a="pos")
    except np.linalg.LinAlgError:
        raise BeamInputError(_buckled_text(beam, g, n_elements)) from None
    tip = int(np.argmax(mesh.p[0]))
    disp = np.array([0.0, 0.0, u[basis.nodal_dofs[0, tip]]])
    return StaticSolution(
        model="beam", nonlinear=False, tip_force_N=F.copy(),
        tip_position_m=np.array([beam.length_m, 0.0, 0.0]) + disp, tip_displacement_m=disp,
        dofs=int(free.size), mesh_level=int(mesh.t.shape[1]),
        timings=Timings(assembly_s=t1 - t0, solve_s=time.perf_counter() - t1))


def beam_self_weight_buckling(beam: Beam, n_elements: int = 200) -> float:
    """Return the gravity (m/s^2, along -x) at which the member standing on its root buckles.

    The smallest lambda of K phi = lambda (-K_g1) phi, K_g1 the geometric stiffness of a unit
    standing gravity (g = (-1, 0, 0) m/s^2).

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> g_cr = pp.beam_self_weight_buckling(beam, n_elements=50)  # m/s^2
    >>> EI, rho_A = 205e9 * 0.05 * 0.01**3 / 12, 7850.0 * 0.05 * 0.01  # N m^2, kg/m
    >>> round(g_cr, 1), round(7.8373 * EI / (rho_A * 1.0**3), 1)  # Greenhill: q L^3 / EI = 7.8373
    (1705.6, 1705.6)
    """
    _check_beam(beam)
    _, _, K, Kg1, _, _, free, _ = _gravity_system(beam, np.array([-1.0, 0.0, 0.0]),
                                                  np.zeros(3), n_elements)
    Kf = K[free][:, free].toarray()
    Gf = -Kg1[free][:, free].toarray()  # positive semi-definite
    # the largest mu of Gf phi = mu K phi is 1 / lambda_min (K is positive definite)
    mu = scipy.linalg.eigh(Gf, Kf, eigvals_only=True, subset_by_index=[free.size - 1] * 2)
    return float(1.0 / mu[0])


def _buckled_text(beam: Beam, g: np.ndarray, n_elements: int) -> str:
    g_cr = beam_self_weight_buckling(beam, n_elements)
    return (f"gravity_m_s2 = {g.tolist()}: the member standing on its root buckles under its "
            f"own weight (g_x <= -{g_cr:.4g} m/s^2 for {beam.name!r}); the 1D truth has no "
            "equilibrium about the straight member there")
