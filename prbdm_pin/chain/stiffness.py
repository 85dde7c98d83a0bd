"""Pose sweep (the paper's equations 10-11) and joint stiffness laws (equation 14, finite segments).

Also the check of a model's joint springs.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import BeamInputError
from ..member.geometry import Beam
from ..options.checks import check_float
from ..options.choices import EPS_RAD, MIN_FRACTION, XI_RAD
from ..options.validate import check_joints, check_modulus, check_type
from .layout import validate_lengths
from .sections import LinkSections
from .stiffness_law import inverse_moment_integral, inverse_section_integral

__all__ = [
    "MAX_POSES",
    "pose_sweep",
    "paper_stiffness",
    "paper_unit_stiffness",
    "finite_segment_stiffness",
    "finite_segment_stiffness_unchecked",
    "inv_width_integral",
    "validate_stiffness",
]


# the most poses a sweep may have (each is a generalized eigensolve per evaluation)
MAX_POSES = 1000


def pose_sweep(
    n_joints: int, xi: float = XI_RAD, eps: float = EPS_RAD, max_tip_angle_rad: float = math.pi / 2
) -> np.ndarray:
    """Return the poses of the paper's sweep (equations 10-11), rad, shape (m, n_joints).

    Pose i = 0, 1, ... has every joint at ``xi + i * eps`` while the tip link's world angle
    ``n_joints * (xi + i * eps)`` stays within ``max_tip_angle_rad`` (a 1e-12 relative slack keeps
    a pose that lands exactly on the limit).

    Parameters
    ----------
    n_joints : int
        Number of joints n (>= 1).
    xi : float
        Joint angle of the first pose, rad.
    eps : float
        Step of the joint angle from pose to pose, rad.
    max_tip_angle_rad : float
        Largest world angle of the tip link, rad.

    Returns
    -------
    ndarray, shape (m, n_joints)
        The poses' joint angles, rad.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> poses = pp.pose_sweep(2)  # rad, xi = 0.05, eps = 0.1
    >>> poses.shape  # 2 (0.05 + 0.1 i) <= pi / 2 holds for i = 0, ..., 7
    (8, 2)
    >>> poses[:3, 0]
    array([0.05, 0.15, 0.25])
    >>> float(np.floor((np.pi / 2 / 2 - 0.05) / 0.1)) + 1  # the count by hand
    8.0
    """
    n_joints = check_joints(n_joints, "n_joints")
    for name, v in (("xi", xi), ("eps", eps), ("max_tip_angle", max_tip_angle_rad)):
        check_float(name, v, unit="rad")
    if eps <= 0.0:
        raise BeamInputError(f"eps = {eps}: must be > 0 (rad)")
    if xi < 0.0 or n_joints * xi > max_tip_angle_rad * (1 + 1e-12):
        raise BeamInputError(
            f"xi = {xi}: must be >= 0 with n_joints * xi <= max_tip_angle ({max_tip_angle_rad})"
        )
    ratio = (max_tip_angle_rad * (1 + 1e-12) / n_joints - xi) / eps  # inf for a subnormal eps
    if not ratio < MAX_POSES:
        raise BeamInputError(f"eps = {eps!r}: the sweep from xi = {xi:g} to a tip angle of "
                             f"{max_tip_angle_rad:g} rad would have more than {MAX_POSES} poses; "
                             "give a larger step (rad)")
    m = int(math.floor(ratio)) + 1
    angles = xi + eps * np.arange(m)
    return np.repeat(angles[:, None], int(n_joints), axis=1)


def paper_stiffness(sections: LinkSections, E_Pa: float, k: float | np.ndarray) -> np.ndarray:
    """Joint stiffness of the paper's equation 14, N m/rad.

    Joint j (0-based) drives link j + 1 and uses its properties: K_j = k sqrt(E I_(j+1) / m_(j+1)),
    with I the link's mean bending area moment (m^4) and m its mass (kg).

    Parameters
    ----------
    sections : LinkSections
    E_Pa : float
        Young's modulus, Pa.
    k : float or array_like, shape (m,)
        Stiffness correction factor(s) (SCF), one per pose.

    Returns
    -------
    ndarray, shape (n,) for a scalar k, (m, n) for an array of k.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> sec = pp.link_sections(beam, [0.2, 0.5, 0.3])
    >>> pp.paper_stiffness(sec, beam.material.E_Pa, 1.0).round(3)  # N m/rad
    array([20.863, 26.933])
    >>> I, m = 0.05 * 0.01**3 / 12, 7850.0 * 0.05 * 0.01 * np.array([0.5, 0.3])  # m^4, kg
    >>> np.sqrt(205e9 * I / m).round(3)  # k sqrt(E I / m) of links 1 and 2
    array([20.863, 26.933])
    >>> pp.paper_stiffness(sec, beam.material.E_Pa, [1.0, 2.0]).shape  # one row per factor k
    (2, 2)
    """
    check_type("sections", sections, LinkSections, "a prbdm_pin.LinkSections (link_sections)")
    base = paper_unit_stiffness(check_modulus("E_Pa", E_Pa), sections.area_moment_m4,
                                sections.mass_kg)
    k_arr = np.asarray(k, dtype=float)
    if k_arr.ndim > 1:
        raise BeamInputError(f"k has shape {k_arr.shape}: must be a scalar or 1-D (one per pose)")
    bad = np.flatnonzero(~(np.isfinite(k_arr.reshape(-1)) & (k_arr.reshape(-1) > 0)))
    if bad.size:
        i = int(bad[0])
        raise BeamInputError(f"k[{i}] = {k_arr.reshape(-1)[i]}: must be finite and > 0")
    return k_arr[..., None] * base if k_arr.ndim else float(k_arr) * base


def paper_unit_stiffness(E_Pa: float, area_moment_m4: np.ndarray,
                         mass_kg: np.ndarray) -> np.ndarray:
    """Equation 14 at unit SCF, ``sqrt(E I_(j+1) / m_(j+1))``, N m/rad, shape (..., n).

    ``area_moment_m4`` (m^4) and ``mass_kg`` (kg) are the links' mean bending area moments and
    masses, shape (..., n+1): one design, or a stack of designs (the fit's inner loop).
    """
    return np.sqrt(E_Pa * area_moment_m4[..., 1:] / mass_kg[..., 1:])


def inv_width_integral(beam: Beam, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Exact ∫_a^b dx / w(x) for the piecewise-linear half-width w, per interval, 1/m * m.

    Under a thickness law the integrand is 1 / (w t^3) (m^-3, to rounding: see
    :mod:`~prbdm_pin.chain.stiffness_law`); for a round member it is 1 / E I_y (1/(N m)).

    ``a``, ``b`` are (k,) or stacks (B, k) of interval ends. All intervals at once: their ends
    and the planform vertices cut the axis into sub-intervals where w is linear; each
    sub-interval's integral is added to every interval containing it (called in the fit's
    inner loop: no Python loop over intervals or vertices).
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    x = beam.x_m
    a2, b2 = a.reshape(-1, a.shape[-1]), b.reshape(-1, b.shape[-1])
    B, k = a2.shape
    cuts = np.empty((B, 2 * k + x.size))
    cuts[:, :k] = a2
    cuts[:, k:2 * k] = b2
    cuts[:, 2 * k:] = x
    cuts.sort(axis=1)
    u, v, part = _sub_integrals(beam, cuts)
    mid = (0.5 * (u + v))[:, :, None]
    inside = (mid > a2[:, None, :]) & (mid < b2[:, None, :])  # (B, s, k)
    return np.add.reduce(np.where(inside, part[:, :, None], 0.0), axis=1).reshape(a.shape)


def _sub_integrals(beam: Beam, cuts: np.ndarray):
    """Return u, v (m) and the exact ∫_u^v dx / w (dimensionless) of each sub-interval.

    The sub-intervals [u, v] lie between consecutive sorted ``cuts`` (B, c), m, which include
    the planform vertices, so w is linear on each; empty sub-intervals give exact zeros.
    """
    if beam.section is not None:  # a section law: the integral is of 1 / E I_y (1/(N m))
        return inverse_section_integral(beam, cuts)
    if beam.thickness_law_m is not None:
        # under a thickness law the integral is of 1 / (w t^3) (m^-3), see stiffness_law
        return inverse_moment_integral(beam, cuts)
    u, v = cuts[:, :-1], cuts[:, 1:]
    # w on [u, v] from its ends' one-sided limits (they differ at a width step)
    if beam.step_index.size:
        wu = beam.half_width_at(u, "right")
        wv = beam.half_width_at(v, "left")
    else:  # no step (the common case, in the fit's inner loop): one interpolation
        w = np.interp(cuts, beam.x_m, beam.half_width_m)
        wu, wv = w[:, :-1], w[:, 1:]
    d = (wv - wu) / wu
    # ∫ dx / w over [u, v] with w linear: (v - u) ln(wv / wu) / (wv - wu)
    small = np.abs(d) < 1e-8
    ratio = np.where(small, 1.0 - 0.5 * d + d * d / 3.0, np.log1p(d) / np.where(small, 1, d))
    return u, v, (v - u) * ratio / wu


def finite_segment_stiffness(
    beam: Beam, lengths_m: np.ndarray, min_fraction: float = MIN_FRACTION
) -> np.ndarray:
    """Physical joint stiffness of the finite-segment law, N m/rad, shape (n,).

    Joint j joins links j and j + 1; its spring stands for the beam between their centres
    c_j and c_(j+1) (the geometric mid-points of the links' spans, not their centres of mass),
    so K_j = E / ∫_(c_j)^(c_(j+1)) dx / I(x) with I(x) = 2 w(x) t^3 / 12. The end links are
    the exception: the clamped link 0 counts from the clamp (c_0 = 0) and the tip link to the
    tip (c_n = L), so the springs' spans tile the whole beam and the chain's compliance under a
    tip moment equals the beam's. (Counting from the mid-points of the end links would treat the
    beam over [0, L_0/2] and [L - L_n/2, L] as rigid: the equal-segment chain with links
    [h/2, h, ..., h, h/2] would then converge only as 1/N instead of getting K = EI/h at every
    joint.) The integral is exact for the piecewise-linear planform (logarithms on each vertex
    interval).

    Parameters
    ----------
    beam : Beam
        Supplies the planform, thickness (m) and Young's modulus (Pa).
    lengths_m : array_like, shape (n+1,)
        Link lengths in m, validated as by :func:`~prbdm_pin.chain.layout.validate_lengths`.
    min_fraction : float
        The bound f of Eq. 15 on each link (a fraction of L; default 0.02).

    Returns
    -------
    ndarray, shape (n,)
        The joint springs, N m/rad.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> pp.finite_segment_stiffness(beam, [0.2, 0.5, 0.3]).round(2)  # N m/rad
    array([1898.15, 1553.03])
    >>> EI = 205e9 * 0.05 * 0.01**3 / 12  # N m^2
    >>> round(EI / (0.45 - 0.0), 2), round(EI / (1.0 - 0.45), 2)  # EI / span: [0, 0.45], [0.45, L]
    (1898.15, 1553.03)
    """
    return finite_segment_stiffness_unchecked(beam, validate_lengths(beam, lengths_m, min_fraction))


def finite_segment_stiffness_unchecked(beam: Beam, lengths: np.ndarray) -> np.ndarray:
    """Compute :func:`finite_segment_stiffness` for lengths already validated, N m/rad.

    Shape (n,), or (B, n) for a stack of designs (B, n+1) (the fit's inner loop).
    """
    ends = np.add.accumulate(lengths, axis=-1)
    centres = ends - 0.5 * lengths
    centres[..., 0] = 0.0
    centres[..., -1] = ends[..., -1]
    n = lengths.shape[-1] - 1
    if lengths.ndim > 1 or n < 2:
        integral = inv_width_integral(beam, centres[..., :-1], centres[..., 1:])  # ∫ dx / w
    else:
        # one design (the fit's inner loop): the springs' spans tile the beam, so one
        # bincount adds each sub-interval to the span its middle lies strictly inside, in
        # order, where inv_width_integral masks every sub-interval against every span (the
        # same sums: for one spring its reduction runs in another order, so it keeps that
        # path); a middle on a span end, or beyond the last span, goes to none (bin n)
        cuts = np.empty((1, n + 1 + beam.x_m.size))
        cuts[0, :n + 1] = centres
        cuts[0, n + 1:] = beam.x_m
        cuts.sort(axis=1)
        u, v, part = _sub_integrals(beam, cuts)
        mid = 0.5 * (u[0] + v[0])
        above = centres.searchsorted(mid)
        span = np.where(above == centres.searchsorted(mid, "right"), above - 1, n)
        integral = np.bincount(span, part[0], n + 1)[:n]
    if beam.section is not None:  # the integral holds 1 / E I_y already
        return 1.0 / integral
    if beam.thickness_law_m is not None:  # the integral holds 1 / t^3 already
        return beam.material.E_Pa * (2.0 / 12.0) / integral
    t = beam.thickness_m
    return beam.material.E_Pa * (2.0 * t**3 / 12.0) / integral


def validate_stiffness(stiffness_Nm_per_rad: Any, n_joints: int) -> np.ndarray:
    """Joint stiffness as a read-only (n,) array, N m/rad; BeamInputError names a bad value."""
    if isinstance(stiffness_Nm_per_rad, (str, bytes, dict)):
        raise BeamInputError(f"stiffness = {stiffness_Nm_per_rad!r}: must be numbers (N m/rad)")
    try:
        k = np.array(stiffness_Nm_per_rad, dtype=float)
    except (TypeError, ValueError):
        raise BeamInputError(
            f"stiffness = {stiffness_Nm_per_rad!r}: must be numbers (N m/rad)"
        ) from None
    if k.ndim == 0:
        k = k.reshape(1)
    if k.shape != (n_joints,):
        raise BeamInputError(
            f"stiffness has shape {k.shape}: needs {n_joints} values, one per joint (N m/rad)"
        )
    # subnormal springs (< 2.2e-308) carry too few digits to compute with
    bad = np.flatnonzero(~(np.isfinite(k) & (k >= np.finfo(float).tiny)))
    if bad.size:
        i = int(bad[0])
        raise BeamInputError(
            f"stiffness[{i}] = {k[i]}: must be finite and > 0, a normal double (N m/rad)"
        )
    k.setflags(write=False)
    return k
