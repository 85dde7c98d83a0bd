"""The fourth-order exponential Rosenbrock step exprb43 (``Exponential(order=4)``).

Hochbruck, Ostermann & Schweitzer (2009), with its embedded third-order scheme, on the same
linearisation as exprb32 (``exponential``): y' = F_n + J (y - y_n) + b s + r(s), J the
(possibly older) decomposed Jacobian, b s the forcing that carries the Jacobian's change since
the decomposition and the force's rate, r the remainder, r(0) = r'(0) = 0. The remainder is
evaluated at two stages, s = h/2 and s = h, and taken to be the cubic r(s) = a s^2 + c s^3
through them; its exact propagation gives

    y_{n+1} = y_n + h phi_1 F_n + h^2 phi_2 b + h (16 phi_3 - 48 phi_4) D_2
              + h (-2 phi_3 + 12 phi_4) D_3,

the phi functions of h J, and the embedded third-order step (phi_4 left out) differs from it
by 12 h phi_4 (D_3 - 4 D_2), the error estimate, of order h^4. Three dynamics evaluations per
step (one with derivatives, two ABA).

Why: exprb32's error estimate is that of its embedded second-order step, of order h^3, while
the step's own error is of order h^4. On releases from 0.1 rad per joint the estimate
overstates the true local error (DOP853 from the same state) by a median 120x at
``step_rtol`` 3e-4 and 1,350x at 1e-5 (5R chain), so its steps grow as step_rtol^(-1/3) while
the error falls faster. exprb43's estimate is of order h^4 (the controller's exponent 1/4):
0.01 % of the peak on every release and step load of n = 1 ... 8 at ``step_rtol=3e-5``, 1.3-3x
cheaper than exprb32 at equal error (``scripts/bench_exponential_release.py``). The
decomposition's refresh by angle matters to both: at ``refresh_rad`` 0.05 instead of 0.01
exprb43's error on the 5R release grows 10x at the same step_rtol, unseen by the estimate (the
stale Jacobian's error enters the remainder, which the estimate sees only through its
polynomial model).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .phi import phi1234


def rb43_phis(h: float, lam: np.ndarray) -> tuple[np.ndarray, ...]:
    """Return the step's phi factors (modal, complex).

    h/2 phi_1 and (h/2)^2 phi_2 of h lam / 2, then h phi_1, h^2 phi_2, h phi_3 and h phi_4 of
    h lam; h in s, lam (the Jacobian's eigenvalues) in 1/s.
    """
    m = lam.size
    # one call for both arguments: its cost is numpy's per-call overhead
    p1, p2, p3, p4 = phi1234(np.concatenate((0.5 * h * lam, h * lam)))
    return (0.5 * h * p1[:m], 0.25 * h * h * p2[:m], h * p1[m:], h * h * p2[m:], h * p3[m:],
            h * p4[m:])


def rb43_step(y: np.ndarray, t: float, h: float, lam: np.ndarray, V: np.ndarray,
              Vinv: np.ndarray, Fn: np.ndarray, b: np.ndarray, phis: tuple,
              remainder: Callable[[float, np.ndarray], np.ndarray]) -> tuple:
    """Take one exprb43 step of length h (s) from (t, y).

    ``remainder(c, U)`` returns the remainder D at the stage s = c h, state U. Returns the end
    state, the error estimate as a state (2n,) and in modal coordinates (2n,), and the
    dense-output record (start time, step, eigenvalues, eigenvectors, the modal coefficients
    of the rate, the remainder's s^2 and s^3 terms and the forcing).
    """
    p1h, p2h, p1, p2, p3, p4 = phis
    c1 = Vinv @ Fn
    cb = Vinv @ b
    U2 = y + (V @ (p1h * c1 + p2h * cb)).real
    cd2 = Vinv @ remainder(0.5, U2)
    lin = p1 * c1 + p2 * cb
    U3 = y + (V @ (lin + p1 * cd2)).real
    cd3 = Vinv @ remainder(1.0, U3)
    y1 = y + (V @ (lin + (16.0 * p3 - 48.0 * p4) * cd2 + (12.0 * p4 - 2.0 * p3) * cd3)).real
    ze = 12.0 * p4 * (cd3 - 4.0 * cd2)
    # the cubic remainder a s^2 + c s^3 through D_2 at h/2 and D_3 at h
    cq = (8.0 * cd2 - cd3) / (h * h)
    cc = (2.0 * cd3 - 8.0 * cd2) / (h * h * h)
    return y1, (V @ ze).real, ze, (t, h, lam, V, c1, cq, cc, cb)
