"""``calibrate``: a clamped planar PRBDM's E, rho and modal damping fitted to a free ring-down.

The parameters are scale factors of E (every spring scales with E) and of rho (every link's mass
and inertia), the ratio ``damping[k]`` of mode k + 1 (the modal damping of
``linearize(..., damping="modal")``) and constant sensor offsets ``offset[CHANNEL]``. The
ring-down's unknown initial state (each mode's amplitude and phase, as (a_k, b_k):
:mod:`.calibration_basis`) and the offsets are linear in the response and are
eliminated by variable projection (Golub and Pereyra; Kaufman's Jacobian), so the nonlinear
search sees only the named parameters. A grid over E/rho first puts the frequencies within the
basin of the phase: over T seconds a relative frequency error e drifts mode 1 by omega_1 T e rad.

Standard errors are s^2 (J^T J)^-1 of the full problem (the parameters and the initial state
together), s^2 the residual's mean square over N - p degrees of freedom: the linearised
covariance, which the projected problem gives too. Each channel is weighted by 1 / its data's
standard deviation, so channels of different units count alike. A Jacobian whose columns (each
scaled to unit length) have a condition number beyond 1 / sqrt(EPS) is refused, naming the
parameters of its near-null direction: a free ring-down sees E / rho only. On a hub of known
inertia it sees them apart: a model with a hub goes to :mod:`.calibrate_hub`.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from ..chain.eigen import generalized_eigh
from ..errors import BeamInputError, InputTypeError
from ..options.choices import LINK_FLOOR_FRACTION
from ..options.validate import check_damping_ratio
from .calibration_data import RingDown, channel_name, read_ring_down
from .calibration_problem import DAMPING, OFFSET, RAYLEIGH, Problem, rank_check, start

__all__ = ["CalibrationResult", "calibrate", "PARAMETER_NAMES"]

PARAMETER_NAMES = ("E", "rho", "damping[k]", *RAYLEIGH, "offset[CHANNEL]")
_SCALE_BOUNDS = (1e-3, 1e3)
_ZETA_MAX = 0.99


@dataclass(frozen=True, eq=False)
class CalibrationResult:
    """The fitted parameters, their standard errors and the calibrated model.

    Attributes
    ----------
    parameters : tuple of str
        The names fitted, as asked (``E``, ``rho``, ``damping[k]``, ``offset[CHANNEL]``).
    values, std_errors : ndarray (p,)
        ``E`` in Pa, ``rho`` in kg/m^3 (the model's times the fitted scale), ``damping[k]``
        the ratio of mode k + 1 (dimensionless), ``offset[CHANNEL]`` the sensor's constant
        offset (the channel's unit); one standard error each, same units.
    E_scale, rho_scale : float
        The fitted scales (1 for one not fitted).
    damping_ratio : ndarray (n,)
        The ratio of each mode in the fit (fitted or the given ``damping_ratio``).
    omega_rad_s : ndarray (n,)
        The calibrated undamped frequencies, rad/s.
    residual_rms : dict of str to float
        Per channel, the RMS of data less model, in the channel's unit.
    fitted : ndarray (N, c)
        The calibrated model's response on the data's times.
    data : RingDown
    model : PrbdmModel
        The calibrated chain: its beam's E and rho scaled, its springs scaled with E.
    model_damping_ratio : ndarray (n_springs,)
        The modal ratio of every mode of the calibrated chain: the fitted ones, the given
        ``damping_ratio`` for the others (with Rayleigh damping, its ratio at each mode).
    """

    parameters: tuple[str, ...]
    values: np.ndarray
    std_errors: np.ndarray
    E_scale: float
    rho_scale: float
    damping_ratio: np.ndarray
    omega_rad_s: np.ndarray
    residual_rms: dict
    fitted: np.ndarray
    data: RingDown
    model: object
    model_damping_ratio: np.ndarray


def _parse(parameters) -> tuple[tuple[str, ...], list[int]]:
    if isinstance(parameters, str):
        parameters = [p.strip() for p in parameters.split(",")]
    if not isinstance(parameters, Sequence) or not parameters:
        raise InputTypeError(f"parameters = {parameters!r:.60}: must name at least one of "
                             "E, rho, damping[k]")
    names, modes = [], []
    for i, p in enumerate(parameters):
        if not isinstance(p, str):
            raise InputTypeError(f"parameters[{i}] = {p!r:.40}: must be a string")
        m = DAMPING.match(p)
        if p not in ("E", "rho", *RAYLEIGH) and m is None and OFFSET.match(p) is None:
            raise BeamInputError(f"parameters[{i}] = {p!r:.40}: must be E, rho, damping[k] "
                                 "(k = 0 for mode 1), rayleigh_alpha, rayleigh_beta or "
                                 "offset[CHANNEL]")
        if p in names:
            raise BeamInputError(f"parameters[{i}] = {p!r}: named twice")
        names.append(p)
        if m is not None:
            modes.append(int(m.group(1)))
    if modes and set(RAYLEIGH) & set(names):
        raise BeamInputError("parameters: damping[k] and rayleigh_alpha/rayleigh_beta are two "
                             "damping forms; fit one")
    return tuple(names), modes


def _chain_modes(model, channels: tuple[str, ...]):
    """Return omega0 (n,) and the modal Cq, Cv (c, n) of the clamped planar chain."""
    from ..plant.linearize import linearize

    if model.hub is not None or model.bus is not None or model.axes.spatial:
        raise BeamInputError("model: calibrate takes a planar chain, clamped or on a hub (no "
                             "bus or spatial axes) for now")
    if model.beam is None:
        raise BeamInputError("model: has no beam (a URDF): E and rho are scaled on the beam; "
                             "give a model JSON or a fit.json")
    try:
        lin = linearize(model, inputs=("tip_force_z",), outputs=channels, damping_ratio=0.0)
    except BeamInputError as exc:  # the channels are linearize's outputs: say it is the data's
        raise BeamInputError(f"data: the channels ({', '.join(channels)}) are outputs: "
                             f"{exc}") from None
    Ca = lin.output_map_acceleration
    if Ca is not None and np.any(Ca):
        bad = [c for c, row in zip(channels, Ca, strict=True) if np.any(row)]
        raise BeamInputError(f"data: channel {bad[0]!r} reads the acceleration; a ring-down "
                             "channel must be a position or a rate")
    n = lin.mass_kg_m2.shape[0]
    w2, phi = generalized_eigh(lin.stiffness_Nm_per_rad, lin.mass_kg_m2, "calibrate")
    C = np.asarray(lin.C)
    return np.sqrt(w2), C[:, :n] @ phi, C[:, n:] @ phi


def calibrate(model, data: RingDown | str | os.PathLike,
              parameters: Sequence[str] | str = ("E", "damping[0]", "damping[1]"), *,
              n_modes: int | None = None, damping_ratio: float = 0.02) -> CalibrationResult:
    """Fit E, rho and modal damping ratios of ``model`` to a free ring-down.

    Parameters
    ----------
    model : PrbdmModel
        A planar chain with its beam (the E and rho it has are the starting values), clamped
        or on a hub of known inertia (E and rho then fitted apart; ``damping[k]`` and
        ``n_modes`` count the flexible modes, the hub's rigid rotation undamped).
    data : RingDown or path
        The measured ring-down (:func:`~prbdm_pin.fitting.calibration_data.read_ring_down`).
    parameters : sequence of str or str
        Names from ``E``, ``rho``, ``damping[k]`` (the ratio of mode k + 1),
        ``rayleigh_alpha`` (1/s) and ``rayleigh_beta`` (s) of C = alpha M + beta K (mode k's
        ratio alpha / (2 omega_k) + beta omega_k / 2; not with ``damping[k]``),
        ``offset[CHANNEL]`` (a constant sensor offset of that data channel), or one
        comma-separated string.
    n_modes : int, optional
        The lowest modes in the response (default: enough for every ``damping[k]``, two
        with both Rayleigh coefficients, else 1). The ring-down's amplitude and phase of
        each is fitted too.
    damping_ratio : float
        The ratio of the modes whose damping is not fitted, and the fitted ones' start.

    Returns
    -------
    CalibrationResult

    Raises
    ------
    BeamInputError
        Naming the argument: unknown parameters, too few samples for the unknowns, a
        constant channel, a parameter the data cannot determine (and which).
    """
    from ..model.prbdm_model import PrbdmModel, build_model

    if not isinstance(model, PrbdmModel):
        raise InputTypeError(f"model = {model!r:.60}: must be a PrbdmModel")
    names, modes = _parse(parameters)
    if isinstance(data, (str, os.PathLike)):
        data = read_ring_down(data)
    if not isinstance(data, RingDown):
        raise InputTypeError(f"data = {data!r:.60}: must be a RingDown or a CSV path")
    zeta = check_damping_ratio("damping_ratio", damping_ratio)
    need = max(modes, default=-1) + 1
    n_given = n_modes  # a hub counts its flexible modes: calibrate_hub checks its own
    if n_modes is None:
        n_modes = max(need, 2 if set(RAYLEIGH) <= set(names) else 1)
    if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) \
            or not max(need, 1) <= n_modes:
        raise BeamInputError(f"n_modes = {n_modes!r:.40}: must be an integer >= {max(need, 1)}"
                             " (at least 1; every damping[k] needs mode k + 1)")
    offsets = []
    for i, n in enumerate(names):
        m = OFFSET.match(n)
        if m is not None:
            ch = channel_name(m.group(1))
            if ch not in data.channels:
                raise BeamInputError(f"parameters[{i}] = {n!r}: no channel {ch!r} in the data "
                                     f"(its channels: {', '.join(data.channels)})")
            offsets.append(data.channels.index(ch))
    if model.hub is not None and model.bus is None:  # E and rho apart: calibrate_hub
        from .calibrate_hub import calibrate_on_hub

        return calibrate_on_hub(model, data, names, modes, n_given, zeta, _initial, _bounds)
    omega0, cq, cv = _chain_modes(model, data.channels)
    if need > omega0.size:
        raise BeamInputError(f"parameters: damping[{need - 1}] is mode {need}'s; the model has "
                             f"{omega0.size} modes")
    if n_modes > omega0.size:
        raise BeamInputError(f"n_modes = {n_modes}: the model has {omega0.size} modes")
    N, c = data.y.shape
    unknowns = len(names) + 2 * n_modes  # the offsets are among the names
    if N * c <= unknowns:
        raise BeamInputError(f"data: t_s: {N} samples x {c} channel(s) for {unknowns} unknowns "
                             f"({len(names)} parameters, {2 * n_modes} of the initial state); "
                             "need more")
    sd = data.y.std(axis=0)
    if np.any(sd == 0.0):
        raise BeamInputError(f"data: {data.channels[int(np.argmin(sd))]}: constant; nothing to "
                             "fit")
    nonlinear = tuple(n for n in names if OFFSET.match(n) is None)
    prob = Problem(nonlinear, data.t_s - data.t_s[0], (data.y / sd).ravel(), 1.0 / sd,
                   omega0[:n_modes], cq[:, :n_modes], cv[:, :n_modes], np.full(n_modes, zeta),
                   tuple(offsets))
    p = len(nonlinear)
    # the Jacobian's columns: the nonlinear parameters, the initial state, the offsets
    labels = [*nonlinear, *([None] * 2 * n_modes),
              *(n for n in names if OFFSET.match(n) is not None)]
    x0 = start(prob, _initial(nonlinear, zeta, omega0[:n_modes]))
    if p:
        B, _, dy = prob.model_jacobian(x0)
        rank_check(labels, np.hstack([dy, B]))
        lo, hi = _bounds(nonlinear)
        x = least_squares(prob.residual, np.clip(x0, lo, hi), jac=prob.projected_jacobian,
                          bounds=(lo, hi), x_scale="jac", method="trf").x
        B, coef, dy = prob.model_jacobian(x)
    else:  # offsets alone: a linear problem
        x = x0
        B = prob.basis(x)
        coef, dy = prob.coefficients(B), np.zeros((B.shape[0], 0))
    J = np.hstack([dy, B])
    rank_check(labels, J)
    r = prob.yw - B @ coef
    s2 = float(r @ r) / (r.size - J.shape[1])
    cov = s2 * np.linalg.pinv(J.T @ J)
    sE, sR, z = prob.unpack(x)
    beam = model.beam
    base = {"E": beam.material.E_Pa, "rho": beam.material.rho_kg_m3}
    # the offsets' coefficients multiply a weighted column: they are in the data's units
    column = {n: i for i, n in enumerate(labels) if n}
    est = np.r_[x, coef]
    values = np.array([base.get(n, 1.0) * est[column[n]] for n in names])
    std = np.array([base.get(n, 1.0) * np.sqrt(cov[column[n], column[n]]) for n in names])
    fitted = (B @ coef).reshape(N, c) * sd
    res = data.y - fitted
    mat = dataclasses.replace(beam.material, E_Pa=beam.material.E_Pa * sE,
                              rho_kg_m3=beam.material.rho_kg_m3 * sR)
    new = build_model(dataclasses.replace(beam, material=mat), model.lengths_m,
                      np.asarray(model.stiffness_Nm_per_rad) * sE,
                      min_fraction=LINK_FLOOR_FRACTION)
    all_z = np.full(omega0.size, zeta)
    all_z[:n_modes] = z
    ab = prob.rayleigh(x)
    if ab is not None:  # every mode of the calibrated chain takes the fitted Rayleigh ratio
        w_all = omega0 * np.sqrt(sE / sR)
        all_z = ab[0] / (2.0 * w_all) + ab[1] * w_all / 2.0
        over = np.flatnonzero(all_z >= 1.0)
        if over.size:
            raise BeamInputError(f"parameters: the fitted Rayleigh damping gives mode "
                                 f"{over[0] + 1} of the chain a ratio {all_z[over[0]]:.3g} >= 1 "
                                 "(over-damped); fit damping[k] instead")
    for a in (values, std, z, fitted, all_z):
        a.setflags(write=False)
    return CalibrationResult(
        parameters=names, values=values, std_errors=std, E_scale=float(sE),
        rho_scale=float(sR), damping_ratio=z, omega_rad_s=omega0[:n_modes] * np.sqrt(sE / sR),
        residual_rms={ch: float(np.sqrt(np.mean(res[:, j] ** 2)))
                      for j, ch in enumerate(data.channels)},
        fitted=fitted, data=data, model=new, model_damping_ratio=all_z)


def _initial(names, zeta: float, w: np.ndarray) -> np.ndarray:
    """Return the start: scales 1, ratios zeta, Rayleigh giving modes 1 and n the ratio zeta."""
    w1, wn = w[0], w[-1]
    if w.size > 1 and {"rayleigh_alpha", "rayleigh_beta"} <= set(names):
        ab = (2 * zeta * w1 * wn / (w1 + wn), 2 * zeta / (w1 + wn))
    else:  # one coefficient alone carries mode 1's zeta
        ab = (2 * zeta * w1, 2 * zeta / w1)
    start_of = {"rayleigh_alpha": ab[0], "rayleigh_beta": ab[1], "E": 1.0, "rho": 1.0}
    return np.array([start_of.get(n, zeta) for n in names])


def _bounds(names) -> tuple[np.ndarray, np.ndarray]:
    lo = {"E": _SCALE_BOUNDS[0], "rho": _SCALE_BOUNDS[0]}
    hi = {"E": _SCALE_BOUNDS[1], "rho": _SCALE_BOUNDS[1], "rayleigh_alpha": np.inf,
          "rayleigh_beta": np.inf}
    return (np.array([lo.get(n, 0.0) for n in names]),
            np.array([hi.get(n, _ZETA_MAX) for n in names]))
