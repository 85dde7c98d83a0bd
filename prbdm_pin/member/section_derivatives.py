"""Derivatives of the rectangular section's Saint-Venant torsion constant in its two sides.

With a >= c the long and short sides and r = a / c, :func:`.section.torsion_constant_m4` is

    J = a c^3 / 3 - (64 / pi^5) c^4 (lambda(5) - T(r)),   T(r) = sum_(n odd) (1 - tanh z_n) / n^5,

z_n = n pi r / 2. Differentiating the series term by term (it converges like exp(-n pi r), so
the same 14 odd terms give T' to rounding), with T'(r) = -(pi / 2) sum sech^2(z_n) / n^4:

    dJ/da = c^3 / 3 + (64 / pi^5) c^3 T'(r),
    dJ/dc = a c^2 - (256 / pi^5) c^3 (lambda(5) - T(r)) - (64 / pi^5) a c^2 T'(r).

J is homogeneous of degree 4 (a dJ/da + c dJ/dc = 4 J), which the tests check. J is symmetric in
the two sides, so the derivative is continuous through the square (a = c).
"""

from __future__ import annotations

import numpy as np

from .section import _LAMBDA5, _ODD

__all__ = ["torsion_constant_gradient"]


def torsion_constant_gradient(width_m, thickness_m) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return J of a solid rectangle and its derivatives in the width and the thickness.

    Parameters
    ----------
    width_m, thickness_m : array_like
        The sides b and t of the rectangle, m (either may be the longer).

    Returns
    -------
    J : ndarray
        The Saint-Venant torsion constant, m^4 (as :func:`.section.torsion_constant_m4`).
    dJ_db, dJ_dt : ndarray
        dJ/db and dJ/dt, m^3, broadcast shape of the inputs.
    """
    b = np.asarray(width_m, dtype=float)
    t = np.asarray(thickness_m, dtype=float)
    b, t = np.broadcast_arrays(b, t)
    a = np.maximum(b, t)
    c = np.minimum(b, t)
    z = (np.pi / 2.0) * (a / c)[..., None] * _ODD
    # 1 - tanh z = 2 / (e^(2z) + 1) and sech^2 z = 4 e^(-2z) / (1 + e^(-2z))^2: no cancellation
    # and no overflow (e^(-2z) underflows to 0 where the terms do not matter)
    e = np.exp(-np.minimum(2.0 * z, 700.0))
    tail = np.sum(2.0 * e / (1.0 + e) / _ODD**5, axis=-1)
    d_tail = -(np.pi / 2.0) * np.sum(4.0 * e / (1.0 + e) ** 2 / _ODD**4, axis=-1)
    k = 64.0 / np.pi**5
    J = a * c**3 / 3.0 * (1.0 - 3.0 * k * (c / a) * (_LAMBDA5 - tail))
    dJ_da = c**3 / 3.0 + k * c**3 * d_tail
    dJ_dc = a * c * c - 4.0 * k * c**3 * (_LAMBDA5 - tail) - k * a * c * c * d_tail
    long_b = b >= t
    return J, np.where(long_b, dJ_da, dJ_dc), np.where(long_b, dJ_dc, dJ_da)
