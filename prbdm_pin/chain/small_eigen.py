"""One small chain's frequencies in one compiled call: scaling, eigenvalues, guard and omega.

The single-pose path of :func:`prbdm_pin.chain.eigen.eig_scaled`. For an n x n chain (n up to
a few tens) LAPACK's ``dsyevd`` spends most of its time in machine-constant queries, norm and
scaling passes and workspace handling, and numpy's calls around it cost more than the
arithmetic: here the scaled matrix S M S is reduced to tridiagonal form by Householder
reflections (as LAPACK's ``dsytd2``, EISPACK's ``tred1``; from the end LAPACK starts at for the
triangle read, which decides how well a graded matrix keeps its small eigenvalues) and its
eigenvalues found by the implicit QL iteration with Wilkinson shifts (EISPACK's ``tql1``),
with the tridiagonal flipped so that QL starts at its small end (as LAPACK's ``dsterf``
chooses between QL and QR). Both steps are backward stable, so each eigenvalue is off by a
small multiple of eps ||S M S||, the bound :data:`prbdm_pin.chain.eigen.COND_LIMIT` is set
from (tests check it against 50-digit mpmath solves and against LAPACK).

Compiled with numba (imported here only: the package's import and the CLI do not load it).
:func:`scaled_omega` returns False whenever the fast guard of
:func:`prbdm_pin.chain.eigen.check_spectrum` would not pass at once, or the QL iteration
does not converge; the caller then takes LAPACK's path, which raises the guard's errors.
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["scaled_omega", "scaled_omega_entry"]

_MAX_QL_ITERATIONS = 30  # per eigenvalue, as EISPACK's tql1 and LAPACK's dsterf
_EPS = np.finfo(float).eps
# the range of the tridiagonal's entries the QL step's squares stay normal in; outside it (and
# for non-finite entries) LAPACK's path answers
_TINY, _HUGE = 1e-140, 1e140


@numba.njit(cache=True)
def _tridiagonalise(a, d, e):  # pragma: no cover - compiled
    """Householder reduction of the symmetric a (lower triangle read, overwritten) to d, e.

    d the diagonal, e[i] the entry below d[i] (i < n - 1). Rows from the last up, as
    EISPACK's tred1 (eigenvalues only).
    """
    n = a.shape[0]
    for i in range(n - 1, 0, -1):
        lo = i - 1
        h = 0.0
        if lo > 0:
            scale = 0.0
            for k in range(i):
                scale += abs(a[i, k])
            if scale == 0.0:
                sub = a[i, lo]
            else:
                for k in range(i):
                    a[i, k] /= scale
                    h += a[i, k] * a[i, k]
                f = a[i, lo]
                g = -math.sqrt(h) if f >= 0.0 else math.sqrt(h)
                sub = scale * g  # stored after the loops, which use e[:i] as scratch
                h -= f * g
                a[i, lo] = f - g
                f = 0.0
                for j in range(i):
                    g = 0.0
                    for k in range(j + 1):
                        g += a[j, k] * a[i, k]
                    for k in range(j + 1, i):
                        g += a[k, j] * a[i, k]
                    e[j] = g / h  # scratch: p = A u / h
                    f += e[j] * a[i, j]
                hh = f / (h + h)
                for j in range(i):
                    f = a[i, j]
                    g = e[j] - hh * f
                    e[j] = g
                    for k in range(j + 1):
                        a[j, k] -= f * e[k] + g * a[i, k]
        else:
            sub = a[i, lo]
        e[i - 1] = sub
    for i in range(n):
        d[i] = a[i, i]


@numba.njit(cache=True)
def _ql_eigenvalues(d, e) -> bool:  # pragma: no cover - compiled
    """Eigenvalues of the symmetric tridiagonal (d, e) into d, ascending; False if no convergence.

    Implicit QL with Wilkinson shifts (EISPACK's tql1); e[i] couples d[i] and d[i + 1] and is
    destroyed. The tridiagonal is first flipped when its top end is the larger (QL converges
    from the top: the small end first, as LAPACK's dsterf arranges). The caller keeps the
    entries within (1e-140, 1e140), so sqrt(f^2 + g^2) needs no hypot (half the latency).
    """
    n = d.size
    if abs(d[n - 1]) < abs(d[0]):
        for i in range(n // 2):
            d[i], d[n - 1 - i] = d[n - 1 - i], d[i]
        for i in range((n - 1) // 2):
            e[i], e[n - 2 - i] = e[n - 2 - i], e[i]
    e[n - 1] = 0.0
    for lo in range(n):
        it = 0
        while True:
            m = lo
            while m < n - 1:
                if abs(e[m]) <= _EPS * (abs(d[m]) + abs(d[m + 1])):
                    break
                m += 1
            if m == lo:
                break
            if it == _MAX_QL_ITERATIONS:
                return False
            it += 1
            # |g| <= 1 / (2 eps) since e[lo] did not deflate: g * g cannot overflow
            g = (d[lo + 1] - d[lo]) / (2.0 * e[lo])
            r = math.sqrt(g * g + 1.0)
            g = d[m] - d[lo] + e[lo] / (g + (r if g >= 0.0 else -r))
            s = 1.0
            c = 1.0
            p = 0.0
            underflow = False
            for i in range(m - 1, lo - 1, -1):
                f = s * e[i]
                b = c * e[i]
                r = math.sqrt(f * f + g * g)
                e[i + 1] = r
                if r == 0.0:  # recover from underflow: deflate here
                    d[i + 1] -= p
                    e[m] = 0.0
                    underflow = True
                    break
                ri = 1.0 / r
                s = f * ri
                c = g * ri
                g = d[i + 1] - p
                r = (d[i] - g) * s + 2.0 * c * b
                p = s * r
                d[i + 1] = g + p
                g = c * r - b
            if underflow:
                continue
            d[lo] -= p
            e[lo] = g
            e[m] = 0.0
    for i in range(1, n):  # insertion sort: numba's sort costs more than a QL sweep here
        x = d[i]
        j = i - 1
        while j >= 0 and d[j] > x:
            d[j + 1] = d[j]
            j -= 1
        d[j + 1] = x
    return True


@numba.njit("b1(f8[:, :], f8[:], f8[:], f8[:], b1, b1, f8, f8)", cache=True)
def scaled_omega(M, s, q, out, squared, lower, cond_limit, safe_scale):  # pragma: no cover
    """Frequencies of one chain from its mass matrix and scaled springs, into ``out``.

    Parameters
    ----------
    M : ndarray (n, n)
        Mass matrix, kg m^2; only the triangle ``lower`` (True: lower) is read.
    s : ndarray (n,)
        s = K^(-1/2), (N m/rad)^(-1/2), finite and > 0.
    q : ndarray
        The pose M was computed at, rad (empty if none): refused unless finite (a chain's M
        does not depend on its first angle, so a NaN there leaves M finite).
    out : ndarray (n,)
        Receives ascending omega (rad/s), or omega^2 (rad^2/s^2) when ``squared``.
    squared, lower : bool
        omega^2 instead of omega; the triangle of M to read.
    cond_limit, safe_scale : float
        :data:`.eigen.COND_LIMIT` and the scale above which 1/mu cannot overflow.

    Returns
    -------
    bool
        False (``out`` undefined) when the fast guard does not pass (q not finite; mu not
        positive, not finite or too ill-conditioned; a scale that could overflow) or the
        iteration does not converge: the caller then takes LAPACK's checked path.
    """
    n = s.size
    if n == 0 or M.shape[0] != n or M.shape[1] != n or out.size != n:
        return False  # the numpy path raises what it raises
    for i in range(q.size):
        if not math.isfinite(q[i]):
            return False
    smax = s[0]
    for i in range(1, n):
        smax = max(smax, s[i])
    sn = s / smax
    # the same products as eig_scaled's M * sn[:, None] * sn[None, :], in the same order,
    # from the triangle LAPACK reads; the reduction runs from the last row up, as LAPACK's
    # from the upper triangle, so the lower triangle's matrix is flipped (a[i, j] =
    # A[n-1-j, n-1-i]) to be reduced from its first row down, as LAPACK's from the lower: the
    # direction decides how well a graded matrix's small eigenvalues come out
    a = np.empty((n, n))
    for i in range(n):
        for j in range(i + 1):
            if lower:
                r, c = n - 1 - j, n - 1 - i
                a[i, j] = M[r, c] * sn[r] * sn[c]
            else:
                a[i, j] = M[j, i] * sn[j] * sn[i]
    d = np.empty(n)
    e = np.empty(n)
    _tridiagonalise(a, d, e)
    size = 0.0
    for i in range(n):
        size = max(size, abs(d[i]), abs(e[i]) if i < n - 1 else 0.0)
    if not (_TINY < size < _HUGE) or not _ql_eigenvalues(d, e):  # NaN fails too
        return False
    lo, hi = d[0], d[n - 1]
    if not (lo > 0.0 and hi / lo <= cond_limit):  # NaN fails too
        return False
    for i in range(n):
        if not math.isfinite(d[i]):
            return False
    if not (smax >= safe_scale and lo >= safe_scale):
        return False
    c = 1.0 / smax
    c = c * c
    for i in range(n):
        w2 = c / d[n - 1 - i]
        out[i] = w2 if squared else math.sqrt(w2)
    return True


def scaled_omega_entry():
    """:func:`scaled_omega`'s compiled entry point for its one signature, or the function.

    Calling the entry point skips the dispatcher's type resolution (half the call's cost for
    a 5 x 5 chain); it unboxes without checking types, so the caller passes float64 arrays
    of the right dimensions only.
    """
    try:
        return scaled_omega.overloads[scaled_omega.signatures[0]].entry_point
    except (AttributeError, IndexError, KeyError):  # another numba: its dispatcher checks
        return scaled_omega
