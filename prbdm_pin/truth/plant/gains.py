"""Modal input and output gains of a clamped truth's selected modes.

Tip force, strain actuators and the tip z output, plus the inertia integrals the hub model
needs.

Sign convention. The PRBDM's joints rotate about +y, which turns e_x towards -z (``planar``:
dz_tip/dq < 0): a positive joint torque bends the tip down. A strain actuator is a moment pair
across the full width, +M about +y on the section at x_b and -M on the section at x_a (a joint
torque spread over [x_a, x_b]); its virtual work on a deflection w is M (psi(x_b) - psi(x_a))
with the section rotation psi = -dw/dx (width-averaged on a plate), so a positive M also bends
the tip down: a uniform cantilever takes the curvature w'' = -M / EI on [x_a, x_b]. Each mode's
sign makes its tip z gain positive (the largest nodal deflection positive if the tip is still).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ...errors import BeamInputError, InputTypeError, TruthError
from ...member.geometry import Beam
from ..modes import mac_matrix
from ..result import TruthResult
from .fields import ModeFields

__all__ = ["FREQUENCY_MATCH_TOL", "MAC_MATCH_MIN", "ModalGains", "check_actuators",
           "truth_modal_gains"]

# the recomputed modes must be the truth's: frequencies within this relative difference (the
# plate's shift-invert Lanczos, started at random, repeats itself to 4e-9 on the stepped strip;
# another mesh level moves a frequency by far more), and shapes with at least this MAC
FREQUENCY_MATCH_TOL = 1e-7
MAC_MATCH_MIN = 0.999
_PLATES = {"plate-argyris": "argyris", "plate-morley": "morley"}


@dataclass(frozen=True, eq=False)
class ModalGains:
    """Input and output gains of the selected clamped modes (mass-normalised, phi^T M phi = 1).

    Attributes
    ----------
    model : str
        The truth's model (``"beam"``, ``"plate-argyris"``, ``"plate-morley"``).
    omega_rad_s : ndarray, shape (N,)
        Clamped natural frequencies of the selected modes, rad/s.
    mode_index : ndarray of int, shape (N,)
        Their indices into the truth's computed modes.
    length_m : float
        Span L; the tip is at x = L.
    actuators_m : ndarray, shape (a, 2)
        Actuator stations (x_a, x_b), m.
    tip_force_per_sqrt_kg : ndarray, shape (N,)
        Generalised force of mode k per newton of tip force F_z: phi_k at the tip (1D), phi_k
        averaged over the free edge (plate, where the static truth spreads its tip load).
    tip_z_per_sqrt_kg : ndarray, shape (N,)
        Tip z (m) per unit modal coordinate (sqrt(kg) m): phi_k at the tip centre (L, 0).
    strain_per_sqrt_kg_m : ndarray, shape (a, N)
        Generalised force of mode k per N m of actuator moment: psi_k(x_b) - psi_k(x_a), with
        psi = -d phi / dx averaged across the full width (see the module's sign convention).
    translation_sqrt_kg, moment_sqrt_kg_m : ndarray, shape (N,)
        Integrals of rho t phi_k dA and rho t x phi_k dA.
    mass_kg, first_moment_kg_m, second_moment_kg_m2 : float
        Integrals of rho t, rho t x and rho t x^2 dA (x from the root).
    corner_per_sqrt_kg : ndarray, shape (2, N), or None
        phi_k at the tip corners (L, +w(L)) (left, row 0) and (L, -w(L)) (right, row 1): the
        generalised force per newton of a z force at a corner (``corner_force_z_left``,
        ``corner_force_z_right``) and the corner's z (m) per unit modal coordinate
        (``corner_z_left``, ``corner_z_right``). Equal on both sides for a mode symmetric
        across the width (bending), opposite for an antisymmetric one (torsion). None for the
        1D beam, which has no width.
    """

    model: str
    omega_rad_s: np.ndarray
    mode_index: np.ndarray
    length_m: float
    actuators_m: np.ndarray
    tip_force_per_sqrt_kg: np.ndarray
    tip_z_per_sqrt_kg: np.ndarray
    strain_per_sqrt_kg_m: np.ndarray
    translation_sqrt_kg: np.ndarray
    moment_sqrt_kg_m: np.ndarray
    mass_kg: float
    first_moment_kg_m: float
    second_moment_kg_m2: float
    corner_per_sqrt_kg: np.ndarray | None = None

    def static_tip_z_m(self, tip_force_N: float = 0.0,
                       moments_Nm: Sequence[float] | np.ndarray = ()) -> float:
        """Return the clamped static tip z (m) of the modal model.

        Under a tip force (N) and actuator moments (N m; none given: all zero):
        sum_k c_k f_k / omega_k^2 over the selected modes.
        """
        m = np.asarray(moments_Nm, dtype=float).reshape(-1)
        if m.size == 0:
            m = np.zeros(self.actuators_m.shape[0])
        if m.size != self.actuators_m.shape[0]:
            raise BeamInputError(f"moments_Nm has {m.size} entries: must match the "
                                 f"{self.actuators_m.shape[0]} actuators")
        f = tip_force_N * self.tip_force_per_sqrt_kg + m @ self.strain_per_sqrt_kg_m
        return float(np.sum(self.tip_z_per_sqrt_kg * f / self.omega_rad_s**2))


def check_actuators(actuators: object, length_m: float) -> np.ndarray:
    """Return actuator stations as an (a, 2) float array, m.

    Parameters
    ----------
    actuators : sequence of (x_a, x_b)
        Patch stations, m from the root.
    length_m : float
        Beam length L, m.

    Raises
    ------
    BeamInputError
        Naming ``actuators[i]`` unless 0 <= x_a < x_b <= L.
    """
    try:
        st = np.array(actuators, dtype=float)
    except (TypeError, ValueError) as exc:
        raise BeamInputError(f"actuators = {actuators!r}: must be pairs (x_a, x_b) in m") from exc
    if st.size == 0:
        return np.zeros((0, 2))
    if st.ndim != 2 or st.shape[1] != 2:
        raise BeamInputError(f"actuators = {actuators!r}: must be pairs (x_a, x_b) in m")
    for i, (a, b) in enumerate(st):
        if not (np.isfinite(a) and np.isfinite(b)):
            raise BeamInputError(f"actuators[{i}] = ({a}, {b}): must be finite, in m")
        if a < 0.0 or b > length_m:
            raise BeamInputError(f"actuators[{i}] = ({a}, {b}) m: must lie within the span "
                                 f"[0, {length_m}] m")
        if a >= b:
            raise BeamInputError(f"actuators[{i}] = ({a}, {b}) m: needs x_a < x_b")
    return st


def _mode_fields(truth: TruthResult, beam: Beam, stations: np.ndarray) -> ModeFields:
    n = int(truth.modal.omega_rad_s.size)
    if truth.modal.kinds is not None:
        raise BeamInputError("truth: a 1D truth with torsion and in-plane modes (spatial=True); "
                             "modal gains need its bending modes only (spatial=False)")
    if truth.model == "beam":
        from .beam_fields import beam_mode_fields

        return beam_mode_fields(beam, n, stations)
    if truth.model in ("plate", "plate-morley"):
        from .plate_fields import plate_mode_fields

        return plate_mode_fields(beam, truth.mesh_level, n, _PLATES[truth.modal.model], stations)
    raise BeamInputError(f"truth.model = {truth.model!r}: modal gains need the 'plate', "
                         "'plate-morley' or 'beam' truth")


def _signs(tip: np.ndarray, node_uz: np.ndarray) -> np.ndarray:
    """+-1 per mode: a positive tip gain, or (tip still) a positive largest nodal deflection."""
    big = node_uz[np.arange(node_uz.shape[0]), np.argmax(np.abs(node_uz), axis=1)]
    still = np.abs(tip) <= 1e-8 * np.abs(big)
    s = np.where(still, np.sign(big), np.sign(tip))
    return np.where(s == 0.0, 1.0, s)


def truth_modal_gains(truth: TruthResult, beam: Beam,
                      actuators: Sequence[tuple[float, float]] = (),
                      mode_index: Sequence[int] | None = None) -> ModalGains:
    """Modal input and output gains of a clamped truth's selected modes.

    The truth keeps only nodal deflections; its modes are recomputed (same model, mesh and
    count, a fraction of the truth's cost) and refused unless they are the truth's.

    Parameters
    ----------
    truth : TruthResult
        A ``"plate"`` (default), ``"plate-morley"`` or ``"beam"`` truth of ``beam``.
    beam : Beam
    actuators : sequence of (x_a, x_b)
        Strain actuators: full-width moment pairs between stations 0 <= x_a < x_b <= L, m.
    mode_index : sequence of int, optional
        The computed modes to keep (0-based indices into ``truth.modal``); default the truth's
        selected (bending) modes, ``truth.mode_index``. The corner gains of a plate need its
        torsion modes too (``truth.labels``): they are not among the selected ones.

    Returns
    -------
    ModalGains

    Raises
    ------
    BeamInputError
        A truth of another beam or model, or bad actuator stations.
    TruthError
        The recomputed modes are not the truth's.
    """
    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r}: must be a prbdm_pin.Beam")
    if not isinstance(truth, TruthResult):
        raise InputTypeError(f"truth = {truth!r}: must be a TruthResult")
    if truth.beam_fingerprint != beam.fingerprint():
        raise BeamInputError(f"truth: computed for another beam than {beam.name!r}")
    stations = check_actuators(actuators, beam.length_m)
    fields = _mode_fields(truth, beam, stations)
    idx = _indices(truth, mode_index)
    w_truth = np.asarray(truth.modal.omega_rad_s)
    if fields.omega_rad_s.size != w_truth.size or np.any(
            np.abs(fields.omega_rad_s / w_truth - 1.0) > FREQUENCY_MATCH_TOL):
        raise TruthError(f"{beam.name!r}: the recomputed {truth.model} modes' frequencies are "
                         "not the truth's (another code version or mesh?)")
    if truth.modal.node_uz is not None:
        mac = np.diag(mac_matrix(fields.node_uz[idx], np.asarray(truth.modal.node_uz)[idx]))
        if np.any(mac < MAC_MATCH_MIN):
            raise TruthError(f"{beam.name!r}: recomputed selected modes {idx[mac < MAC_MATCH_MIN]}"
                             f" do not match the truth's shapes (MAC {mac.min():.4f})")
    s = _signs(fields.tip_z_per_sqrt_kg[idx], fields.node_uz[idx])
    return ModalGains(
        model=fields.model,
        omega_rad_s=_ro(fields.omega_rad_s[idx]),
        mode_index=_ro(idx),
        length_m=float(beam.length_m),
        actuators_m=_ro(stations),
        tip_force_per_sqrt_kg=_ro(s * fields.tip_force_per_sqrt_kg[idx]),
        tip_z_per_sqrt_kg=_ro(s * fields.tip_z_per_sqrt_kg[idx]),
        strain_per_sqrt_kg_m=_ro(s * fields.strain_per_sqrt_kg_m[:, idx]),
        translation_sqrt_kg=_ro(s * fields.translation_sqrt_kg[idx]),
        moment_sqrt_kg_m=_ro(s * fields.moment_sqrt_kg_m[idx]),
        mass_kg=fields.mass_kg,
        first_moment_kg_m=fields.first_moment_kg_m,
        second_moment_kg_m2=fields.second_moment_kg_m2,
        corner_per_sqrt_kg=None if fields.corner_per_sqrt_kg is None else
        _ro(s * fields.corner_per_sqrt_kg[:, idx]),
    )


def _indices(truth: TruthResult, mode_index: Sequence[int] | None) -> np.ndarray:
    """Return the modes kept: the selected ones, or ``mode_index`` checked (BeamInputError)."""
    if mode_index is None:
        return np.asarray(truth.mode_index)
    n = int(truth.modal.omega_rad_s.size)
    try:
        idx = np.array(mode_index, dtype=int).reshape(-1)
        ok = idx.size > 0 and np.array_equal(idx, np.asarray(mode_index, dtype=float).ravel())
    except (TypeError, ValueError):
        ok = False
    if not ok or np.any(idx < 0) or np.any(idx >= n) or np.unique(idx).size != idx.size:
        raise BeamInputError(f"mode_index = {mode_index!r:.80}: must be distinct indices of the "
                             f"truth's {n} computed modes (0..{n - 1})")
    return np.sort(idx)  # ascending in frequency, as the selected modes


def _ro(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float) if np.asarray(a).dtype.kind == "f" else np.array(a)
    a.setflags(write=False)
    return a
