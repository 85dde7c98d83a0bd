"""Dormand-Prince 8(5,3) and 5(4) over a batch of systems: one shared step, numpy over the batch.

Each scheme, its error estimate, its step-size rule and its dense output are scipy's
``DOP853`` (seventh-order interpolant, three more stages per step that samples) and ``RK45``
(fourth-order interpolant from the step's own stages) with scipy's own coefficient tables,
applied to B states at once: each stage is one call of the batched right-hand side. The error
is measured per design with scipy's norm (each design's own tolerances, the RMS over its
coordinates) and the step is set by the largest of those norms: every design meets its own
tolerance, as it would alone, or better. One shared step is what keeps every stage one call
over the batch (per-design steps would split the batch into designs at different times); the
price is that the stiffest design sets the step for all of them: on a lightly damped chain the
highest mode bounds an explicit step (h omega_max of about 5 for DOP853), not the tolerance.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..errors import SolveError

__all__ = ["BatchSamples", "integrate_batch"]

_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0  # scipy's step-size rule
METHODS = ("DOP853", "RK45")


@dataclass(frozen=True)
class BatchSamples:
    """Samples of a batched run: t (s,), states (B, s, d), and what the run cost."""

    t_s: np.ndarray
    y: np.ndarray
    steps: int
    rejected_steps: int
    rhs_evaluations: int


class _Scheme:
    """A scipy explicit Runge-Kutta pair's tables, error norm and interpolant, batched."""

    def __init__(self, method: str):
        import scipy.integrate

        solver = getattr(scipy.integrate, method)  # scipy's tables: public class attributes
        self.A, self.B, self.C, self.ns = solver.A, solver.B, solver.C, solver.n_stages
        # scipy's step rule: factor = err ** (-1 / (error estimator order + 1))
        self.exponent = -1.0 / (solver.error_estimator_order + 1)
        self.dop853 = method == "DOP853"
        if self.dop853:
            self.E3, self.E5, self.D = solver.E3, solver.E5, solver.D
            self.A_extra, self.C_extra = solver.A_EXTRA, solver.C_EXTRA
        else:
            self.E, self.P = solver.E, solver.P
            self.A_extra, self.C_extra = (), ()

    def error(self, combine, h: float, scale: np.ndarray) -> np.ndarray:
        """Return each design's scaled error norm (B,): scipy's, design by design."""
        d = scale.shape[1]
        if not self.dop853:
            e = combine(self.E, self.ns + 1) / scale
            return h * np.sqrt(_rms(e) / d)
        # the fifth-order estimate damped by the third's
        e5 = _rms(combine(self.E5, self.ns + 1) / scale)
        e3 = _rms(combine(self.E3, self.ns + 1) / scale)
        denom = np.sqrt((e5 + 0.01 * e3) * d)
        return np.where(denom > 0.0, h * e5 / np.where(denom > 0.0, denom, 1.0), 0.0)

    def dense(self, rhs, K, combine, t, h, y_old, y, f_old, f, t_s, out) -> int:
        """Write the last step's interpolant at the times ``t_s`` into ``out`` (B, len, d).

        Returns the right-hand side evaluations it took.
        """
        x_s = (t_s - t) / h
        if not self.dop853:
            for j, x in enumerate(x_s):
                w = self.P @ np.cumprod(np.full(self.P.shape[1], x))
                out[:, j] = y_old + h * combine(w, self.ns + 1)
            return 0
        ns = self.ns
        for s, (a, c) in enumerate(zip(self.A_extra, self.C_extra, strict=True), start=ns + 1):
            K[s] = rhs(t + c * h, y_old + h * combine(a[:s], s))
        dy = y - y_old
        F = [dy, h * f_old - dy, 2.0 * dy - h * (f + f_old)]
        F.extend(h * combine(row, len(K)) for row in self.D)
        for j, x in enumerate(x_s):
            acc = np.zeros_like(y_old)
            for i, fi in enumerate(reversed(F)):
                acc += fi
                acc *= x if i % 2 == 0 else 1.0 - x
            out[:, j] = acc + y_old
        return len(self.C_extra)


