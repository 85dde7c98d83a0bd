"""The fixed-step RK4 run of a trajectory gradient: state, cost and sensitivities in one vector.

y = (x (2n), S (2n x P, row-major), J, g (P)); y' = (f, (df/dx) S + df/dp, l, dl/dx S + dl/dp)
with df/dx's upper half the identity on the rates (q' = v). RK4 combines whole stage vectors,
so the sensitivities take exactly the state's steps (see :mod:`.sensitivity`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError
from .sensitivity_field import Field


@dataclass(frozen=True)
class Run:
    """The samples at every step (t s, x, u, the tip m) and J with its gradient."""

    t: np.ndarray
    x: np.ndarray
    u: np.ndarray
    tip: np.ndarray
    cost: float
    gradient: np.ndarray


def _refuse(cost, what: str, t: float, value) -> None:
    raise BeamInputError(f"cost = {cost!r:.60}: its {what} at t = {t:.6g} s is {value!r:.60}; "
                         "a trajectory cost must be finite")


def _running(cost, t, x, u, z):
    """(l, dl/dx, dl/du, dl/dz), through the cost's one-call method when it has one."""
    both = getattr(cost, "running_with_partials", None)
    if both is not None:
        return both(t, x, u, z)
    return (cost.running(t, x, u, z), *cost.running_partials(t, x, u, z))


def _partials(cost, t, lx, lu, lz, x, u):
    lx = np.asarray(lx, dtype=float).reshape(-1)
    lu = np.asarray(lu, dtype=float).reshape(-1)
    lz = float(lz)
    if lx.size != x.size or lu.size != u.size:
        raise BeamInputError(f"cost = {cost!r:.60}: running_partials must return dl/dx "
                             f"({x.size},), dl/du ({u.size},) and dl/dz")
    return lx, lu, lz  # their finiteness: checked by the compiled stage (Field.stage_rates)


def rk4_run(field: Field, cost, x0: np.ndarray, T: float, steps: int) -> Run:
    """Step the state, J and (when the field has parameters) their sensitivities over [0, T]."""
    d = field.d
    n, P, m = d.n, d.size, d.m
    nx = 2 * n
    iJ = nx + nx * P  # J's entry; the gradient follows

    def rates(t: float, y: np.ndarray, out: np.ndarray, record: list | None = None) -> None:
        x = y[:nx]
        out[:n] = x[n:]
        if P:
            a, u, z = field.sensitivity_stage(t, x)
            l, lx, lu, lz = _running(cost, t, x, u, z)
        else:
            a, u, z, _ = field.value(t, x)
            l = cost.running(t, x, u, z)
        out[n:nx] = a
        if not math.isfinite(l):
            _refuse(cost, "running value", t, l)
        out[iJ] = l
        if record is not None:
            record.append((u, field.tip_x(), z))
        if P:
            lx, lu, lz = _partials(cost, t, lx, lu, lz, x, u)
            if not field.stage_rates(x, y[nx:iJ].reshape(nx, P), lx, lu, lz,
                                     out[nx:iJ].reshape(nx, P), out[iJ + 1:]):
                _refuse(cost, "running_partials", t, (lx, lu, lz))

    h = T / steps
    y = np.zeros(iJ + 1 + P)
    y[:nx] = x0
    start = d.slices.get("initial")
    if start is not None:  # S(0) = dx0/dx0: the identity on the start state's columns
        y[nx:iJ].reshape(nx, P)[:, start] = np.eye(nx)
    t_s = np.arange(steps + 1) * h
    X = np.empty((steps + 1, nx))
    U: list = []
    # the stages' rates and the stage state in buffers, updated in place: the same operations
    # in the same order as y + (h/2) k1, ..., y + (h/6) (k1 + 2 (k2 + k3) + k4), without an
    # allocation per operation (the vector holds the 2n x P sensitivities)
    k1, k2, k3, k4 = np.empty((4, y.size))
    ys = np.empty(y.size)
    for i in range(steps):
        t = t_s[i]
        X[i] = y[:nx]
        rates(t, y, k1, U)
        np.multiply(k1, 0.5 * h, out=ys)
        ys += y
        rates(t + 0.5 * h, ys, k2)
        np.multiply(k2, 0.5 * h, out=ys)
        ys += y
        rates(t + 0.5 * h, ys, k3)
        np.multiply(k3, h, out=ys)
        ys += y
        rates(t + h, ys, k4)
        np.add(k2, k3, out=ys)
        ys *= 2.0
        ys += k1
        ys += k4
        ys *= h / 6.0
        y += ys
    X[steps] = y[:nx]
    t_end = float(t_s[-1])
    xT = y[:nx]
    a, uT, zT, dzT = field.value(t_end, xT)
    U.append((uT, field.tip_x(), zT))
    phi = float(cost.terminal(xT, zT)) if hasattr(cost, "terminal") else 0.0
    if not math.isfinite(phi):
        _refuse(cost, "terminal value", t_end, phi)
    J = float(y[iJ]) + phi
    grad = y[iJ + 1:].copy()
    if P and hasattr(cost, "terminal_partials"):
        px, pz = cost.terminal_partials(xT, zT)
        px = np.asarray(px, dtype=float).reshape(-1)
        pz = float(pz)
        if px.size != nx or not math.isfinite(float(px.sum()) + pz):
            _refuse(cost, "terminal_partials", t_end, (px, pz))
        px = px.copy()
        px[:n] += pz * dzT
        grad += px @ y[nx:iJ].reshape(nx, P) + pz * field.tip_station_derivative(xT[:n])
    if not math.isfinite(J) or not np.all(np.isfinite(grad)):
        raise BeamInputError(f"the run diverged (J = {J!r}): take a smaller dt_s or a larger "
                             "steps_per_period")
    tip = np.zeros((steps + 1, 3))
    tip[:, 0] = [r[1] for r in U]
    tip[:, 2] = [r[2] for r in U]
    return Run(t_s, X, np.array([r[0] for r in U]).reshape(steps + 1, m), tip, J, grad)
