"""Dormand-Prince 8(5,3) and 5(4) over a batch of planar chains: one shared step, compiled stages.

Each scheme, its error estimate, its step-size rule and its dense output are scipy's
``DOP853`` (seventh-order interpolant, three more stages per step that samples) and ``RK45``
(fourth-order interpolant from the step's own stages) with scipy's own coefficient tables,
applied to B designs at once. A step's twelve stages (six for RK45) and each design's error
norm are one compiled call over the batch (:mod:`.batch_rk_kernel`), the designs in blocks of
``BLOCK`` along the arrays' last axis (SIMD lanes); this loop only decides the step. The error
is measured per design with scipy's norm (each design's own tolerances, the RMS over its
coordinates) and the step is set by the largest of those norms: every design meets its own
tolerance, as it would alone, or better. One shared step keeps the designs in lockstep (the
same stage on every lane); the price is that the stiffest design sets the step for all of
them: on a lightly damped chain the highest mode bounds an explicit step (h omega_max of about
5 for DOP853), not the tolerance, and it bounds each design's own run about as much.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SolveError

__all__ = ["BatchSamples", "integrate_batch", "stage_table", "blocks", "BLOCK"]

_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0  # scipy's step-size rule
METHODS = ("DOP853", "RK45")
BLOCK = 128  # designs per block: a block's stages (16 x 10 x 128 doubles for a 5R) stay in L2


@dataclass(frozen=True)
class BatchSamples:
    """Samples of a batched run: t (s,), states (B, s, d), and what the run cost."""

    t_s: np.ndarray
    y: np.ndarray
    steps: int
    rejected_steps: int
    rhs_evaluations: int


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


def _dense_weights(sc: _Scheme, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return the interpolant at x = (t - t_old) / h as y_old + a (y - y_old) + h w . K.

    scipy's interpolants are linear in the step's increment and stages with coefficients that
    depend on x only: DOP853's seven terms F (dy, h f_old - dy, 2 dy - h (f + f_old), h D K)
    nested in x and 1 - x, RK45's h K^T P (x, x^2, x^3, x^4).
    """
    S = len(sc.C)
    w, a = np.zeros((x.size, S)), np.zeros(x.size)
    for r, xr in enumerate(x):
        if not sc.dop853:
            w[r, :len(sc.P)] = sc.P @ np.cumprod(np.full(sc.P.shape[1], xr))
            continue
        # the coefficient of F_k: the product of the factors applied after it was added
        mult = [xr if i % 2 == 0 else 1.0 - xr for i in range(7)]
        c = [float(np.prod(mult[6 - k:])) for k in range(7)]
        a[r] = c[0] - c[1] + 2.0 * c[2]
        w[r, 0] += c[1] - c[2]
        w[r, sc.ns] -= c[2]
        w[r] += np.asarray(c[3:]) @ sc.D
    return w, a


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
    """
    from ..chain.planar_batch_kernel import scratch_rows
    from .batch_rk_kernel import dense, stages

    sc = stage_table(method)
    B, d = y0.shape
    W = min(BLOCK, B)
    P, n, m, damped, gained, T = plant.block_constants(W)
    nc, S = P.shape[0], len(sc.C)
    Y, Ynew = blocks(y0, W), np.empty((nc, d, W))
    K, X = np.empty((nc, S, d, W)), np.empty((d, W))
    scratch = np.empty((max(scratch_rows(n, m), 4), W))
    atol_b = blocks(np.broadcast_to(atol, (B, 1))[:, 0], W)
    errs = np.empty(nc * W)
    consts = (P, n, m, damped, gained)

    def run(t, h, s0, s1):
        FT, UT = plant.stage_inputs(t + sc.C * h, S)
        stages(*consts, FT, UT, T, Y, K, Ynew, sc.A, h, s0, s1, sc.ns, sc.E5, sc.E3,
               sc.dop853, rtol, atol_b, errs, X, scratch)

    t = 0.0
    h = _first_step(run, sc, Y, K, t_end, rtol, atol_b)
    evals = 2
    ts, ys = [0.0], [y0.copy()]  # every step's samples (no grid)
    if t_out is not None:  # the grid's samples are written in place, design-major
        Y_out = np.empty((B, len(t_out), d))
    k_out = 0  # the next sample
    steps = rejected = 0
    while t < t_end:
        if steps >= max_steps:
            raise SolveError(f"simulate_batch: {max_steps} steps reached at t = {t:.6g} s "
                             "(max_steps)")
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        accepted = was_rejected = False
        while not accepted:
            if h < min_step:
                raise SolveError(f"simulate_batch: the step fell below {min_step:.3g} s at "
                                 f"t = {t:.6g} s")
            t_new = min(t + h, t_end)
            h = t_new - t
            run(t, h, 1, sc.ns + 1)
            evals += sc.ns
            err = float(errs.max())
            if not np.isfinite(err):
                raise SolveError(f"simulate_batch: the state is no longer finite at t = {t:.6g}"
                                 " s")
            if err < 1.0:
                factor = _MAX_FACTOR if err == 0.0 else min(_MAX_FACTOR,
                                                            _SAFETY * err ** sc.exponent)
                if was_rejected:
                    factor = min(1.0, factor)
                accepted = True
            else:
                factor = max(_MIN_FACTOR, _SAFETY * err ** sc.exponent)
                was_rejected = True
                rejected += 1
            h_next = h * factor
            if not accepted:
                h = h_next
        steps += 1
        if t_out is None:
            ts.append(t_new)
            ys.append(_unblock(Ynew, B))
        else:
            # as the single run samples: the times in [t, t_new), the last step also the end
            # and its rounding slack beyond
            k_end = len(t_out) if t_new >= t_end else int(np.searchsorted(t_out, t_new))
            if k_end > k_out:
                if S > sc.ns + 1:  # DOP853's interpolant: three more stages
                    run(t, h, sc.ns + 1, S)
                    evals += S - sc.ns - 1
                w, a = _dense_weights(sc, (t_out[k_out:k_end] - t) / h)
                dense(Y, Ynew, K, w, a, h, Y_out, k_out, B, scratch[0])
                k_out = k_end
        t, h = t_new, h_next
        Y, Ynew = Ynew, Y
        K[:, 0] = K[:, sc.ns]  # f at the new start (FSAL)
    if t_out is not None:
        return BatchSamples(t_out.copy(), Y_out, steps, rejected, evals)
    return BatchSamples(np.asarray(ts, dtype=float), np.stack(ys, axis=1), steps, rejected,
                        evals)


def _unblock(Y: np.ndarray, B: int) -> np.ndarray:
    """(blocks, d, W) -> (B, d)."""
    return np.moveaxis(Y, 2, 1).reshape(-1, Y.shape[1])[:B].copy()


def _first_step(run, sc: _Scheme, Y, K, t_end: float, rtol: float, atol) -> float:
    """Return scipy's initial step (Hairer's rule), the smallest over the designs.

    f(y0) is stage 0 at h = 0; f(y0 + h0 f0) is stage 1 with h = h0 / A[1, 0].
    """
    d = Y.shape[1]

    def rms(x):  # (blocks, d, W) -> per design
        return np.sqrt(np.einsum("cdw,cdw->cw", x, x) / d)

    run(0.0, 0.0, 0, 1)
    f0 = K[:, 0].copy()
    scale = atol[:, None, :] + np.abs(Y) * rtol
    d0, d1 = rms(Y / scale), rms(f0 / scale)
    h0 = np.where((d0 < 1e-5) | (d1 < 1e-5), 1e-6, 0.01 * d0 / np.maximum(d1, 1e-300))
    h0 = float(min(np.min(h0), t_end))
    run(0.0, h0 / sc.A[1, 0], 1, 2)
    d2 = rms((K[:, 1] - f0) / scale) / h0
    h1 = np.where((d1 <= 1e-15) & (d2 <= 1e-15), max(1e-6, h0 * 1e-3),
                  (0.01 / np.maximum(np.maximum(d1, d2), 1e-300)) ** -sc.exponent)
    return float(min(100.0 * h0, np.min(h1), t_end))
