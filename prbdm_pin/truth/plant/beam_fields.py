"""The clamped 1D Euler-Bernoulli truth's modes as full Hermite DOF vectors, with slopes anywhere.

``truth.beam`` keeps its assembly to itself and hands out sampled shapes only; the plant needs
deflections and slopes of exactly the modes the truth computed. They are assembled here from the
same stations (``beam_stations``), element (cubic Hermite), quadrature and sections, and
``truth_modal_gains`` refuses them unless their frequencies and shapes are the truth's.
(The truth's own modules stay untouched, so the truth's code digest and cache keys do not move.)
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from skfem import Basis, BilinearForm, ElementLineHermite, MeshLine, asm
from skfem.helpers import dd

from ...errors import SolveError
from ...geometry import Beam
from ..beam import beam_stations
from .fields import ModeFields, section_rotation_sign

__all__ = ["BEAM_ELEMENTS", "beam_mode_fields", "hermite_slope"]

# the 1D truth's default element count (beam_modal, beam_static)
BEAM_ELEMENTS = 200
# w(x) linear, Hermite cubic: the mass integrand has degree 7 (as in truth.beam)
_INTORDER = 7


@BilinearForm
def _stiffness(u, v, w):
    return w["EI"] * dd(u)[0, 0] * dd(v)[0, 0]


@BilinearForm
def _mass(u, v, w):
    return w["rhoA"] * u * v


def hermite_slope(xs: np.ndarray, u: np.ndarray, ux: np.ndarray, x: np.ndarray) -> np.ndarray:
    """du/dx at ``x`` (m) of the cubic Hermite fields with nodal values ``u`` and slopes ``ux``
    (rows: fields) at ascending nodes ``xs`` (m); shape (fields, len(x))."""
    e = np.clip(np.searchsorted(xs, x, side="right") - 1, 0, xs.size - 2)
    h = xs[e + 1] - xs[e]
    s = (x - xs[e]) / h
    d00 = (6 * s**2 - 6 * s) / h
    d10 = 3 * s**2 - 4 * s + 1
    d01 = -d00
    d11 = 3 * s**2 - 2 * s
    return d00 * u[:, e] + d10 * ux[:, e] + d01 * u[:, e + 1] + d11 * ux[:, e + 1]


def beam_mode_fields(beam: Beam, n_modes: int, stations_m: np.ndarray,
                     n_elements: int = BEAM_ELEMENTS) -> ModeFields:
    """Every input, output and inertia term of the 1D truth's ``n_modes`` lowest modes.

    Parameters
    ----------
    beam : Beam
    n_modes : int
        Modes computed (the truth's count; fewer if the mesh has fewer DOFs).
    stations_m : ndarray, shape (a, 2)
        Actuator stations (x_a, x_b) in m, checked by the caller.
    n_elements : int
        As ``beam_modal``'s (the truth uses the default).

    Returns
    -------
    ModeFields
        Tip force acting at, and tip z read at, the tip node (as ``beam_static``).
    """
    xs = beam_stations(beam, n_elements)
    basis = Basis(MeshLine(xs), ElementLineHermite(), intorder=_INTORDER)
    xq = basis.global_coordinates()[0]
    mat = beam.material
    width = 2.0 * beam.half_width_at(xq)
    K = asm(_stiffness, basis, EI=mat.E_Pa * width * beam.thickness_m**3 / 12.0).toarray()
    M = asm(_mass, basis, rhoA=mat.rho_kg_m3 * width * beam.thickness_m).toarray()
    u_dof, ux_dof = basis.nodal_dofs  # MeshLine keeps the ascending order of xs
    free = np.setdiff1d(np.arange(basis.N), basis.nodal_dofs[:, 0])
    n = min(int(n_modes), free.size)
    # the inverse problem M phi = mu K phi, as truth.beam solves it (no rounding of low modes)
    mu, vec = scipy.linalg.eigh(M[np.ix_(free, free)], K[np.ix_(free, free)],
                                subset_by_index=[free.size - n, free.size - 1])
    lam, vec = 1.0 / mu[::-1], vec[:, ::-1]
    if np.any(lam <= 0.0) or not np.all(np.isfinite(lam)):
        raise SolveError(f"beam eigenvalues not positive: min = {lam.min():.3e} (rad/s)^2")
    phi = np.zeros((basis.N, n))
    phi[free] = vec
    phi /= np.sqrt(np.einsum("ij,ij->j", phi, M @ phi))
    u, ux = phi[u_dof].T, phi[ux_dof].T
    st = np.asarray(stations_m, dtype=float).reshape(-1, 2)
    rot = section_rotation_sign() * hermite_slope(xs, u, ux, st.ravel())  # (k, 2a)
    strain = (rot[:, 1::2] - rot[:, 0::2]).T
    r0 = np.zeros(basis.N)
    r0[u_dof] = 1.0  # the field 1: exact in the Hermite space
    r1 = np.zeros(basis.N)
    r1[u_dof], r1[ux_dof] = xs, 1.0  # the field x
    M0, M1 = M @ r0, M @ r1
    return ModeFields(
        model="beam",
        omega_rad_s=np.sqrt(lam),
        node_uz=u,
        tip_force_per_sqrt_kg=u[:, -1].copy(),
        tip_z_per_sqrt_kg=u[:, -1].copy(),
        strain_per_sqrt_kg_m=strain,
        translation_sqrt_kg=M0 @ phi,
        moment_sqrt_kg_m=M1 @ phi,
        mass_kg=float(r0 @ M0),
        first_moment_kg_m=float(r0 @ M1),
        second_moment_kg_m2=float(r1 @ M1),
    )
