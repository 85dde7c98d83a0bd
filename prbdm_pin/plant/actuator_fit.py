"""Strain actuator maps fitted to the truth.

The joint weights that give the PRBDM's n clamped modes the finite-element truth's modal input
gains.

With the mass-normalised modes Phi (n x n) of the clamped chain at the straight pose (K phi =
omega^2 M phi, phi^T M phi = 1), a map w (N m on each joint per N m of patch moment) forces
mode k with phi_k^T w. The truth's gain b_k of the same patch (``truth_modal_gains``) is
matched by solving Phi^T w = b: n equations in n unknowns, exact, and well conditioned
(Phi^-T = M Phi). With ``match="tip_z"`` the strain -> tip z residues are matched instead,
(c_k phi_k^T w = c_k^truth b_k, c the tip z per unit modal coordinate): the n-mode strain -> tip
z FRF is then the truth's exactly when the frequencies are, while the other outputs carry the
ratio c^truth / c of each mode; ``"modal"`` (the default) keeps every output as consistent with
the truth as the tip force's is.

Mode k of the PRBDM is paired with the truth's k-th selected mode, and the truth mode's sign is
aligned with the PRBDM's by the sign of the tip deflection each gives (``tip_z_per_sqrt_kg``
against J_z phi_k), or, when one of them barely moves its tip, of the tip rotation (the truth's
gain of the full-span patch, psi_k(L), against the chain's sum of joint angles). "Barely" is
against the mode's own amplitude along the beam: its largest deflection (or section rotation),
from the link ends of the chain and, on the truth, from psi_k at ``PROFILE_POINTS`` stations
(the gains of the patches (0, x_i); psi(0) = 0 at the clamp) and its integral.

A hub model is fitted on its clamped beam (the hub held): a patch's moment pair is internal to
the beam, so it acts on the beam joints only, and the truth's hybrid model uses the same clamped
modal gains.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..chain.eigen import modes_from_mass
from ..errors import BeamInputError
from ..model.inputs import StrainActuator, check_patch
from ..options.checks import check_float

__all__ = ["MATCHES", "PROFILE_POINTS", "SEPARATION_MIN_RTOL", "STILL_RTOL", "WEIGHT_LIMIT",
           "clamped_modes", "fit_strain_actuators", "fitted_weights", "mode_signs",
           "profile_stations"]

MATCHES = ("modal", "tip_z")
# consecutive PRBDM frequencies closer than this (relative) make modes whose shapes a fit's
# frequency error can mix, so "mode k" would not be a shape to pair with the truth's
SEPARATION_MIN_RTOL = 1e-2
# a mode's tip deflection (rotation) below this fraction of its own largest deflection (section
# rotation) along the beam is "still": the other indicator gives its sign
STILL_RTOL = 0.05
# stations of the truth's rotation profile, for the amplitudes above
PROFILE_POINTS = 40
# a sanity bound, not a tuning: the virtual-work map's weights lie in [0, 1] and fitted maps of
# a model whose modes match the truth's stay near that size; a weight an order of magnitude
# beyond means the modes do not correspond (another beam, a poor fit) and the map is refused
WEIGHT_LIMIT = 10.0


def clamped_modes(model) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Return the clamped chain's modes at the straight pose (a hub model with its hub held).

    Returns
    -------
    omega_rad_s : ndarray (n,)
        Ascending frequencies, rad/s.
    shapes : ndarray (n, n)
        Mass-normalised modes (columns) over the beam joints, rad per sqrt(kg) m.
    tip_z : ndarray (n,)
        Tip z per unit modal coordinate, m per sqrt(kg) m.
    tip_rotation : ndarray (n,)
        Tip section rotation (the sum of the joint angles) per unit modal coordinate.
    """
    off = int(model.hub is not None)
    q0 = np.zeros(model.pin_model.nq)
    M = model.mass_matrix(q0)[off:, off:]
    omega, Phi = modes_from_mass(M[None], np.asarray(model.stiffness_Nm_per_rad, dtype=float))
    Jz = model.tip_jacobian(q0)[2, off:]
    return omega[0], Phi[0], Jz @ Phi[0], Phi[0].sum(axis=0)


