"""Published and prototype reference values the tests compare against, each written once.

Imported as ``from reference import ...``: pytest puts this folder on ``sys.path`` for the test
modules in it (rootdir-relative ``tests/`` without ``__init__.py``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["BETA_L", "ELASTICA", "REF_OMEGA"]

# clamped-free Euler-Bernoulli roots beta_k L of cos(beta L) cosh(beta L) = -1
BETA_L = np.array([1.8751040687120, 4.6940911329742, 7.8547574382376, 10.995540734875,
                   14.137168391046, 17.278759532088])

# inextensible elastica of a uniform cantilever under a tip load perpendicular to its axis:
# P L^2 / EI -> (tip retreat (L - x)/L, tip deflection y/L), Mattiasson (1981) Table 1
ELASTICA = {
    1.0: (0.056433, 0.301721),
    2.0: (0.160642, 0.493457),
    5.0: (0.387628, 0.713792),
    10.0: (0.554996, 0.810609),
}

# prototype truth for examples/beams/reference-random.json, first five bending modes (rad/s)
REF_OMEGA = np.array([39.65, 333.8, 1018.0, 1974.0, 2800.0])
