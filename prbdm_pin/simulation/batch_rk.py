"""Dormand-Prince 8(5,3) and 5(4) over a batch of planar chains: blocks of designs, compiled.

Each scheme, its error estimate, its step-size rule and its dense output are scipy's
``DOP853`` (seventh-order interpolant, three more stages per step that samples) and ``RK45``
(fourth-order interpolant from the step's own stages) with scipy's own coefficient tables,
applied to blocks of ``BLOCK`` designs side by side (the arrays' last axis: SIMD lanes), each
block's whole run one compiled call (:mod:`.batch_rk_kernel`; a call per attempt when a load
is a function of time, evaluated here at the stage times). The error is measured per design
with scipy's norm (each design's own tolerances, the RMS over its coordinates) and a block's
step is set by the largest of its designs' norms: every design meets its own tolerance, as it
would alone, or better. Lockstep keeps every lane at the same stage; the price is that a
block's stiffest design sets its step: on a lightly damped chain the highest mode bounds an
explicit step (h omega_max of about 5 for DOP853), not the tolerance. So the designs are
sorted by their highest natural frequency at the start before they are cut into blocks:
designs of like stiffness step together.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SolveError

__all__ = ["BatchSamples", "integrate_batch", "stage_table", "blocks", "BLOCK"]

METHODS = ("DOP853", "RK45")
BLOCK = 128  # designs per block: a block's stages (16 x 10 x 128 doubles for a 5R) stay in L2


@dataclass(frozen=True)
class BatchSamples:
    """Samples of a batched run: t (s,), states (B, s, d), what the run cost, tip positions."""

    t_s: np.ndarray
    y: np.ndarray
    steps: np.ndarray
    rejected_steps: np.ndarray
    rhs_evaluations: np.ndarray
    tip_m: np.ndarray  # tip positions (B, s, 3), m


@dataclass(frozen=True, eq=False)
class _Scheme:
    """A scipy explicit Runge-Kutta pair: its stage table and its error and dense weights."""

    A: np.ndarray  # (S, S): stage s's weights; row ns is the step's end, then the extra stages
    C: np.ndarray  # (S,): stage times over h
    ns: int  # stages of the step (the step's end f is stage ns)
    E5: np.ndarray
    E3: np.ndarray
    exponent: float
    dop853: bool
    P: np.ndarray | None  # RK45's interpolant
    D: np.ndarray | None  # DOP853's interpolant


def stage_table(method: str) -> _Scheme:
    """Return scipy's tables of ``method`` (``"DOP853"`` or ``"RK45"``) as one stage table."""
    import scipy.integrate

    solver = getattr(scipy.integrate, method)  # scipy's tables: public class attributes
    ns = solver.n_stages
    dop = method == "DOP853"
    extra_a, extra_c = (solver.A_EXTRA, solver.C_EXTRA) if dop else ((), ())
    S = ns + 1 + len(extra_c)
    A = np.zeros((S, S))
    A[:ns, :solver.A.shape[1]] = solver.A
    A[ns, :ns] = solver.B
    for i, row in enumerate(extra_a):
        A[ns + 1 + i, :ns + 1 + i] = row[:ns + 1 + i]
    C = np.concatenate((solver.C, [1.0], extra_c))
    if dop:
        E5, E3 = solver.E5, solver.E3
    else:
        E5, E3 = solver.E, np.zeros(ns + 1)
    # scipy's step rule: factor = err ** (-1 / (error estimator order + 1))
    return _Scheme(np.ascontiguousarray(A), C, ns, np.ascontiguousarray(E5, dtype=float),
                   np.ascontiguousarray(E3, dtype=float),
                   -1.0 / (solver.error_estimator_order + 1), dop,
                   None if dop else solver.P, solver.D if dop else None)


