"""The exact planform integrals of a member of one thickness, in compiled calls (numba).

The links' properties (:func:`prbdm_pin.chain.sections.link_sections`: the area, its first
and second moment in x about the mid-span and its y^2 moment by two-point Gauss on every
sub-interval between planform vertices and link ends, and the masses, centres and inertias
made of them) and the finite-segment springs' ∫ dx / w
(:func:`prbdm_pin.chain.stiffness.finite_segment_stiffness`, logarithms on every
sub-interval between vertices and span ends). Written as loops: their numpy form spent about
50 us of a 5-joint fit evaluation in numpy's calls on a dozen numbers each, for arithmetic
that takes well under a microsecond. The sums run in the order the numpy form ran them
(sub-intervals from the root, Gauss points in order) and the half-width is interpolated as
``numpy.interp`` does, so the numbers are the numpy form's to the bit.

A thickness law and a section law keep their numpy paths. Imported on first use only (the
package's import and the CLI do not load numba).
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["planform_properties", "inverse_width_spans", "segment_centres", "segment_springs"]

# two-point Gauss-Legendre on [0, 1]: exact for polynomials up to degree 3
_T0 = 0.5 - 0.5 / math.sqrt(3.0)
_T1 = 0.5 + 0.5 / math.sqrt(3.0)

# one signature each; inputs read-only (a writable array converts)
_IN1 = numba.types.Array(numba.float64, 1, "A", readonly=True)
_IN2 = numba.types.Array(numba.float64, 2, "A", readonly=True)
_OUT2 = numba.types.Array(numba.float64, 2, "C")
_OUT3 = numba.types.Array(numba.float64, 3, "C")


@numba.njit(cache=True)
def _advance(j, x, xp):  # pragma: no cover - compiled
    """Return the last i >= j with xp[i] <= x (xp ascending, xp[j] <= x): numpy.interp's search.

    The callers' abscissae ascend, so the search walks on from the last one's index.
    """
    while j + 1 < xp.size and xp[j + 1] <= x:
        j += 1
    return j


@numba.njit(cache=True)
def _interp_at(j, x, xp, fp):  # pragma: no cover - compiled
    """numpy.interp(x, xp, fp) for one x whose search gave j, with its arithmetic and clamping."""
    last = xp.size - 1
    if x > xp[last]:
        return fp[last]
    if x < xp[0]:
        return fp[0]
    if j == last or xp[j] == x:
        return fp[j]
    slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
    return slope * (x - xp[j]) + fp[j]


@numba.njit(cache=True)
def _sort_small(a):  # pragma: no cover - compiled
    """Sort a short array in place (insertion: a few tens of entries, mostly in order)."""
    for i in range(1, a.size):
        x = a[i]
        j = i - 1
        while j >= 0 and a[j] > x:
            a[j + 1] = a[j]
            j -= 1
        a[j + 1] = x


@numba.njit(numba.types.void(_IN1, _IN1, numba.float64, numba.float64, numba.float64,
                             numba.float64, _IN2, _OUT3), cache=True)
def planform_properties(xv, hw, length, rho_t, t3_12, t2_12, lengths,
                        out):  # pragma: no cover - compiled
    """Compute the links' properties of B designs of a member of one thickness at once.

    Parameters
    ----------
    xv, hw : ndarray (v,)
        Planform vertices along the axis and half-widths there, m (piecewise linear).
    length : float
        The member's length, m (the tip is the member's end, not a rounded sum).
    rho_t, t3_12, t2_12 : float
        rho t (kg/m^2), t^3 / 12 (m^3) and t^2 / 12 (m^2) of the thickness t.
    lengths : ndarray (B, nl)
        Link lengths of B designs, m.
    out : ndarray (12, B, nl)
        Receives per link: start, end and mid-span (m); mass (kg); the centre of mass's offset
        from the mid-span (m); rho t times the second moments about the centre of mass in x
        and in y (kg m^2); the thickness term m t^2 / 12 (kg m^2); the mean bending area
        moment (m^4); Izz about the centre of mass (kg m^2); the centre of mass's distance
        from the link's start (m) and the inertia about it around y (kg m^2).

    The planform integrals (area, its first and second moment in x about the mid-span and
    the y^2 moment 2 w^3 / 3) by two-point Gauss on every sub-interval between vertices and
    link ends.
    """
    B, nl = lengths.shape
    nv = xv.size
    cuts = np.empty(nv + nl)
    A = np.empty(nl)
    S1 = np.empty(nl)
    S2 = np.empty(nl)
    Syy = np.empty(nl)
    for b in range(B):
        starts, ends, mids = out[0, b], out[1, b], out[2, b]
        acc = 0.0
        for i in range(nl):
            starts[i] = acc
            acc += lengths[b, i]
            ends[i] = acc
        ends[nl - 1] = length
        for i in range(nl):
            mids[i] = 0.5 * (starts[i] + ends[i])
            A[i] = 0.0
            S1[i] = 0.0
            S2[i] = 0.0
            Syy[i] = 0.0
        # sub-intervals between all planform vertices and link ends (an empty one where
        # an end meets a vertex adds exact zeros)
        cuts[:nv] = xv
        cuts[nv:] = ends
        _sort_small(cuts)
        link = 0
        j = 0
        for k in range(nv + nl - 1):
            u = cuts[k]
            v = cuts[k + 1]
            centre = 0.5 * (u + v)
            while link < nl - 1 and ends[link] < centre:  # the link the middle lies in
                link += 1
            h = v - u
            s0 = 0.0
            s1 = 0.0
            s2 = 0.0
            s3 = 0.0
            for g in range(2):
                xg = u + h * (_T0 if g == 0 else _T1)
                j = _advance(j, xg, xv)
                wg = _interp_at(j, xg, xv, hw)
                xl = xg - mids[link]
                w2 = 2.0 * wg
                f1 = w2 * xl
                s0 += w2
                s1 += f1
                s2 += f1 * xl
                s3 += w2 * wg * wg / 3.0
            half = 0.5 * h
            A[link] += s0 * half
            S1[link] += s1 * half
            S2[link] += s2 * half
            Syy[link] += s3 * half
        for i in range(nl):
            mass = rho_t * A[i]
            dx = S1[i] / A[i]  # the centre of mass's offset from the mid-span
            Sxx_c = S2[i] - A[i] * dx * dx  # second moment about the centre of mass
            Ixx_c = rho_t * Sxx_c
            thick = mass * t2_12
            out[3, b, i] = mass
            out[4, b, i] = dx
            out[5, b, i] = Ixx_c
            out[6, b, i] = rho_t * Syy[i]
            out[7, b, i] = thick
            out[8, b, i] = A[i] * t3_12 / (ends[i] - starts[i])  # mean of 2 w t^3 / 12
            out[9, b, i] = rho_t * (Sxx_c + Syy[i])
            out[10, b, i] = mids[i] + dx - starts[i]
            out[11, b, i] = Ixx_c + thick


@numba.njit(cache=True)
def _spans(xv, hw, a, b, out, cuts):  # pragma: no cover - compiled
    """Write the exact ∫_a^b dx / w(x) of the spans (a, b) (k,) of one design into ``out``.

    ``cuts`` (2 k + v,) scratch. Each sub-interval between all span ends and vertices is added,
    from the root, to every span its middle lies strictly inside. On a sub-interval [u, v] w
    is linear, with its one-sided limits at a width step, and
    ∫ dx / w = (v - u) ln(wv / wu) / (wv - wu), by its series where wv / wu - 1 < 1e-8.
    """
    k = a.size
    nv = xv.size
    cuts[:k] = a
    cuts[k:2 * k] = b
    cuts[2 * k:] = xv
    _sort_small(cuts)
    for i in range(k):
        out[i] = 0.0
    j = 0
    for s in range(2 * k + nv - 1):
        u = cuts[s]
        v = cuts[s + 1]
        mid = 0.5 * (u + v)
        # the vertex interval [xv[j], xv[j + 1]] holding [u, v]: the tip side of a step
        j = min(_advance(j, mid, xv), nv - 2)
        slope = (hw[j + 1] - hw[j]) / (xv[j + 1] - xv[j])
        wu = hw[j] if u == xv[j] else slope * (u - xv[j]) + hw[j]
        wv = hw[j + 1] if v == xv[j + 1] else slope * (v - xv[j]) + hw[j]
        dw = (wv - wu) / wu
        if abs(dw) < 1e-8:
            ratio = 1.0 - 0.5 * dw + dw * dw / 3.0
        else:
            ratio = math.log1p(dw) / dw
        part = (v - u) * ratio / wu
        for i in range(k):
            if mid > a[i] and mid < b[i]:
                out[i] += part


@numba.njit(numba.types.void(_IN1, _IN1, _IN2, _IN2, _OUT2), cache=True)
def inverse_width_spans(xv, hw, a, b, out):  # pragma: no cover - compiled
    """Compute the exact ∫_a^b dx / w(x) over spans of B designs, 1/m * m.

    Parameters
    ----------
    xv, hw : ndarray (v,)
        Planform vertices and half-widths, m; a width step is two vertices at one station.
    a, b : ndarray (B, k)
        Span ends, m, within [xv[0], xv[-1]].
    out : ndarray (B, k)
        Receives the integrals (:func:`_spans`).
    """
    B, k = a.shape
    cuts = np.empty(2 * k + xv.size)
    for d in range(B):
        _spans(xv, hw, a[d], b[d], out[d], cuts)


@numba.njit(numba.types.void(_IN2, _OUT2), cache=True)
def segment_centres(lengths, out):  # pragma: no cover - compiled
    """Write the finite-segment springs' span ends of B designs (B, n+1) into ``out``, m.

    The links' geometric mid-points, except the clamp (0) at the root and the summed lengths
    at the tip (:func:`prbdm_pin.chain.stiffness.finite_segment_stiffness`).
    """
    B, nl = lengths.shape
    for b in range(B):
        acc = 0.0
        for i in range(nl):
            acc += lengths[b, i]
            out[b, i] = acc - 0.5 * lengths[b, i]
        out[b, 0] = 0.0
        out[b, nl - 1] = acc


@numba.njit(numba.types.void(_IN1, _IN1, numba.float64, _IN2, _OUT2), cache=True)
def segment_springs(xv, hw, scale, lengths, out):  # pragma: no cover - compiled
    """Write the finite-segment springs of B designs (B, n+1) of one thickness into ``out``.

    K_j = scale / ∫ dx / w over the span [c_j, c_(j+1)] (:func:`segment_centres`), N m/rad,
    with ``scale`` = E 2 t^3 / 12 (N m).
    """
    B, nl = lengths.shape
    c = np.empty((B, nl))
    segment_centres(lengths, c)
    cuts = np.empty(2 * (nl - 1) + xv.size)
    for b in range(B):
        _spans(xv, hw, c[b, :-1], c[b, 1:], out[b], cuts)
        for j in range(nl - 1):
            out[b, j] = scale / out[b, j]
