"""Mode classification and selection: z mass participation, symmetry, MAC with beam modes.

A chain of rigid links bending about y can only represent modes that are symmetric about the
x axis and whose shape along the axis looks like a beam's. Two policies pick "the first N bending
modes": ``paper`` (the N modes of largest z mass participation, ascending in frequency, as the
paper did with COMSOL) and ``shape`` (symmetric modes whose best MAC with a 1D beam bending mode
is at least ``MAC_BEAM_LIKE``).
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from ..member.geometry import Beam
from .result import ModalSolution
from .settings import SELECTIONS

__all__ = [
    "MAC_BEAM_LIKE",
    "IN_PLANE_Z_ENERGY",
    "AXIAL_X_ENERGY",
    "SELECTIONS",
    "mac_matrix",
    "mass_participation_z",
    "symmetry_about_x",
    "beam_mac",
    "width_variation",
    "label_modes",
    "select_modes",
    "selection_warnings",
]

MAC_BEAM_LIKE = 0.8
# ||u - u_c|| / ||u|| > 1 means extruding the centreline shape across the width fits the mode worse
# than zero: the cross-sections move mostly against the axis (a nodal line along x), i.e.
# chordwise bending. Measured: bending modes 0.00-0.77 (second bending of the square plate 0.47),
# chordwise modes 1.1-1.6.
WIDTH_VARIATION_CHORDWISE = 1.0
# below this share of kinetic energy in z motion a mode moves mainly in plane (bending and torsion
# modes of thin panels: above 0.99)
IN_PLANE_Z_ENERGY = 0.5
# of the in-plane modes, those with most of their kinetic energy in x motion extend the member
# (the narrow strip's first: x share 1.00; its first four in-plane bending modes: 0.001-0.025)
AXIAL_X_ENERGY = 0.5


def mac_matrix(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Modal assurance criterion between the rows of ``a`` (k, s) and of ``b`` (m, s): (k, m)."""
    a = np.atleast_2d(a)
    b = np.atleast_2d(b)
    num = (a @ b.T) ** 2
    den = np.outer(np.einsum("ij,ij->i", a, a), np.einsum("ij,ij->i", b, b))
    return num / np.where(den > 0.0, den, np.inf)


def mass_participation_z(M, phi: np.ndarray, r_z: np.ndarray) -> np.ndarray:
    """Return the z mass participation (phi^T M r_z)^2 / (phi^T M phi) of each column, kg."""
    Mphi = M @ phi
    return (r_z @ Mphi) ** 2 / np.einsum("ij,ij->j", phi, Mphi)


def _mirror_index(xy: np.ndarray, tol: float) -> np.ndarray:
    key = np.round(xy / tol).astype(np.int64)
    lookup = {(int(kx), int(ky)): i for i, (kx, ky) in enumerate(key)}
    out = np.full(xy.shape[0], -1, dtype=np.int64)
    for i, (kx, ky) in enumerate(key):
        out[i] = lookup.get((int(kx), int(-ky)), -1)
    return out


def symmetry_about_x(nodes_m: np.ndarray, node_uz: np.ndarray) -> np.ndarray:
    """Signed symmetry of every mode about the x axis, in [-1, 1].

    +1: u(x, -y) = u(x, y) (symmetric); -1: antisymmetric. Computed over the nodes whose mirror
    image is also a node (the planform meshes are mirror-symmetric).

    Parameters
    ----------
    nodes_m : ndarray, shape (N, 2 or 3)
    node_uz : ndarray, shape (k, N)
    """
    xy = np.asarray(nodes_m)[:, :2]
    span = float(np.ptp(xy[:, 0])) or 1.0
    mirror = _mirror_index(xy, 1e-9 * span)
    ok = mirror >= 0
    if not ok.any():
        raise ValueError("no node has a mirror image about y = 0: cannot judge symmetry")
    u = np.atleast_2d(node_uz)[:, ok]
    um = np.atleast_2d(node_uz)[:, mirror[ok]]
    return np.einsum("ij,ij->i", u, um) / np.maximum(np.einsum("ij,ij->i", u, u), 1e-300)


def beam_mac(
    beam: Beam, centerline_x_m: np.ndarray, centerline_uz: np.ndarray, n_beam_modes: int = 8
) -> tuple[np.ndarray, np.ndarray]:
    """Best MAC of every mode's centreline z displacement with a 1D beam bending mode.

    Returns
    -------
    mac : ndarray, shape (k,)
    index : ndarray of int, shape (k,)
        0-based index of the best-matching beam mode.
    """
    from .beam import beam_bending_modes

    x = np.asarray(centerline_x_m, dtype=float)
    _, shapes = beam_bending_modes(beam, x, n_beam_modes)
    # weight by station spacing so graded (non-uniform) stations do not bias the correlation
    wts = np.sqrt(np.gradient(x)) if x.size > 1 else np.ones(1)
    m = mac_matrix(np.atleast_2d(centerline_uz) * wts, shapes * wts)
    return m.max(axis=1), m.argmax(axis=1)


