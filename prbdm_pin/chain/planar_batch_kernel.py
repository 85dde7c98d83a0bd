"""Compiled accelerations of a block of planar chains, the designs innermost (numba).

The batched simulation's right-hand side spends its time here: per design, the closed forms of
:mod:`.planar_batch` (M(q), the Coriolis/centrifugal forces h, J^T F), the inputs and a
L D L^T solve of M a = tau - K q - C v - h + J^T F. Every array holds a block of W designs
along its last axis, and every loop runs over that axis innermost: the same arithmetic on W
designs side by side, which the compiler turns into SIMD instructions (one design per lane).
The sines and cosines are a polynomial (:func:`sincos`) for the same reason: the C library's
are calls the compiler cannot vectorise, and they cost more than the rest of the arithmetic.
numba (chosen over JAX: a small dependency that compiles these loops as they are written, with
an on-disk cache) is imported by this module only, loaded on the first batched run.

A block's constants are rows of one array P (R, W) (:func:`param_rows` gives the layout): the
link lengths, masses, centre-of-mass offsets and inertias, the springs, a constant tip force,
the inputs' constant part u0, then the damping matrix, the input map B0 and the feedback gain
G when there are any. With p_k the joints and c_i the centres of mass (xz-plane, z flipped as
in :mod:`.planar_mass`), the entries of M for j <= k are computed about joint k, free of the
cancellation of absolute coordinates:

    M_jk = S_k + (p_k - p_j) . T_k,  S_k = sum_(i >= k) m_i |c_i - p_k|^2 + I_i,
                                      T_k = sum_(i >= k) m_i (c_i - p_k).
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["param_rows", "mass_rows", "block_rates", "batch_state_rates", "scratch_rows",
           "sincos"]

# pi/2 in two parts (fdlibm's): k * _PIO2_HI is exact for |k| < 2^20, so the reduction below is
# exact to rounding for |x| < about 8e5 rad, far beyond a chain's joint angles
_PIO2_HI, _PIO2_LO = 1.57079632673412561417e+00, 6.07710050650619224932e-11
_TWO_OVER_PI = 0.63661977236758134308


@numba.njit(cache=True)
def sincos(x):  # pragma: no cover - compiled
    """Return sin x and cos x: reduced to |r| <= pi/4, then Taylor to x^17, x^16."""
    k = math.floor(x * _TWO_OVER_PI + 0.5)
    r = (x - k * _PIO2_HI) - k * _PIO2_LO
    r2 = r * r
    s = r * (1.0 + r2 * (-1.0 / 6 + r2 * (1.0 / 120 + r2 * (-1.0 / 5040 + r2 * (
        1.0 / 362880 + r2 * (-1.0 / 39916800 + r2 * (1.0 / 6227020800 + r2 * (
            -1.0 / 1307674368000 + r2 * (1.0 / 355687428096000)))))))))
    c = 1.0 + r2 * (-0.5 + r2 * (1.0 / 24 + r2 * (-1.0 / 720 + r2 * (1.0 / 40320 + r2 * (
        -1.0 / 3628800 + r2 * (1.0 / 479001600 + r2 * (-1.0 / 87178291200 + r2 * (
            1.0 / 20922789888000))))))))
    q = np.int64(k) & 3
    sq = c if q & 1 else s  # the quadrant: sin and cos swapped and signed
    cq = s if q & 1 else c
    sq = -sq if q & 2 else sq
    cq = -cq if (q + 1) & 2 else cq
    return sq, cq


def param_rows(n: int, m: int, damped: bool, gained: bool) -> dict[str, int]:
    """Return the first row of each block in P: L, mass, off, Ma, Mb, k, F, u0, C, B0, G, end.

    L, mass, off: :class:`~.planar_batch.PlanarLinks`' lengths, masses and centre-of-mass
    offsets; Ma, Mb: :func:`mass_rows`; k: the springs; F: a constant tip force.
    """
    rows, at = {}, 0
    for name, size in (("L", n + 1), ("mass", n), ("off", n), ("Ma", n), ("Mb", n), ("k", n),
                       ("F", 3),
                       ("u0", m), ("C", n * n if damped else 0), ("B0", n * m),
                       ("G", 2 * n * m if gained else 0)):
        rows[name] = at
        at += size
    rows["end"] = at
    return rows


def mass_rows(links) -> tuple[np.ndarray, np.ndarray]:
    """Return the constants a_k, b_k (B, n) of M(q)'s recursion from the tip down.

    With mu_k the mass of links k..n-1 beyond joint k and the step p_(k+1) - p_k = L_(k+1) e_k,

        T_k = T_(k+1) + a_k e_k,                     a_k = mu_(k+1) L_(k+1) + m_k d_k,
        S_k = S_(k+1) + 2 L_(k+1) e_k . T_(k+1) + b_k,  b_k = mu_(k+1) L_(k+1)^2 + m_k d_k^2 + I_k,

    the sums S_k, T_k of the module's docstring in n steps instead of n^2 / 2 terms.
    """
    m, d, L = links.mass_kg, links.com_offset_m, links.lengths_m[:, 1:]
    beyond = np.zeros_like(m)
    beyond[:, :-1] = np.add.accumulate(m[:, ::-1], axis=1)[:, ::-1][:, 1:]
    return beyond * L + m * d, beyond * L * L + m * d * d + links.inertia_yy_kg_m2


def scratch_rows(n: int, m: int) -> int:
    """Rows of the scratch array :func:`block_rates` takes (S, shape (rows, W))."""
    return 11 * n + n * n + m + 15


@numba.njit(cache=True, error_model="numpy", fastmath={"contract"})
def block_rates(P, n, m, damped, gained, ft, ut, T, x, out, S):  # pragma: no cover
    """Write the rates (v, a) (2n, W) of a block at its states x = (q, v) (2n, W) into out.

    P: the block's constants (:func:`param_rows`); ft (3,) and ut (m,): the tip force and the
    inputs' shared functions of time at this stage; T (3, m): which inputs are tip forces; S:
    scratch. A matrix that is not positive definite gives NaN accelerations (the integrator's
    error check sees them).
    """
    W = x.shape[1]
    oL, om, oo, oMa, oMb, ok = 0, n + 1, 2 * n + 1, 3 * n + 1, 4 * n + 1, 5 * n + 1
    oF, ou = 6 * n + 1, 6 * n + 4
    oC = ou + m
    oB = oC + (n * n if damped else 0)
    oG = oB + n * m
    # scratch rows: per joint (co, si, px, pz, cx, cz, ax, az, w2, rhs, tau), M, u, singles
    co, si, px, pz, cx, cz = 0, n, 2 * n, 3 * n, 4 * n, 5 * n
    ax, az, w2, rh, ta = 6 * n, 7 * n, 8 * n, 9 * n, 10 * n
    oM = 11 * n
    uu = oM + n * n
    z = uu + m
    phi, w, jx, jz, tc, tax, taz, rc = z, z + 1, z + 2, z + 3, z + 4, z + 5, z + 6, z + 7
    rs, fx, fz, s_, tx, tz, acc = z + 8, z + 9, z + 10, z + 11, z + 12, z + 13, z + 14
    for b in range(W):
        S[phi, b] = 0.0
        S[w, b] = 0.0
        S[jx, b] = 0.0
        S[jz, b] = 0.0
    for i in range(n):
        for b in range(W):
            p = S[phi, b] + x[i, b]
            S[phi, b] = p
            sn, cs = sincos(p)
            S[co + i, b] = cs
            S[si + i, b] = sn
            v = S[w, b] + x[n + i, b]
            S[w, b] = v
            S[w2 + i, b] = v * v
            out[i, b] = x[n + i, b]
    for b in range(W):
        S[px, b] = P[oL, b]
        S[pz, b] = 0.0
        _com(P, S, b, 0, om, oo, co, si, px, pz, cx, cz, ax, az, w2, jx, jz)
    for i in range(1, n):
        for b in range(W):
            Li, c0, s0, v2 = P[oL + i, b], S[co + i - 1, b], S[si + i - 1, b], S[w2 + i - 1, b]
            S[px + i, b] = S[px + i - 1, b] + Li * c0
            S[pz + i, b] = S[pz + i - 1, b] + Li * s0
            S[jx, b] -= Li * v2 * c0
            S[jz, b] -= Li * v2 * s0
            _com(P, S, b, i, om, oo, co, si, px, pz, cx, cz, ax, az, w2, jx, jz)
    # the inputs u = u0 + u(t) - G x, their joint torques B0 u and tip forces T u
    for r in range(m):
        for b in range(W):
            S[uu + r, b] = P[ou + r, b] + ut[r]
        if gained:
            for c in range(2 * n):
                for b in range(W):
                    S[uu + r, b] -= P[oG + r * 2 * n + c, b] * x[c, b]
    for b in range(W):
        S[fx, b] = P[oF, b] + ft[0]
        S[fz, b] = P[oF + 2, b] + ft[2]
    for r in range(m):
        for b in range(W):
            S[fx, b] += T[0, r] * S[uu + r, b]
            S[fz, b] += T[2, r] * S[uu + r, b]
    for j in range(n):
        for b in range(W):
            S[ta + j, b] = -P[ok + j, b] * x[j, b]
        for r in range(m):
            for b in range(W):
                S[ta + j, b] += P[oB + j * m + r, b] * S[uu + r, b]
        if damped:
            for p in range(n):
                for b in range(W):
                    S[ta + j, b] -= P[oC + j * n + p, b] * x[n + p, b]
    # from the tip down: h_j = sum_(i >= j) (c_i - p_j) x m_i a_i; J^T F by lever arms
    for b in range(W):
        S[tc, b] = 0.0
        S[tax, b] = 0.0
        S[taz, b] = 0.0
        S[rc, b] = 0.0
        S[rs, b] = 0.0
    for j in range(n - 1, -1, -1):
        for b in range(W):
            S[tc, b] += S[cx + j, b] * S[az + j, b] - S[cz + j, b] * S[ax + j, b]
            S[tax, b] += S[ax + j, b]
            S[taz, b] += S[az + j, b]
            S[rc, b] += P[oL + j + 1, b] * S[co + j, b]
            S[rs, b] += P[oL + j + 1, b] * S[si + j, b]
            S[rh + j, b] = (S[ta + j, b] - (S[tc, b] - (S[px + j, b] * S[taz, b]
                                                       - S[pz + j, b] * S[tax, b]))
                            - S[fx, b] * S[rs, b] - S[fz, b] * S[rc, b])
    # S_k and T_k from the tip down (:func:`mass_rows`' constants a_k, b_k), then row k of M
    for b in range(W):
        S[s_, b] = 0.0
        S[tx, b] = 0.0
        S[tz, b] = 0.0
    for k in range(n - 1, -1, -1):
        for b in range(W):
            c, sn, Lk = S[co + k, b], S[si + k, b], P[oL + k + 1, b]
            S[s_, b] += 2.0 * Lk * (c * S[tx, b] + sn * S[tz, b]) + P[oMb + k, b]
            S[tx, b] += P[oMa + k, b] * c
            S[tz, b] += P[oMa + k, b] * sn
        for j in range(k + 1):
            for b in range(W):
                S[oM + k * n + j, b] = S[s_, b] + (S[px + k, b] - S[px + j, b]) * S[tx, b] \
                    + (S[pz + k, b] - S[pz + j, b]) * S[tz, b]
    _ldl_solve(S, n, oM, rh, co, si, acc, out)


@numba.njit(cache=True)
def _com(P, S, b, i, om, oo, co, si, px, pz, cx, cz, ax, az, w2, jx, jz):  # pragma: no cover
    """Centre of mass i and its acceleration at zero joint accelerations, times its mass."""
    d, c, s, v2, mi = P[oo + i, b], S[co + i, b], S[si + i, b], S[w2 + i, b], P[om + i, b]
    S[cx + i, b] = S[px + i, b] + d * c
    S[cz + i, b] = S[pz + i, b] + d * s
    S[ax + i, b] = mi * (S[jx, b] - d * v2 * c)
    S[az + i, b] = mi * (S[jz, b] - d * v2 * s)


@numba.njit(cache=True, error_model="numpy", fastmath={"contract"})
def _ldl_solve(S, n, oM, rh, dd, inv, acc, out):  # pragma: no cover - compiled
    """Solve M a = rhs for every design by M = L D L^T (M's lower triangle at rows oM).

    L (unit lower) is factored in place, D into rows dd and its reciprocal into rows inv (the
    cosines' and sines' rows, no longer needed); a into out[n:]. No square roots (a
    vectorised square root costs as much as a dozen multiplications); a non-positive pivot
    is NaN, and so is a.
    """
    W = S.shape[1]
    for j in range(n):
        for b in range(W):
            S[acc, b] = S[oM + j * n + j, b]
        for p in range(j):
            for b in range(W):
                lj = S[oM + j * n + p, b]
                S[acc, b] -= lj * lj * S[dd + p, b]
        for b in range(W):
            d = S[acc, b] if S[acc, b] > 0.0 else np.nan
            S[dd + j, b] = d
            S[inv + j, b] = 1.0 / d
        for i in range(j + 1, n):
            for p in range(j):
                for b in range(W):
                    S[oM + i * n + j, b] -= S[oM + i * n + p, b] * S[oM + j * n + p, b] \
                        * S[dd + p, b]
            for b in range(W):
                S[oM + i * n + j, b] *= S[inv + j, b]
    for i in range(n):
        for b in range(W):
            out[n + i, b] = S[rh + i, b]
        for p in range(i):
            for b in range(W):
                out[n + i, b] -= S[oM + i * n + p, b] * out[n + p, b]
    for i in range(n - 1, -1, -1):
        for b in range(W):
            out[n + i, b] *= S[inv + i, b]
        for p in range(i + 1, n):
            for b in range(W):
                out[n + i, b] -= S[oM + p * n + i, b] * out[n + p, b]


def batch_state_rates(links, Y: np.ndarray, stiffness_Nm_per_rad: np.ndarray,
                      damping_Nms_per_rad: np.ndarray | None, tau_Nm: np.ndarray | None,
                      force_N: np.ndarray | None) -> np.ndarray:
    """Return the rates (v, a) (B, 2n) of B planar chains at their own states Y = (q, v).

    a = M(q)^-1 (tau - K q - C v - h(q, v) + J(q)^T F) per design: the B designs as one block
    of :func:`block_rates` (the torques tau as an input of unit map).

    Parameters
    ----------
    links : PlanarLinks
        The designs (:func:`prbdm_pin.chain.planar_batch.design_links`).
    Y : ndarray, shape (B, 2n)
        Joint angles (rad) and rates (rad/s).
    stiffness_Nm_per_rad : ndarray, shape (B, n)
        Joint springs K (diagonal), N m/rad.
    damping_Nms_per_rad : ndarray, shape (B, n, n), or None
        Damping matrices C, N m s/rad.
    tau_Nm : ndarray, shape (B, n), or None
        Other joint torques (the inputs'), N m.
    force_N : ndarray, shape (B, 3) or (3,), or None
        World-frame tip forces, N.

    Returns
    -------
    ndarray, shape (B, 2n)
    """
    B, n2 = Y.shape
    n = n2 // 2
    damped = damping_Nms_per_rad is not None
    m = 0 if tau_Nm is None else n
    rows = param_rows(n, m, damped, False)
    P = np.zeros((rows["end"], B))
    Ma, Mb = mass_rows(links)
    for name, a in (("L", links.lengths_m), ("mass", links.mass_kg),
                    ("off", links.com_offset_m), ("Ma", Ma), ("Mb", Mb),
                    ("k", stiffness_Nm_per_rad)):
        P[rows[name]:rows[name] + a.shape[1]] = a.T
    if force_N is not None:
        P[rows["F"]:rows["F"] + 3] = np.broadcast_to(force_N, (B, 3)).T
    if damped:
        P[rows["C"]:rows["C"] + n * n] = damping_Nms_per_rad.reshape(B, n * n).T
    if m:
        P[rows["u0"]:rows["u0"] + n] = tau_Nm.T
        P[rows["B0"]:rows["B0"] + n * n] = np.eye(n).reshape(n * n, 1)
    out = np.empty((n2, B))
    block_rates(P, n, m, damped, False, np.zeros(3), np.zeros(m), np.zeros((3, m)),
                np.ascontiguousarray(Y.T), out, np.empty((scratch_rows(n, m), B)))
    return out.T.copy()
