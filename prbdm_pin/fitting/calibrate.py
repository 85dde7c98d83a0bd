"""``calibrate``: a clamped planar PRBDM's E, rho and modal damping fitted to a free ring-down.

The parameters are scale factors of E (every spring scales with E) and of rho (every link's mass
and inertia), and the ratio ``damping[k]`` of mode k + 1 (the modal damping of
``linearize(..., damping="modal")``). The ring-down's unknown initial state (each mode's
amplitude and phase, as (a_k, b_k): :mod:`.calibration_basis`) is linear in the response and is
eliminated by variable projection (Golub and Pereyra; Kaufman's Jacobian), so the nonlinear
search sees only the named parameters. A grid over E/rho first puts the frequencies within the
basin of the phase: over T seconds a relative frequency error e drifts mode 1 by omega_1 T e rad.

Standard errors are s^2 (J^T J)^-1 of the full problem (the parameters and the initial state
together), s^2 the residual's mean square over N - p degrees of freedom: the linearised
covariance, which the projected problem gives too. Each channel is weighted by 1 / its data's
standard deviation, so channels of different units count alike. A Jacobian whose columns (each
scaled to unit length) have a condition number beyond 1 / sqrt(EPS) is refused, naming the
parameters of its near-null direction: a free ring-down sees E / rho only.
"""

from __future__ import annotations

import dataclasses
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from ..chain.eigen import generalized_eigh
from ..errors import BeamInputError, InputTypeError
from ..options.choices import LINK_FLOOR_FRACTION
from ..options.validate import check_damping_ratio
from .calibration_basis import ring_basis
from .calibration_data import RingDown, read_ring_down

__all__ = ["CalibrationResult", "calibrate", "PARAMETER_NAMES"]

PARAMETER_NAMES = ("E", "rho", "damping[k]")
_DAMPING = re.compile(r"^damping\[(\d+)\]$")
_COND_MAX = 1.0 / np.sqrt(np.finfo(float).eps)  # 6.7e7: beyond it half the digits are lost
_SCALE_BOUNDS = (1e-3, 1e3)
_ZETA_MAX = 0.99