def width_variation(
    nodes_m: np.ndarray, node_uz: np.ndarray, centerline_x_m: np.ndarray, centerline_uz: np.ndarray
) -> np.ndarray:
    """Each mode's nodal misfit by its centreline shape extruded across the width (>= 0).

    A beam-like mode moves every cross-section rigidly, u(x, y) = u(x, 0); a chordwise or torsion
    mode varies across the width. Value: ||u - u_c(x)|| / ||u|| over the nodes (0 for a beam-like
    mode, 1 for torsion, above 1 for chordwise bending).
    """
    x = np.asarray(nodes_m)[:, 0]
    u = np.atleast_2d(node_uz)
    uc = np.array([np.interp(x, centerline_x_m, c) for c in np.atleast_2d(centerline_uz)])
    return np.linalg.norm(u - uc, axis=1) / np.maximum(np.linalg.norm(u, axis=1), 1e-300)


def label_modes(modal: ModalSolution) -> tuple[str, ...]:
    """Label every mode: bending, torsion, chordwise, mixed, in-plane or axial.

    ``in-plane``: less than half of the kinetic energy in z motion (the 3D solid's membrane
    modes, which a plate model does not have); of those, ``axial``: more than half of it in x
    motion (extension, where the model reports that share). ``torsion``: antisymmetric about x.
    ``bending``: symmetric, beam-like along the axis (MAC >= 0.8) and nearly uniform across the
    width. ``chordwise``: symmetric with a large variation across the width. ``mixed``:
    symmetric, uniform across the width, but not beam-like along the axis (jagged panels).
    A model that names the family of every mode (``modal.kinds``: the 1D beam's bending,
    torsion and in-plane modes) keeps its names.
    """
    k = modal.omega_rad_s.size
    if modal.kinds is not None:  # a model that solved the families apart names them
        return tuple(modal.kinds)
    if modal.model == "beam" or modal.nodes_m is None or modal.node_uz is None:
        return ("bending",) * k
    wv = width_variation(modal.nodes_m, modal.node_uz, modal.centerline_x_m, modal.centerline_uz)
    ez = modal.z_energy_fraction
    ex = modal.x_energy_fraction
    labels = []
    for i in range(k):
        if ez is not None and ez[i] < IN_PLANE_Z_ENERGY:
            axial = ex is not None and ex[i] > AXIAL_X_ENERGY
            labels.append("axial" if axial else "in-plane")
        elif not modal.symmetric[i]:
            labels.append("torsion")
        elif wv[i] > WIDTH_VARIATION_CHORDWISE:
            labels.append("chordwise")
        elif modal.mac_beam[i] >= MAC_BEAM_LIKE:
            labels.append("bending")
        else:
            labels.append("mixed")
    return tuple(labels)


def select_modes(modal: ModalSolution, n_modes: int, selection: str = "paper") -> np.ndarray:
    """Return indices (ascending in frequency) of the ``n_modes`` bending modes under a policy.

    Parameters
    ----------
    modal : ModalSolution
    n_modes : int
    selection : {"paper", "shape"}
        ``paper``: the ``n_modes`` modes with the largest z mass participation, ascending.
        ``shape``: the lowest ``n_modes`` modes labelled ``bending``: symmetric, best beam MAC
        >= 0.8 and not chordwise (MAC on the axis alone accepts the square plate's chordwise
        mode 4 at 0.85, which a chain cannot represent).

    Raises
    ------
    BeamInputError
        Unknown policy or non-positive count.
    ValueError
        Fewer qualifying modes were computed than asked for (compute more modes).
    """
    if selection not in SELECTIONS:
        raise BeamInputError(f"selection = {selection!r}: must be one of {SELECTIONS}")
    if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) or n_modes < 1:
        raise BeamInputError(f"modes = {n_modes!r}: must be an integer >= 1")
    k = modal.omega_rad_s.size
    if selection == "paper":
        if n_modes > k:
            raise ValueError(f"{n_modes} modes asked for, only {k} computed")
        idx = np.argsort(-np.asarray(modal.mpf_z), kind="stable")[:n_modes]
        return np.sort(idx)
    ok = np.flatnonzero(np.array(label_modes(modal)) == "bending")
    if ok.size < n_modes:
        raise ValueError(
            f"only {ok.size} of {k} computed modes are beam-like bending modes (symmetric, "
            f"MAC >= {MAC_BEAM_LIKE}, not chordwise); {n_modes} asked for"
        )
    return ok[:n_modes]


def selection_warnings(modal: ModalSolution, index: np.ndarray, labels: tuple[str, ...]) -> tuple:
    """Warnings for selected modes a chain of rigid links cannot represent."""
    out = []
    for rank, i in enumerate(index, start=1):
        if labels[i] != "bending":
            out.append(
                f"selected mode {rank} (mode {i + 1}, {modal.omega_rad_s[i]:.6g} rad/s) is "
                f"{labels[i]}, not beam-like: MAC with the best beam mode "
                f"{modal.mac_beam[i]:.2f}, z participation {modal.mpf_z_fraction[i]:.3g}"
            )
    # the policy cannot know whether a not-computed mode would have ranked higher
    if modal.mpf_z_fraction.sum() < 0.8:
        out.append(
            f"the computed modes hold only {modal.mpf_z_fraction.sum():.0%} of the z mass: "
            "compute more modes to be sure the selection is complete"
        )
    return tuple(out)
