"""``calibrate`` of a chain on a hub of known inertia: E and rho fitted apart from a ring-down.

:func:`~prbdm_pin.fitting.calibrate.calibrate` hands a model with a hub here. The problem is
:class:`~.calibration_hub.HubProblem` (the coupled modes re-solved at every evaluation); the
search, the standard errors and the rank refusal are those of the clamped calibration. The
start: a grid along s_E (s_E alone when rho is not fitted, s_rho alone when E is not) puts mode
1 within 1 rad of drift over the record; with both fitted and two or more flexible modes, a
second grid along s_rho, s_E following so that mode 1 keeps its frequency, does the same for
mode 2, whose frequency relative to mode 1's is what s_rho moves.

``damping[k]`` is the ratio of flexible mode k + 1 (the rigid rotation of the free hub is
undamped); Rayleigh coefficients give the flexible modes alpha / (2 omega) + beta omega / 2.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.optimize import least_squares

from ..errors import BeamInputError
from .calibration_hub import HubProblem, hub_matrices
from .calibration_problem import OFFSET, RAYLEIGH, rank_check

__all__ = ["calibrate_on_hub"]

_E_RANGE = (1.0 / 3.0, 3.0)  # the start's grid: omega within -42 %, +73 % (as the clamped one)
_RHO_RANGE = (1.0 / 3.0, 3.0)
_COARSE = 65  # points that trace a mode's frequency along a grid's path
_GRID_POINTS = 300  # a grid's cost bound: it runs on a prefix of the record short enough


def _prefix(prob: HubProblem, n: int) -> HubProblem:
    c = prob.weights.size
    return dataclasses.replace(prob, t=prob.t[:n], yw=prob.yw[:n * c])


def _scan(prob: HubProblem, path, lo: float, hi: float, mode: int) -> tuple[float, int]:
    """Return the u in [lo, hi] of least residual and the samples the grid used.

    u steps so that mode ``mode`` drifts 1 rad over a prefix of the record, the prefix as
    long as _GRID_POINTS steps allow (all of it when they do).
    """
    u = np.linspace(lo, hi, _COARSE)
    w = np.array([prob.modes(*path(ui))[0][mode] for ui in u])
    arc = np.r_[0.0, np.cumsum(np.abs(np.diff(w)))]
    T = prob.t[-1] - prob.t[0]
    T_p = min(T, _GRID_POINTS / max(arc[-1], 1e-300))
    n = max(int(np.searchsorted(prob.t, prob.t[0] + T_p)), min(prob.t.size, 16))
    part = _prefix(prob, n)
    fine = np.interp(np.linspace(0.0, arc[-1], int(arc[-1] * T_p) + 2), arc, u)
    cost = [float(np.sum(part.residual(np.array(path(ui))) ** 2)) for ui in fine]
    return float(fine[int(np.argmin(cost))]), n


def _start(prob: HubProblem, x0: np.ndarray, lo, hi) -> np.ndarray:
    """Return the start: the grids (module notes), then fits on doubling prefixes."""
    names = prob.names
    if "E" not in names and "rho" not in names:
        return x0
    grid = dataclasses.replace(prob, names=("E", "rho"), zeta0=prob.zeta0[:1])
    if "E" in names:
        def path(u):
            return np.exp(u), 1.0
        u_lo, u_hi = np.log(_E_RANGE)
    else:
        def path(u):
            return 1.0, np.exp(u)
        u_lo, u_hi = np.log(_RHO_RANGE)
    u, n = _scan(grid, path, u_lo, u_hi, 0)
    sE, sR = path(u)
    if {"E", "rho"} <= set(names) and prob.n_modes >= 2:
        grid = dataclasses.replace(grid, zeta0=prob.zeta0[:2])
        w1 = grid.modes(sE, sR)[0][0]

        def along(v):  # s_rho moves, s_E keeps mode 1 where the first grid put it
            r = sR * np.exp(v)
            return (w1 / grid.modes(1.0, r)[0][0]) ** 2, r
        v, m = _scan(grid, along, *np.log(_RHO_RANGE), 1)
        sE, sR = along(v)
        n = min(n, m)
    x = x0.copy()
    for name, v in (("E", sE), ("rho", sR)):
        if name in names:
            x[names.index(name)] = v
    # a fit on a prefix pins the frequencies to well within 1 rad of drift over twice its
    # length: doubling keeps each fit inside the basin of the phases
    while n < prob.t.size // 2:
        part = _prefix(prob, n)
        x = least_squares(part.residual, np.clip(x, lo, hi), jac=part.projected_jacobian,
                          bounds=(lo, hi), x_scale="jac", method="trf").x
        n *= 2
    return x


def _rank_check(labels, J, model, M_beam, Cq) -> None:
    try:
        rank_check(labels, J)
    except BeamInputError as exc:
        text = str(exc).split(" (a free ring-down")[0]
        if {"E", "rho"} <= set(labels) and "E, rho" in text:
            J_b = float(M_beam[0, 0])
            text += (f" (on this hub E and rho show apart only through the beam's inertia "
                     f"about the hub axis, J_b = {J_b:.4g} kg m^2, against the hub's "
                     f"J_h = {model.hub.inertia_kg_m2:.4g} kg m^2: a hub much heavier than the "
                     "beam holds it as a clamp, and a hub turning about x or z does not couple "
                     "to the bending at all; fit one of them)")
        if "offset[" in text and np.any(Cq[:, 0]):
            text += (" (on a hub the rigid rotation's rest angle is a constant in every channel "
                     "that reads the hub's angle: offsets on all of those cannot be told from "
                     "it)")
        raise BeamInputError(text) from None


def calibrate_on_hub(model, data, names, modes, n_modes, zeta: float, initial, bounds):
    """Fit ``names`` of the hub chain ``model`` to the ring-down ``data``.

    Called by :func:`~prbdm_pin.fitting.calibrate.calibrate` after its argument checks
    (``initial`` and ``bounds`` its start and bounds of the nonlinear parameters); returns
    its :class:`~prbdm_pin.fitting.calibration_result.CalibrationResult`, the model on its hub.
    """
    from .calibration_result import estimates, frozen_result, over_damped, scaled_model

    need = max(modes, default=-1) + 1
    n_flex = model.n_springs
    if need > n_flex:
        raise BeamInputError(f"parameters: damping[{need - 1}] is flexible mode {need}'s; the "
                             f"model on its hub has {n_flex} flexible modes (k counts the "
                             "flexible modes; the hub's rigid rotation is undamped)")
    if n_modes is None:
        both = {"E", "rho"} <= set(names) or set(RAYLEIGH) <= set(names)
        n_modes = min(max(need, 2 if both else 1), n_flex)
    if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) \
            or not max(need, 1) <= n_modes <= n_flex:
        raise BeamInputError(f"n_modes = {n_modes!r:.40}: must be an integer in "
                             f"[{max(need, 1)}, {n_flex}] (the flexible modes on the hub)")
    offsets = [data.channels.index(_channel(n)) for n in names if OFFSET.match(n)]
    N, c = data.y.shape
    K, M_beam, M_hub, Cq, Cv = hub_matrices(model, data.channels)
    sd = data.y.std(axis=0)
    if np.any(sd == 0.0):
        raise BeamInputError(f"data: {data.channels[int(np.argmin(sd))]}: constant; nothing to "
                             "fit")
    nonlinear = tuple(n for n in names if OFFSET.match(n) is None)
    prob = HubProblem(nonlinear, data.t_s - data.t_s[0], (data.y / sd).ravel(), 1.0 / sd, K,
                      M_beam, M_hub, Cq, Cv, np.full(n_modes, zeta), tuple(offsets))
    n_rigid = prob.fixed_columns().shape[1] - len(offsets)
    unknowns = len(names) + 2 * n_modes + n_rigid
    if N * c <= unknowns:
        raise BeamInputError(f"data: t_s: {N} samples x {c} channel(s) for {unknowns} unknowns "
                             f"({len(names)} parameters, {2 * n_modes + n_rigid} of the initial "
                             "state); need more")
    labels = [*nonlinear, *([None] * (2 * n_modes + n_rigid)),
              *(n for n in names if OFFSET.match(n) is not None)]
    w_start = prob.modes(1.0, 1.0)[0]
    x = initial(nonlinear, zeta, w_start)
    if nonlinear:
        B, _, dy = prob.model_jacobian(x)
        _rank_check(labels, np.hstack([dy, B]), model, M_beam, Cq)
        lo, hi = bounds(nonlinear)
        x = _start(prob, x, lo, hi)
        x = least_squares(prob.residual, np.clip(x, lo, hi), jac=prob.projected_jacobian,
                          bounds=(lo, hi), x_scale="jac", method="trf").x
        B, coef, dy = prob.model_jacobian(x)
    else:
        B = prob.basis(x)
        coef, dy = prob.coefficients(B), np.zeros((B.shape[0], 0))
    J = np.hstack([dy, B])
    _rank_check(labels, J, model, M_beam, Cq)
    r = prob.yw - B @ coef
    values, std = estimates(model, names, labels, J, r, np.r_[x, coef])
    sE, sR = prob.scales(x)
    fitted = (B @ coef).reshape(N, c) * sd
    try:
        new = scaled_model(model, sE, sR)
    except BeamInputError as exc:  # a runaway along the weakly determined E-rho direction
        raise BeamInputError(f"parameters: the fit drove E and rho to {sE:.3g} and {sR:.3g} "
                             f"times the model's, which no member has ({exc}); this data "
                             "barely separates them (a hub heavy against the beam's own "
                             "inertia about its axis): fit one of them") from None
    w_all = dataclasses.replace(prob, zeta0=np.full(n_flex, zeta)).modes(sE, sR)[0]
    z = prob.ratios(x, w_all[:n_modes])
    all_z = np.full(n_flex, zeta)
    all_z[:n_modes] = z
    if set(RAYLEIGH) & set(names):  # every flexible mode takes the fitted Rayleigh ratio
        all_z = prob.ratios(x, w_all)
        over_damped(all_z, "flexible mode")
    return frozen_result(names, values, std, sE, sR, z, w_all[:n_modes], data.y - fitted,
                         fitted, data, new, all_z)


def _channel(name: str) -> str:
    from .calibration_data import channel_name

    return channel_name(OFFSET.match(name).group(1))