def _rms(x: np.ndarray) -> np.ndarray:
    """Per-design sum of squares over the coordinates of (B, d)."""
    return np.einsum("bd,bd->b", x, x)


def _first_step(rhs, t0: float, y0: np.ndarray, f0: np.ndarray, t_end: float, rtol: float,
                atol: np.ndarray, exponent: float) -> float:
    """Return scipy's initial step (Hairer's rule), the smallest over the designs."""
    d = y0.shape[1]
    scale = atol + np.abs(y0) * rtol
    d0 = np.sqrt(_rms(y0 / scale) / d)
    d1 = np.sqrt(_rms(f0 / scale) / d)
    h0 = np.where((d0 < 1e-5) | (d1 < 1e-5), 1e-6, 0.01 * d0 / np.maximum(d1, 1e-300))
    h0 = float(min(np.min(h0), t_end - t0))
    f1 = rhs(t0 + h0, y0 + h0 * f0)
    d2 = np.sqrt(_rms((f1 - f0) / scale) / d) / h0
    h1 = np.where((d1 <= 1e-15) & (d2 <= 1e-15), max(1e-6, h0 * 1e-3),
                  (0.01 / np.maximum(np.maximum(d1, d2), 1e-300)) ** -exponent)
    return float(min(100.0 * h0, np.min(h1), t_end - t0))


def integrate_batch(rhs: Callable[[float, np.ndarray], np.ndarray], y0: np.ndarray,
                    t_end: float, rtol: float, atol: np.ndarray, t_out: np.ndarray | None,
                    max_steps: int, method: str = "DOP853") -> BatchSamples:
    """Integrate y' = rhs(t, y) for B states y (B, d) from t = 0 to ``t_end`` (s).

    Parameters
    ----------
    rhs : callable (t, Y (B, d)) -> (B, d)
        The batched right-hand side.
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
    sc = _Scheme(method)
    A, Bw, C, ns = sc.A, sc.B, sc.C, sc.ns
    B, d = y0.shape
    K = np.empty((ns + 1 + len(sc.C_extra), B, d))
    K2 = K.reshape(len(K), B * d)  # the stages' combinations as BLAS matrix-vector products

    def combine(w: np.ndarray, s: int) -> np.ndarray:
        return (w @ K2[:s]).reshape(B, d)

    t, y = 0.0, y0.copy()
    f = rhs(t, y)
    evals = 2
    h = _first_step(rhs, t, y, f, t_end, rtol, atol, sc.exponent)
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
            K[0] = f
            for s in range(1, ns):
                K[s] = rhs(t + C[s] * h, y + h * combine(A[s, :s], s))
            y_new = y + h * combine(Bw, ns)
            f_new = rhs(t_new, y_new)
            K[ns] = f_new
            evals += ns
            scale = atol + np.maximum(np.abs(y), np.abs(y_new)) * rtol
            err = float(np.max(sc.error(combine, h, scale)))
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
            ys.append(y_new)
        else:
            # as the single run samples: the times in [t, t_new), the last step also the end
            # and its rounding slack beyond
            k_end = len(t_out) if t_new >= t_end else int(np.searchsorted(t_out, t_new))
            if k_end > k_out:
                evals += sc.dense(rhs, K, combine, t, h, y, y_new, f, f_new,
                                  t_out[k_out:k_end], Y_out[:, k_out:k_end])
                k_out = k_end
        t, y, f, h = t_new, y_new, f_new, h_next
    if t_out is not None:
        return BatchSamples(t_out.copy(), Y_out, steps, rejected, evals)
    return BatchSamples(np.asarray(ts, dtype=float), np.stack(ys, axis=1), steps, rejected,
                        evals)
