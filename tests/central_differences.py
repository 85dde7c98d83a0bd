"""Central differences with a bound on their error, for checking analytic derivatives.

Imported as ``from central_differences import ...`` (pytest puts this folder on ``sys.path``, as
for ``tolerances``); not a test module.

D(h) = (f(x + h) - f(x - h)) / (2 h) is off from f' by its truncation c h^2 + O(h^4) and by its
rounding, at most ``noise / h`` when each value of f carries up to ``noise`` (absolute). D(2h)'s
truncation is 4 c h^2, so |D(h) - D(2h)| = 3 |c| h^2 (to O(h^4), and up to 1.5 noise / h of
rounding) bounds D(h)'s truncation with a factor 3 to spare; the bound adds 2 noise / h for the
rounding of D(h) itself, which the difference may cancel.
"""

from __future__ import annotations

import numpy as np

__all__ = ["central_difference"]


def central_difference(f, x: np.ndarray, steps: np.ndarray, noise) -> tuple[np.ndarray,
                                                                              np.ndarray]:
    """Return D(h) of ``f`` at ``x`` along each coordinate (h = ``steps[i]``) and its error bound.

    ``f`` maps a vector like ``x`` to an array; ``noise`` (scalar or f's shape) is the absolute
    rounding of one value of f. Both results have shape f.shape + (x.size,).
    """
    x = np.asarray(x, dtype=float)
    cols, bounds = [], []
    for i, h in enumerate(np.broadcast_to(steps, x.shape)):
        e = np.zeros_like(x)
        e[i] = h
        d1 = (np.asarray(f(x + e)) - np.asarray(f(x - e))) / (2.0 * h)
        d2 = (np.asarray(f(x + 2.0 * e)) - np.asarray(f(x - 2.0 * e))) / (4.0 * h)
        cols.append(d1)
        bounds.append(np.abs(d1 - d2) + 2.0 * np.asarray(noise) / h)
    return np.stack(cols, axis=-1), np.stack(bounds, axis=-1)
