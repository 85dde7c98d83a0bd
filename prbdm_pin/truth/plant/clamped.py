"""The clamped truth as a linear plant: its selected modes in modal coordinates.

With mass-normalised modes the coordinates eta_k obey

    eta_k'' + 2 zeta omega_k eta_k' + omega_k^2 eta_k = b_k F_z + sum_i s_ik M_i,
    tip z = sum_k c_k eta_k,

with the modal gains of :func:`truth_modal_gains` (b: tip force, s: strain actuators, c: tip
z). The inputs and outputs carry the PRBDM plant's names (``tip_force_z``, ``strain[i]``;
``tip_z``, ``tip_z_rate``) and its signs, so the two plants compare pair by pair. With
``corners`` (a plate truth) the z forces at the tip corners and the corners' z are inputs and
outputs too (``corner_force_z_left``, ``corner_force_z_right``; ``corner_z_left``,
``corner_z_right``), through the modes' values at the corners; a corner transfer needs the
plate's torsion modes, which are not among the selected (bending) modes: ask for them with
``mode_index`` (:func:`~prbdm_pin.truth.plant.gains.truth_modal_gains`). The modal
damping is the same definition as ``prbdm_pin.linearize(..., damping="modal")`` on a clamped
PRBDM: every mode gets ``damping_ratio``.

``base_accel_z`` (m/s^2, the last input) accelerates the clamp along +z: in the clamp's frame
every mass element feels the d'Alembert force -rho t a dA, so mode k receives
-int rho t phi_k dA per m/s^2 (``translation_sqrt_kg``), and the outputs are then measured
relative to the clamp (the PRBDM plant's ``base_accel_z`` and its base-frame outputs).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ...errors import BeamInputError
from ...io.records import readonly_array as _ro
from ...member.geometry import Beam
from ..result import TruthResult
from .gains import ModalGains, truth_modal_gains

__all__ = ["BASE_INPUT_NAMES", "CLAMPED_OUTPUT_NAMES", "CORNER_INPUT_NAMES",
           "CORNER_OUTPUT_NAMES", "ClampedModel", "clamped_from_gains", "clamped_input_names",
           "clamped_model"]

CLAMPED_OUTPUT_NAMES = ("tip_z", "tip_z_rate")
CORNER_INPUT_NAMES = ("corner_force_z_left", "corner_force_z_right")
CORNER_OUTPUT_NAMES = ("corner_z_left", "corner_z_right")
BASE_INPUT_NAMES = ("base_accel_z",)


def clamped_input_names(n_actuators: int) -> tuple[str, ...]:
    """Return the input names: ``tip_force_z``, ``strain[0..a-1]``."""
    return ("tip_force_z", *(f"strain[{i}]" for i in range(n_actuators)))


@dataclass(frozen=True, eq=False)
class ClampedModel:
    """The clamped modal model as second-order matrices and as a state space.

    Generalised coordinates q = eta (sqrt(kg) m); state x = [q, dq/dt]. Inputs u
    (``input_names``): tip force F_z (N), actuator moments (N m), with corners the corner
    forces (N). Outputs y (``output_names``): tip z (m) and its rate (m/s), with corners the
    corners' z (m).

    Attributes
    ----------
    damping_ratio : float
    mass, stiffness, damping : ndarray, shape (N, N)
        I, diag(omega_k^2) (1/s^2) and diag(2 zeta omega_k) (1/s).
    input_matrix : ndarray, shape (N, 2+a) (4+a with corners)
        Generalised forces per unit input (modal gains).
    output_matrix : ndarray, shape (1, N) (3, N with corners)
        Tip z (and the left and right corners' z) per unit modal coordinate.
    A, B, C, D : ndarray
        dx/dt = A x + B u, y = C x + D u (D = 0).
    frequencies_rad_s : ndarray, shape (N,)
        Clamped natural frequencies, rad/s, ascending.
    input_names, output_names : tuple of str
    """

    damping_ratio: float
    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    input_matrix: np.ndarray
    output_matrix: np.ndarray
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    frequencies_rad_s: np.ndarray
    input_names: tuple[str, ...]
    output_names: tuple[str, ...] = CLAMPED_OUTPUT_NAMES


def _check_zeta(damping_ratio: object) -> float:
    if isinstance(damping_ratio, bool) or not isinstance(
            damping_ratio, (int, float, np.integer, np.floating)) \
            or not (0.0 <= float(damping_ratio) < 1.0):
        raise BeamInputError(f"damping_ratio = {damping_ratio!r}: must be a number in [0, 1)")
    return float(damping_ratio)


def _corner_gains(gains: ModalGains, corners: bool) -> np.ndarray:
    """Return the modes at the two tip corners (2, N), or (0, N) without ``corners``."""
    if not corners:
        return np.zeros((0, np.asarray(gains.omega_rad_s).size))
    if gains.corner_per_sqrt_kg is None:
        raise BeamInputError(f"corners: the {gains.model} truth has no width, so no tip "
                             "corners; use a plate truth")
    return np.asarray(gains.corner_per_sqrt_kg, dtype=float)


def clamped_from_gains(gains: ModalGains, damping_ratio: float = 0.02,
                       corners: bool = False) -> ClampedModel:
    """Return the clamped plant of ``gains`` (see ``clamped_model``).

    Parameters
    ----------
    gains : ModalGains
        The clamped truth's modal gains (``truth_modal_gains``).
    damping_ratio : float
        zeta in [0, 1) of every mode, dimensionless.
    corners : bool
        Add the corner forces and the corners' z (module notes); BeamInputError for a truth
        without width.

    Returns
    -------
    ClampedModel
    """
    zeta = _check_zeta(damping_ratio)
    G = _corner_gains(gains, corners)
    w = np.asarray(gains.omega_rad_s, dtype=float)
    n = w.size
    # the clamp's acceleration: the d'Alembert load -rho t a on every element (module notes)
    Bq = np.column_stack([gains.tip_force_per_sqrt_kg, gains.strain_per_sqrt_kg_m.T, G.T,
                          -np.asarray(gains.translation_sqrt_kg, dtype=float)])
    Cq = np.vstack([np.asarray(gains.tip_z_per_sqrt_kg, dtype=float)[None, :], G])
    K, D = np.diag(w**2), np.diag(2.0 * zeta * w)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -D]])
    B = np.vstack([np.zeros_like(Bq), Bq])  # M = I
    z = np.zeros_like(Cq)
    # rows: tip z, tip z rate, then the corners' z
    C = np.vstack([np.hstack([Cq[:1], z[:1]]), np.hstack([z[:1], Cq[:1]]),
                   np.hstack([Cq[1:], z[1:]])])
    return ClampedModel(
        damping_ratio=zeta, mass=_ro(np.eye(n)), stiffness=_ro(K), damping=_ro(D),
        input_matrix=_ro(Bq), output_matrix=_ro(Cq), A=_ro(A), B=_ro(B), C=_ro(C),
        D=_ro(np.zeros((C.shape[0], Bq.shape[1]))), frequencies_rad_s=_ro(w),
        input_names=clamped_input_names(gains.actuators_m.shape[0])
        + (CORNER_INPUT_NAMES if corners else ()) + BASE_INPUT_NAMES,
        output_names=CLAMPED_OUTPUT_NAMES + (CORNER_OUTPUT_NAMES if corners else ()),
    )


def clamped_model(truth: TruthResult, beam: Beam,
                  actuators: Sequence[tuple[float, float]] = (),
                  damping_ratio: float = 0.02, corners: bool = False,
                  mode_index: Sequence[int] | None = None) -> ClampedModel:
    """Return the clamped truth (its selected modes) as a linear plant.

    Parameters
    ----------
    truth : TruthResult
        A ``"plate"``, ``"plate-morley"`` or ``"beam"`` truth of ``beam``.
    beam : Beam
    actuators : sequence of (x_a, x_b)
        Strain actuators' stations, m (see ``truth_modal_gains``).
    damping_ratio : float
        zeta in [0, 1) of every mode.
    corners : bool
        Add the corner forces and the corners' z (a plate truth; module notes).
    mode_index : sequence of int, optional
        The computed modes in the plant (default the truth's selected ones; see
        ``truth_modal_gains``).

    Returns
    -------
    ClampedModel
    """
    _check_zeta(damping_ratio)  # before the modal solve
    if corners and truth.model == "beam":  # before the modal solve: no width, no corners
        raise BeamInputError("corners: the 1D beam truth has no width, so no tip corners; use "
                             "a plate truth")
    return clamped_from_gains(truth_modal_gains(truth, beam, actuators, mode_index),
                              damping_ratio, corners)