@dataclass(frozen=True, eq=False)
class CalibrationResult:
    """The fitted parameters, their standard errors and the calibrated model.

    Attributes
    ----------
    parameters : tuple of str
        The names fitted, as asked (``E``, ``rho``, ``damping[k]``).
    values, std_errors : ndarray (p,)
        ``E`` in Pa, ``rho`` in kg/m^3 (the model's times the fitted scale), ``damping[k]``
        the ratio of mode k + 1 (dimensionless); one standard error each, same units.
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
        m = _DAMPING.match(p)
        if p not in ("E", "rho") and m is None:
            raise BeamInputError(f"parameters[{i}] = {p!r:.40}: must be E, rho or damping[k] "
                                 "(k = 0 for mode 1)")
        if p in names:
            raise BeamInputError(f"parameters[{i}] = {p!r}: named twice")
        names.append(p)
        if m is not None:
            modes.append(int(m.group(1)))
    return tuple(names), modes


def _chain_modes(model, channels: tuple[str, ...]):
    """Return omega0 (n,) and the modal Cq, Cv (c, n) of the clamped planar chain."""
    from ..plant.linearize import linearize

    if model.hub is not None or model.bus is not None or model.axes.spatial:
        raise BeamInputError("model: calibrate takes a clamped planar chain (no hub, bus or "
                             "spatial axes) for now")
    if model.beam is None:
        raise BeamInputError("model: has no beam (a URDF): E and rho are scaled on the beam; "
                             "give a model JSON or a fit.json")
    lin = linearize(model, inputs=("tip_force_z",), outputs=channels, damping_ratio=0.0)
    Ca = lin.output_map_acceleration
    if Ca is not None and np.any(Ca):
        bad = [c for c, row in zip(channels, Ca, strict=True) if np.any(row)]
        raise BeamInputError(f"data: channel {bad[0]!r} reads the acceleration; a ring-down "
                             "channel must be a position or a rate")
    n = lin.mass_kg_m2.shape[0]
    w2, phi = generalized_eigh(lin.stiffness_Nm_per_rad, lin.mass_kg_m2, "calibrate")
    C = np.asarray(lin.C)
    return np.sqrt(w2), C[:, :n] @ phi, C[:, n:] @ phi


@dataclass(frozen=True)
class _Problem:
    names: tuple[str, ...]
    t: np.ndarray
    yw: np.ndarray  # weighted data, flattened (N c,)
    weights: np.ndarray  # (c,)
    omega0: np.ndarray
    cq: np.ndarray
    cv: np.ndarray
    zeta0: np.ndarray

    def unpack(self, x):
        sE = sR = 1.0
        z = self.zeta0.copy()
        for name, v in zip(self.names, x, strict=True):
            if name == "E":
                sE = v
            elif name == "rho":
                sR = v
            else:
                z[int(_DAMPING.match(name).group(1))] = v
        return sE, sR, z

    def basis(self, x, derivatives=False):
        sE, sR, z = self.unpack(x)
        w = self.omega0 * np.sqrt(sE / sR)
        out = ring_basis(self.t, w, z, self.cq * self.weights[:, None],
                         self.cv * self.weights[:, None], derivatives)
        return (sE, sR, w, out) if derivatives else out.reshape(-1, 2 * w.size)

    def coefficients(self, B):
        return np.linalg.lstsq(B, self.yw, rcond=None)[0]

    def residual(self, x):
        B = self.basis(x)
        return self.yw - B @ self.coefficients(B)

    def model_jacobian(self, x):
        """Return B (Nc, 2n), the coefficients and dy/dx (Nc, p) at the optimal coefficients."""
        sE, sR, w, (B, dBw, dBz) = self.basis(x, True)
        n = w.size
        B, dBw, dBz = (a.reshape(-1, 2 * n) for a in (B, dBw, dBz))
        c = self.coefficients(B)
        per_w = (dBw * c).reshape(-1, n, 2).sum(axis=2)  # d y / d omega_k (Nc, n)
        cols = []
        for name in self.names:
            if name == "E":
                cols.append(per_w @ (w / (2.0 * sE)))  # omega ~ sqrt(sE / sR)
            elif name == "rho":
                cols.append(per_w @ (-w / (2.0 * sR)))
            else:
                k = int(_DAMPING.match(name).group(1))
                cols.append(dBz[:, 2 * k:2 * k + 2] @ c[2 * k:2 * k + 2])
        return B, c, np.column_stack(cols)

    def projected_jacobian(self, x):
        B, _, dy = self.model_jacobian(x)
        Q = np.linalg.qr(B)[0]
        return -(dy - Q @ (Q.T @ dy))  # Kaufman: the residual's, the coefficients held


def _rank_check(names, J_full):
    norms = np.linalg.norm(J_full, axis=0)
    p = len(names)
    dead = np.flatnonzero(norms[:p] == 0.0)
    if dead.size:
        raise BeamInputError(f"parameters: {names[dead[0]]} does not change the model's "
                             "response to this data: it cannot be determined")
    U = J_full / np.where(norms > 0.0, norms, 1.0)
    s, Vt = np.linalg.svd(U, full_matrices=False)[1:]
    if s[-1] <= s[0] / _COND_MAX:
        v = Vt[-1]
        which = [names[i] for i in range(p) if abs(v[i]) > 0.1]
        hint = (" (a free ring-down sees E/rho only: frequencies scale with sqrt(E/rho) and "
                "the unknown amplitudes take the rest; fit one of them)"
                if {"E", "rho"} <= set(which) else "")
        raise BeamInputError(f"parameters: {', '.join(which) or 'the initial state'} not "
                             f"determined by this data (the Jacobian's condition "
                             f"{s[0] / max(s[-1], 1e-300):.3g} > {_COND_MAX:.3g}){hint}")


def _start(prob: _Problem, x0: np.ndarray) -> np.ndarray:
    """Return x0 with the E or rho scale from a grid over E/rho (mode 1 alone)."""
    names = prob.names
    if "E" not in names and "rho" not in names:
        return x0
    T = prob.t[-1] - prob.t[0]
    # steps of 1 rad of mode 1's drift over T, ratio in [1/3, 3] (omega within -42 %, +73 %)
    step = 1.0 / max(prob.omega0[0] * T, 1.0)
    r = np.exp(np.arange(np.log(1 / 3), np.log(3.0), 2.0 * step))
    one = dataclasses.replace(prob, omega0=prob.omega0[:1], cq=prob.cq[:, :1],
                              cv=prob.cv[:, :1], zeta0=prob.zeta0[:1],
                              names=tuple(n for n in names if n in ("E", "rho")))
    x1 = np.ones(len(one.names))
    cost = []
    for ri in r:
        x1[0] = ri if one.names[0] == "E" else 1.0 / ri
        cost.append(float(np.sum(one.residual(x1) ** 2)))
    best = r[int(np.argmin(cost))]
    x = x0.copy()
    i = names.index(one.names[0])
    x[i] = best if one.names[0] == "E" else 1.0 / best
    return x


def calibrate(model, data: RingDown | str | os.PathLike,
              parameters: Sequence[str] | str = ("E", "damping[0]", "damping[1]"), *,
              n_modes: int | None = None, damping_ratio: float = 0.02) -> CalibrationResult:
    """Fit E, rho and modal damping ratios of ``model`` to a free ring-down.

    Parameters
    ----------
    model : PrbdmModel
        A clamped planar chain with its beam (the E and rho it has are the starting values).
    data : RingDown or path
        The measured ring-down (:func:`~prbdm_pin.fitting.calibration_data.read_ring_down`).
    parameters : sequence of str or str
        Names from ``E``, ``rho``, ``damping[k]`` (the ratio of mode k + 1), or one
        comma-separated string.
    n_modes : int, optional
        The lowest modes in the response (default: enough for every ``damping[k]``, at
        least 1). The ring-down's amplitude and phase of each is fitted too.
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
    if n_modes is None:
        n_modes = max(need, 1)
    if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) \
            or not need <= n_modes:
        raise BeamInputError(f"n_modes = {n_modes!r:.40}: must be an integer >= {max(need, 1)}"
                             " (every damping[k] needs mode k + 1)")
    omega0, cq, cv = _chain_modes(model, data.channels)
    if n_modes > omega0.size:
        raise BeamInputError(f"n_modes = {n_modes}: the model has {omega0.size} modes")
    N, c = data.y.shape
    unknowns = len(names) + 2 * n_modes
    if N * c <= unknowns:
        raise BeamInputError(f"data: t_s: {N} samples x {c} channel(s) for {unknowns} unknowns "
                             f"({len(names)} parameters, {2 * n_modes} of the initial state); "
                             "need more")
    sd = data.y.std(axis=0)
    if np.any(sd == 0.0):
        raise BeamInputError(f"data: {data.channels[int(np.argmin(sd))]}: constant; nothing to "
                             "fit")
    prob = _Problem(names, data.t_s - data.t_s[0], (data.y / sd).ravel(), 1.0 / sd,
                    omega0[:n_modes], cq[:, :n_modes], cv[:, :n_modes], np.full(n_modes, zeta))
    x0 = np.array([zeta if n.startswith("damping") else 1.0 for n in names])
    x0 = _start(prob, x0)
    B, _, dy = prob.model_jacobian(x0)
    _rank_check(names, np.hstack([dy, B]))
    lo = np.array([0.0 if n.startswith("damping") else _SCALE_BOUNDS[0] for n in names])
    hi = np.array([_ZETA_MAX if n.startswith("damping") else _SCALE_BOUNDS[1] for n in names])
    sol = least_squares(prob.residual, np.clip(x0, lo, hi), jac=prob.projected_jacobian,
                        bounds=(lo, hi), x_scale="jac", method="trf")
    x = sol.x
    B, coef, dy = prob.model_jacobian(x)
    J = np.hstack([dy, B])
    _rank_check(names, J)
    r = prob.yw - B @ coef
    s2 = float(r @ r) / (r.size - J.shape[1])
    cov = s2 * np.linalg.pinv(J.T @ J)
    sE, sR, z = prob.unpack(x)
    beam = model.beam
    base = {"E": beam.material.E_Pa, "rho": beam.material.rho_kg_m3}
    values = np.array([base.get(n, 1.0) * v for n, v in zip(names, x, strict=True)])
    std = np.array([base.get(n, 1.0) * np.sqrt(cov[i, i]) for i, n in enumerate(names)])
    fitted = (B @ coef).reshape(N, c) * sd
    res = data.y - fitted
    mat = dataclasses.replace(beam.material, E_Pa=beam.material.E_Pa * sE,
                              rho_kg_m3=beam.material.rho_kg_m3 * sR)
    new = build_model(dataclasses.replace(beam, material=mat), model.lengths_m,
                      np.asarray(model.stiffness_Nm_per_rad) * sE,
                      min_fraction=LINK_FLOOR_FRACTION)
    for a in (values, std, z, fitted):
        a.setflags(write=False)
    return CalibrationResult(
        parameters=names, values=values, std_errors=std, E_scale=float(sE),
        rho_scale=float(sR), damping_ratio=z, omega_rad_s=omega0[:n_modes] * np.sqrt(sE / sR),
        residual_rms={ch: float(np.sqrt(np.mean(res[:, j] ** 2)))
                      for j, ch in enumerate(data.channels)},
        fitted=fitted, data=data, model=new)