def blocks(arr: np.ndarray, W: int) -> np.ndarray:
    """(B, ...) -> (blocks, ..., W), the last block padded with copies of design 0."""
    B = arr.shape[0]
    nc = -(-B // W)
    idx = np.arange(nc * W)
    idx[idx >= B] = 0  # a copy of a real design: finite, and no new largest error
    return np.ascontiguousarray(np.moveaxis(arr[idx].reshape((nc, W) + arr.shape[1:]), 1, -1))


def integrate_batch(plant, y0: np.ndarray, t_end: float, rtol: float, atol: np.ndarray,
                    t_out: np.ndarray | None, max_steps: int, method: str = "DOP853"
                    ) -> BatchSamples:
    """Integrate the designs' y' = f(t, y), y (B, d), from t = 0 to ``t_end`` (s).

    With an output grid, the designs are sorted by their highest natural frequency at the
    start (what bounds an explicit step) and cut into blocks of ``BLOCK``, each stepped on its
    own: a block's step is set by its stiffest design, not the batch's. Without one (a sample
    at every step, so one time grid for all) the batch is one block.

    Parameters
    ----------
    plant : BatchPlant
        The designs' equations (:mod:`.batch_rhs`).
    y0 : ndarray, shape (B, d)
        Initial states.
    t_end : float
        End time, s.
    rtol : float
        Relative tolerance, every design.
    atol : ndarray, shape (B, 1)
        Absolute tolerance of each design.
    t_out : ndarray or None
        Sample times, s, ascending in [0, t_end]; None: every accepted step (and t = 0).
    max_steps : int
        Cap on accepted steps; SolveError beyond it.
    method : str
        ``"DOP853"`` or ``"RK45"``.

    Returns
    -------
    BatchSamples
        ``steps``, ``rejected_steps`` and ``rhs_evaluations`` per design (B,).
    """
    from ..chain.planar_batch_kernel import scratch_rows
    from ..chain.planar_batch_tip import batch_tips
    from .batch_rk_kernel import advance, block_stages

    sc = stage_table(method)
    B, d = y0.shape
    every = t_out is None
    W = B if every else min(BLOCK, B)
    order = plant.stiffness_order(y0) if W < B else np.arange(B)
    P, n, m, damped, gained, T = plant.block_constants(W, order)
    nc, S = P.shape[0], len(sc.C)
    Yb = blocks(y0[order], W)
    atol_b = blocks(np.broadcast_to(atol, (B, 1))[order, 0], W)
    idx = blocks(order, W)
    idx[np.arange(nc * W).reshape(nc, W) >= B] = -1  # the padding lanes: not written
    K, Ynew, X = np.empty((S, d, W)), np.empty((d, W)), np.empty((d, W))
    scratch = np.empty((max(scratch_rows(n, m), d + 3), W))
    t_grid = np.zeros(0) if every else t_out
    Y_out = np.empty((B, 0 if every else len(t_out), d))
    tips = np.empty((B, 0 if every else len(t_out), 3))
    counts = np.zeros((B, 3), dtype=int)
    ts, ys = [0.0], [y0.copy()]  # every step's samples (no grid)
    P45 = sc.P if sc.P is not None else np.zeros((1, 1))
    D = sc.D if sc.D is not None else np.zeros((1, 1))
    timed = plant.timed
    for c in range(nc):
        Y = Yb[c]

        def run(t, h, s0, s1, Y=Y, c=c):
            FT, UT = plant.stage_inputs(t + sc.C * h, S)
            block_stages(P[c], n, m, damped, gained, FT, UT, T, Y, K, Ynew, sc.A, h, s0, s1,
                         sc.ns, X, scratch)

        ints = np.zeros(6, dtype=np.int64)
        ints[2] = 2
        fl = np.array([0.0, _first_step(run, sc, Y, K, t_end, rtol, atol_b[c])])
        FT, UT = plant.stage_inputs(sc.C * 0.0, S)
        while True:
            if timed:  # the shared functions of time at the next attempt's stage times
                h = min(fl[0] + fl[1], t_end) - fl[0]  # the step as advance clips it
                FT, UT = plant.stage_inputs(fl[0] + sc.C * h, S)
            status = advance(P[c], n, m, damped, gained, FT, UT, T, Y, K, Ynew, X, scratch,
                             sc.A, sc.C, sc.ns, sc.E5, sc.E3, sc.dop853, P45, D, sc.exponent,
                             rtol, atol_b[c], t_end, max_steps, t_grid, Y_out, tips, idx[c],
                             ints, fl, timed or every)
            if status:
                raise SolveError(_FAILURES[status].format(t=fl[0], steps=max_steps))
            if every and ints[5]:
                ts.append(float(fl[0]))
                ys.append(Y.T.copy())
            if not fl[0] < t_end:
                break
        counts[idx[c][idx[c] >= 0]] = ints[[0, 1, 2]]
    if every:
        Y_out = np.stack(ys, axis=1)
        tips = batch_tips(P[0, :n + 1].T, Y_out)  # one block: P's lanes are the designs
        return BatchSamples(np.asarray(ts, dtype=float), Y_out, *counts.T, tips)
    return BatchSamples(t_out.copy(), Y_out, *counts.T, tips)


_FAILURES = {1: "simulate_batch: the step fell below scipy's minimum at t = {t:.6g} s",
             2: "simulate_batch: {steps} steps reached at t = {t:.6g} s (max_steps)",
             3: "simulate_batch: the state is no longer finite at t = {t:.6g} s"}


def _first_step(run, sc: _Scheme, Y, K, t_end: float, rtol: float, atol) -> float:
    """Return scipy's initial step (Hairer's rule), the smallest over the block's designs.

    f(y0) is stage 0 at h = 0; f(y0 + h0 f0) is stage 1 with h = h0 / A[1, 0].
    """
    d = Y.shape[0]

    def rms(x):  # (d, W) -> per design
        return np.sqrt(np.einsum("dw,dw->w", x, x) / d)

    run(0.0, 0.0, 0, 1)
    f0 = K[0].copy()
    scale = atol + np.abs(Y) * rtol
    d0, d1 = rms(Y / scale), rms(f0 / scale)
    h0 = np.where((d0 < 1e-5) | (d1 < 1e-5), 1e-6, 0.01 * d0 / np.maximum(d1, 1e-300))
    h0 = float(min(np.min(h0), t_end))
    run(0.0, h0 / sc.A[1, 0], 1, 2)
    d2 = rms((K[1] - f0) / scale) / h0
    h1 = np.where((d1 <= 1e-15) & (d2 <= 1e-15), max(1e-6, h0 * 1e-3),
                  (0.01 / np.maximum(np.maximum(d1, d2), 1e-300)) ** -sc.exponent)
    K[0] = f0  # stage 0 stays f(t0, y0) for the first step
    return float(min(100.0 * h0, np.min(h1), t_end))