def _chain_amplitudes(model, Phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return the largest ``|z|`` of the link ends and ``|section rotation|`` of the links.

    One of each per mode.
    """
    x = np.cumsum(np.asarray(model.lengths_m, dtype=float))  # joints, then the tip
    arm = np.clip(x[:, None] - x[None, :-1], 0.0, None)  # dz(end i)/dq_j = -(x_i - x_j)
    z = -arm @ Phi
    rot = np.cumsum(Phi, axis=0)
    return np.abs(z).max(axis=0), np.abs(rot).max(axis=0)


def profile_stations(length_m: float) -> tuple[tuple[float, float], ...]:
    """Return the patches (0, x_i), x_i = i L / PROFILE_POINTS (the last: the full span).

    Their truth gains are the section rotation profile :func:`fitted_weights` needs.
    """
    x = np.linspace(0.0, float(length_m), PROFILE_POINTS + 1)[1:]
    x[-1] = float(length_m)
    return tuple((0.0, float(v)) for v in x)


def _truth_amplitudes(gains, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return tip rotation, largest ``|deflection|`` and ``|rotation|`` of the truth's modes.

    They are those of the truth's first n modes, from the profile patches at the end of
    ``gains``.
    """
    psi = np.asarray(gains.strain_per_sqrt_kg_m, dtype=float)[-PROFILE_POINTS:, :n]
    x = np.asarray(gains.actuators_m, dtype=float)[-PROFILE_POINTS:, 1]
    xs, ps = np.concatenate([[0.0], x]), np.vstack([np.zeros(n), psi])
    w = -np.concatenate([np.zeros((1, n)), np.cumsum(0.5 * (ps[1:] + ps[:-1])
                                                     * np.diff(xs)[:, None], axis=0)])
    tip = np.abs(np.asarray(gains.tip_z_per_sqrt_kg, dtype=float)[:n])
    return psi[-1], np.maximum(np.abs(w).max(axis=0), tip), np.abs(psi).max(axis=0)


def mode_signs(tip_z: np.ndarray, tip_rotation: np.ndarray, truth_tip_z: np.ndarray,
               truth_tip_rotation: np.ndarray, amplitudes=None) -> np.ndarray:
    """Return +-1 per mode: the sign that turns each truth mode into the PRBDM's.

    The sign matches the tip deflection; the tip rotation's where either side's tip is still
    (``STILL_RTOL``).

    ``amplitudes``: (z, rotation, truth z, truth rotation), each mode's largest deflection and
    section rotation along the beam on either side (default: each indicator's largest ``|value|``
    over the modes).

    Raises BeamInputError when a mode moves neither tip on one side, or when the two indicators
    disagree (the modes do not correspond).
    """
    values = (tip_z, tip_rotation, truth_tip_z, truth_tip_rotation)
    if amplitudes is None:
        amplitudes = tuple(np.full(np.shape(v), np.max(np.abs(v))) for v in values)
    ok = [np.abs(v) > STILL_RTOL * np.asarray(a) for v, a in zip(values, amplitudes, strict=True)]
    by_z = np.sign(tip_z) * np.sign(truth_tip_z)
    by_rot = np.sign(tip_rotation) * np.sign(truth_tip_rotation)
    z_ok = ok[0] & ok[2]
    rot_ok = ok[1] & ok[3]
    for k in range(tip_z.size):
        if not (z_ok[k] or rot_ok[k]):
            raise BeamInputError(f"model mode {k + 1}: neither its tip deflection nor its tip "
                                 "rotation is clear on both sides; its sign against the "
                                 "truth's cannot be told")
        if z_ok[k] and rot_ok[k] and by_z[k] != by_rot[k]:
            raise BeamInputError(f"model mode {k + 1}: its tip deflection and tip rotation "
                                 "disagree on its sign against truth mode "
                                 f"{k + 1}; the modes do not correspond (fit to this truth?)")
    return np.where(z_ok, by_z, by_rot)


def _check_pairing(omega: np.ndarray, omega_truth: np.ndarray) -> None:
    n = omega.size
    if omega_truth.size < n:
        raise BeamInputError(f"truth: has {omega_truth.size} selected modes, fewer than the "
                             f"model's {n} joints; compute it with modes >= {n}")
    gaps = omega[1:] / omega[:-1] - 1.0
    if gaps.size and gaps.min() < SEPARATION_MIN_RTOL:
        k = int(np.argmin(gaps))
        raise BeamInputError(f"model: modes {k + 1} and {k + 2} ({omega[k]:.6g}, "
                             f"{omega[k + 1]:.6g} rad/s) are not well separated (closer than "
                             f"{100 * SEPARATION_MIN_RTOL:g} %): their shapes are not defined "
                             "well enough to pair with the truth's")
    near = np.argmin(np.abs(np.log(omega[:, None] / omega_truth[None, :])), axis=1)
    for k in range(n):
        if near[k] != k:
            raise BeamInputError(f"model mode {k + 1} ({omega[k]:.6g} rad/s) is nearer truth "
                                 f"mode {near[k] + 1} ({omega_truth[near[k]]:.6g} rad/s) than "
                                 f"truth mode {k + 1} ({omega_truth[k]:.6g} rad/s): the model "
                                 "was not fitted to this truth's frequencies")


def fitted_weights(model, gains, match: str = "modal",
                   weight_limit: float = WEIGHT_LIMIT) -> np.ndarray:
    """Return the joint weights (a, n) of the actuators of ``gains``.

    ``gains`` is a ``ModalGains`` of the truth whose last ``PROFILE_POINTS`` actuators are
    :func:`profile_stations`, used for the sign alignment and not fitted.

    See :func:`fit_strain_actuators`.
    """
    if match not in MATCHES:
        raise BeamInputError(f"match = {match!r}: must be one of {', '.join(MATCHES)}")
    omega, Phi, c, rot = clamped_modes(model)
    n = omega.size
    _check_pairing(omega, np.asarray(gains.omega_rad_s, dtype=float))
    c_t = np.asarray(gains.tip_z_per_sqrt_kg, dtype=float)[:n]
    S = np.asarray(gains.strain_per_sqrt_kg_m, dtype=float)[:, :n]
    if S.shape[0] <= PROFILE_POINTS:
        raise BeamInputError("gains: must end with the profile_stations patches")
    rot_t, z_amp_t, rot_amp_t = _truth_amplitudes(gains, n)
    z_amp, rot_amp = _chain_amplitudes(model, Phi)
    s = mode_signs(c, rot, c_t, rot_t, (z_amp, rot_amp, z_amp_t, rot_amp_t))
    b = S[:-PROFILE_POINTS] * s  # the truth's gains of the PRBDM's modes, as the PRBDM signs them
    if match == "tip_z":
        b = b * (s * c_t / c)  # c_k phi_k^T w = c_t,k b_t,k
    W = np.linalg.solve(Phi.T, b.T).T
    big = np.abs(W) > weight_limit
    if np.any(big):
        i, j = np.argwhere(big)[0]
        raise BeamInputError(f"actuators[{i}].joint_weights[{j}] = {W[i, j]:.4g}: beyond "
                             f"+-{weight_limit:g} N m per N m, the model's modes do not match "
                             "the truth's (fit the model to this truth)")
    return W


def fit_strain_actuators(model, truth, beam, actuators: Sequence, match: str = "modal",
                         weight_limit: float = WEIGHT_LIMIT) -> tuple[StrainActuator, ...]:
    """Strain actuators whose joint weights are fitted to the truth's modal gains.

    Parameters
    ----------
    model : PrbdmModel
        A PRBDM of ``beam``, clamped or on a hub (its beam joints get the weights).
    truth : TruthResult
        A ``"beam"``, ``"plate"`` or ``"plate-morley"`` truth of ``beam`` with at least n
        selected modes (n joints); the model's frequencies should be fitted to them.
    beam : Beam
    actuators : sequence of StrainActuator or (x_a, x_b)
        The patches, m from the root (any joint weights they carry are replaced).
    match : {"modal", "tip_z"}
        Match the modal input gains (default) or the strain -> tip z residues (module notes).
    weight_limit : float
        Refuse a fitted weight beyond +- this, N m per N m (default ``WEIGHT_LIMIT``): such a
        weight says the model's modes do not match the truth's.

    Returns
    -------
    tuple of StrainActuator
        The same stations, each with ``joint_weights`` (N m per N m of patch moment).

    Raises
    ------
    BeamInputError
        Bad actuators, a truth of another beam or with fewer modes than joints, model modes not
        well separated or not paired with the truth's, a weight beyond ``WEIGHT_LIMIT``.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -100.0])
    >>> truth = pp.compute_truth(beam, model="beam", modes=2)
    >>> target = pp.target_from_truth(truth, beam.tip_force_N)
    >>> result = pp.fit(beam, target, 2, objective="eigen", stiffness="joint", starts=1,
    ...                 progress=False)
    >>> model = pp.build_model(beam, result.lengths_m, result.stiffness_Nm_per_rad)
    >>> patches = pp.fit_strain_actuators(model, truth, beam, [(0.0, 0.1)])
    >>> len(patches), len(patches[0].joint_weights)
    (1, 2)
    """
    from ..member.geometry import Beam
    from ..model.checks import check_model
    from ..options.validate import check_type
    from ..truth.plant.gains import truth_modal_gains
    from ..truth.result import TruthResult

    check_model(model)
    check_type("truth", truth, TruthResult, "a prbdm_pin.TruthResult (compute_truth)")
    check_type("beam", beam, Beam)

    if isinstance(actuators, (str, bytes, StrainActuator)) or not isinstance(actuators, Sequence):
        raise BeamInputError(f"actuators = {actuators!r:.60}: must be a sequence of "
                             "StrainActuator or (x_a, x_b) pairs")
    acts = tuple(a if isinstance(a, StrainActuator) else _pair(i, a)
                 for i, a in enumerate(actuators))
    if not acts:
        raise BeamInputError("actuators: none to fit")
    if model.beam is not None and model.beam.fingerprint() != beam.fingerprint():
        raise BeamInputError(f"model: built for another beam than {beam.name!r}")
    for i, a in enumerate(acts):
        check_patch(model.lengths_m, a, f"actuators[{i}]")  # on the beam; a joint or not
    if match not in MATCHES:
        raise BeamInputError(f"match = {match!r}: must be one of {', '.join(MATCHES)}")
    L = float(beam.length_m)
    # the stations are on the chain's span, which is the beam's to rounding: clip to the truth's
    stations = [(min(max(a.x_start_m, 0.0), L), min(max(a.x_end_m, 0.0), L)) for a in acts]
    n_selected = int(np.asarray(getattr(truth, "omega_rad_s", ())).size)
    if 0 < n_selected < model.n_joints:
        raise BeamInputError(f"truth: has {n_selected} selected modes, fewer than the model's "
                             f"{model.n_joints} joints; compute it with modes >= "
                             f"{model.n_joints}")
    gains = truth_modal_gains(truth, beam, [*stations, *profile_stations(L)])
    W = fitted_weights(model, gains, match, check_float("weight_limit", weight_limit,
                                                       low=0.0, low_open=True))
    return tuple(StrainActuator(a.x_start_m, a.x_end_m, joint_weights=tuple(w))
                 for a, w in zip(acts, W, strict=True))


def _pair(i: int, value) -> StrainActuator:
    try:
        a, b = value
    except (TypeError, ValueError):
        raise BeamInputError(f"actuators[{i}] = {value!r:.60}: must be a StrainActuator or a "
                             "pair (x_a, x_b) in m") from None
    try:
        return StrainActuator(a, b)
    except BeamInputError as exc:
        raise BeamInputError(f"actuators[{i}]: {exc}") from None
