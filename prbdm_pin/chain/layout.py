"""Link lengths: validation, joint positions, bounds, uniform sampling and repair on the simplex.

The n + 1 link lengths of a PRBDM live on the bounded simplex
{l : sum(l) = L, f L <= l_i <= (1 - f) L} with f = ``min_fraction`` (the paper's Eq. 15, f = 0.02).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import BeamInputError
from ..options.choices import MIN_FRACTION

__all__ = [
    "DEFAULT_MIN_FRACTION",
    "check_min_fraction",
    "validate_lengths",
    "joint_positions",
    "length_bounds",
    "sample_lengths",
    "repair_lengths",
]

_SUM_RTOL = 1e-9
# Eq. 15: every link at least 2 % of the beam
DEFAULT_MIN_FRACTION = MIN_FRACTION


def check_min_fraction(min_fraction: Any, joints: int, name: str = "min_fraction") -> float:
    """Validate the lower bound f on link lengths (a fraction of L) for an nR fit.

    A fit draws and bounds lengths in [f L, (1 - f) L] on a simplex that is not empty only if
    0 < f < 1 / (n + 1). ``name`` is what the error calls the value (the CLI's ``--min-link``).

    Raises
    ------
    BeamInputError
        Naming ``name`` and the value, and the largest value that fits n + 1 links.
    """
    if isinstance(min_fraction, bool) or not isinstance(min_fraction,
                                                        (int, float, np.integer, np.floating)):
        raise BeamInputError(f"{name} = {min_fraction!r}: must be a number in (0, 1/(n+1))")
    if isinstance(joints, bool) or not isinstance(joints, (int, np.integer)) or joints < 1:
        raise BeamInputError(f"joints = {joints!r}: must be an integer >= 1")
    f = float(min_fraction)
    n = int(joints)
    cap = 1.0 / (n + 1)
    if math.isfinite(f) and f >= cap:
        raise BeamInputError(
            f"{name} = {f:g}: {n + 1} links (n = {n} joints) of at least {f:g} L do not fit in "
            f"L; must be in (0, 1/(n+1)) = (0, {cap:.4g})"
        )
    if not (math.isfinite(f) and f > 0.0):
        raise BeamInputError(f"{name} = {f:g}: must be in (0, 1/(n+1)) = (0, {cap:.4g}) "
                             f"(n = {n} joints)")
    from ..options.choices import LINK_FLOOR_FRACTION

    # a fit must not write links that its own readers refuse
    if f < LINK_FLOOR_FRACTION:
        raise BeamInputError(f"{name} = {f:g}: must be at least {LINK_FLOOR_FRACTION:g} (the "
                             "shortest link a model file may hold, as a fraction of L)")
    return f


def _check_fraction(min_fraction: float, n_links: int) -> None:
    if not (isinstance(min_fraction, (int, float, np.floating)) and 0.0 <= min_fraction < 0.5):
        raise BeamInputError(f"min_fraction = {min_fraction!r}: must be a number in [0, 0.5)")
    if n_links * min_fraction > 1.0 + 1e-12:
        raise BeamInputError(
            f"n_links = {n_links}: {n_links} links of at least {min_fraction} L do not fit in L"
        )


def _check_n_links(n_links: Any) -> int:
    if isinstance(n_links, bool) or not isinstance(n_links, (int, np.integer)) or n_links < 2:
        raise BeamInputError(f"n_links = {n_links!r}: must be an integer >= 2 (n >= 1 joints)")
    return int(n_links)


def validate_lengths(beam: Any, lengths_m: Any, min_fraction: float = MIN_FRACTION) -> np.ndarray:
    """Check link lengths against a beam and return them as a float array.

    Parameters
    ----------
    beam : Beam
        Supplies the length L (m).
    lengths_m : array_like, shape (n+1,)
        Link lengths in m, n >= 1: finite, summing to L (relative tolerance 1e-9), each in
        [min_fraction L, (1 - min_fraction) L].
    min_fraction : float
        The bound f of Eq. 15 (default 0.02).

    Returns
    -------
    ndarray, shape (n+1,)

    Raises
    ------
    BeamInputError
        Naming the field ``lengths`` and the offending value.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> pp.validate_lengths(beam, [0.2, 0.5, 0.3])  # m
    array([0.2, 0.5, 0.3])
    >>> pp.validate_lengths(beam, [0.2, 0.5, 0.2])  # they sum to 0.9 m, not L = 1 m
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: lengths sum to ... m: must ...
    """
    from ..member.geometry import Beam
    from ..options.validate import check_type, real_vector

    check_type("beam", beam, Beam)
    arr = real_vector("lengths", lengths_m, "m")  # finite reals: not complex, not strings
    if arr.size < 2:
        raise BeamInputError(
            f"lengths = {arr.tolist()}: needs at least 2 links (n >= 1 joints), got {arr.size}"
        )
    L = float(beam.length_m)
    _check_fraction(min_fraction, arr.size)
    with np.errstate(over="ignore"):  # lengths near 1e308 overflow the sum: reported below
        total = float(np.sum(arr))
    if not math.isclose(total, L, rel_tol=_SUM_RTOL, abs_tol=0.0):
        raise BeamInputError(f"lengths sum to {total!r} m: must equal the beam length {L} m")
    lo, hi = min_fraction * L, (1.0 - min_fraction) * L
    slack = _SUM_RTOL * L  # bounds hold to the same tolerance as the sum
    bad = np.flatnonzero((arr < lo - slack) | (arr > hi + slack))
    if bad.size:
        i = int(bad[0])
        raise BeamInputError(f"lengths[{i}] = {float(arr[i])!r} m: must lie in [{lo}, {hi}] m")
    return arr.copy()


def joint_positions(lengths_m: np.ndarray) -> np.ndarray:
    """Joint stations x_j = L_0 + ... + L_(j-1) along the beam, m, shape (n,)."""
    return np.cumsum(np.asarray(lengths_m, dtype=float))[:-1]


def length_bounds(
    length_m: float, n_links: int, min_fraction: float = MIN_FRACTION
) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds on each link length, m, each of shape (n_links,)."""
    n_links = _check_n_links(n_links)
    _check_fraction(min_fraction, n_links)
    L = float(length_m)
    return np.full(n_links, min_fraction * L), np.full(n_links, (1.0 - min_fraction) * L)


def sample_lengths(
    rng: np.random.Generator,
    length_m: float,
    n_links: int,
    size: int,
    min_fraction: float = MIN_FRACTION,
) -> np.ndarray:
    """Link lengths drawn uniformly on the bounded simplex, shape (size, n_links), m.

    A flat Dirichlet draw (the same law as the sorted-uniform spacings of Smith & Tromble) scaled
    to the free length L - n_links f L and shifted by the lower bound; draws that break the upper
    bound are redrawn (with n_links >= 2 the upper bound is implied and nothing is redrawn).

    Parameters
    ----------
    rng : numpy.random.Generator
        The only source of randomness.
    length_m : float
        Beam length L, m.
    n_links : int
        Number of links n + 1.
    size : int
        Number of draws.
    min_fraction : float
        The bound f of Eq. 15 on each link (a fraction of L; default 0.02).

    Returns
    -------
    ndarray, shape (size, n_links)
        The drawn link lengths, m.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> draws = pp.sample_lengths(np.random.default_rng(0), 1.0, n_links=3, size=1000)
    >>> draws.shape
    (1000, 3)
    >>> bool(np.allclose(draws.sum(axis=1), 1.0)), bool(draws.min() >= 0.02)  # sum L, each >= f L
    (True, True)
    >>> bool(np.abs(draws.mean(axis=0) - 1 / 3).max() < 0.02)  # a flat draw: L / 3 on average
    True
    """
    from ..options.checks import check_int
    from ..options.validate import check_size, check_type

    check_type("rng", rng, np.random.Generator, "a numpy.random.Generator (default_rng(seed))")
    length_m = check_size("length_m", length_m)
    size = check_int("size", size, 0)
    n_links = _check_n_links(n_links)
    lo, hi = length_bounds(length_m, n_links, min_fraction)
    free = float(length_m) - float(np.sum(lo))
    out = np.empty((int(size), n_links))
    filled = 0
    while filled < out.shape[0]:
        d = rng.dirichlet(np.ones(n_links), out.shape[0] - filled)
        x = lo + free * d
        x = x[np.all(x <= hi, axis=1)]
        out[filled:filled + x.shape[0]] = x
        filled += x.shape[0]
    return out


def repair_lengths(lengths: np.ndarray, length_m: float,
                   min_fraction: float = MIN_FRACTION) -> np.ndarray:
    """Euclidean projection of link lengths onto the bounded simplex (row-wise for 2-D input).

    Solves min ||l - x|| subject to sum(l) = L, lo <= l <= hi: l = clip(x - tau, lo, hi) with the
    scalar tau found by bisection and then made exact on the final active set.

    Parameters
    ----------
    lengths : ndarray, shape (n+1,) or (B, n+1)
        Link lengths to repair, m.
    length_m : float
        Beam length L, m.
    min_fraction : float
        The bound f of Eq. 15: lo = f L, hi = (1 - f) L (default 0.02).

    Returns
    -------
    ndarray, shape of ``lengths``
        The nearest lengths on the bounded simplex, m.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> x = np.array([0.5, 0.6, 0.1])  # m: 0.2 m too long for L = 1 m
    >>> pp.repair_lengths(x, 1.0).round(4)  # m
    array([0.4333, 0.5333, 0.0333])
    >>> (x - (x.sum() - 1.0) / 3).round(4)  # no bound active: the excess shared equally
    array([0.4333, 0.5333, 0.0333])
    >>> pp.repair_lengths(np.array([0.9, 0.3, 0.0]), 1.0).round(4)  # the last link at f L = 0.02 m
    array([0.79, 0.19, 0.02])
    """
    from ..errors import InputTypeError
    from ..options.checks import shown
    from ..options.validate import check_size

    raw = np.asarray(lengths)
    if raw.dtype.kind not in "iuf" or raw.ndim not in (1, 2):
        raise InputTypeError(f"lengths = {shown(lengths)}: must be real numbers (m), of shape "
                             "(n+1,) or (B, n+1)")
    length_m = check_size("length_m", length_m)
    x = raw.astype(float)
    one = x.ndim == 1
    X = np.atleast_2d(x)
    n_links = X.shape[1]
    lo, hi = length_bounds(length_m, n_links, min_fraction)
    lo, hi = lo[0], hi[0]
    L = float(length_m)
    X = np.where(np.isfinite(X), X, L / n_links)
    # sum(clip(x - tau)) is non-increasing in tau; bracket the root
    t_lo = np.min(X, axis=1) - hi
    t_hi = np.max(X, axis=1) - lo
    for _ in range(100):
        tm = 0.5 * (t_lo + t_hi)
        s = np.clip(X - tm[:, None], lo, hi).sum(axis=1)
        big = s > L
        t_lo = np.where(big, tm, t_lo)
        t_hi = np.where(big, t_hi, tm)
    tau = 0.5 * (t_lo + t_hi)
    Y = np.clip(X - tau[:, None], lo, hi)
    free = (Y > lo) & (Y < hi)
    nfree = free.sum(axis=1)
    fixed_sum = np.where(free, 0.0, Y).sum(axis=1)
    ok = nfree > 0
    tau_exact = np.where(
        ok, (np.where(free, X, 0.0).sum(axis=1) - (L - fixed_sum)) / np.maximum(nfree, 1), tau
    )
    Y = np.where(free, X - tau_exact[:, None], Y)
    Y = np.clip(Y, lo, hi)
    return Y[0] if one else Y
