"""Fourth-order central differences of ``elastica_static`` in the design variables and the tip
load: the references of the elastica gradient tests.

Imported as ``from elastica_differences import ...`` (pytest puts this folder on ``sys.path``).
"""

from __future__ import annotations

import numpy as np

import prbdm_pin as pp
from prbdm_pin.truth.elastica import elastica_static

__all__ = ["TOL", "REL", "fd_design", "fd_force", "check"]

# the solver tolerance of both the gradient and the finite differences: at solve_bvp's default
# 1e-9 the differences of re-meshed solves scatter by up to 1e-6 relative at a moved step
TOL = 1e-11
# fourth-order central differences, step 1e-3 of the variable's scale (truncation ~1e-12)
STENCIL = ((1.0, 8.0), (-1.0, -8.0), (2.0, -1.0), (-2.0, 1.0))
# measured: at most 1e-10 relative (per variable, against its largest tip component) on the
# beams of the tests; the bound leaves room for the re-meshing noise of the differenced solves
REL = 1e-9


def fd_design(beam, names, rel=1e-3, **kwargs):
    """d tip_position / d p (3, variables) of ``elastica_static(..., **kwargs)``."""
    d = pp.Design(beam, names)
    p0, scales = d.values, d.scales
    out = np.zeros((3, d.size))
    for j in range(d.size):
        h = rel * scales[j]
        e = np.zeros(d.size)
        e[j] = h
        out[:, j] = sum(c * elastica_static(d.beam_at(p0 + k * e), tol=TOL,
                                            **kwargs).tip_position_m
                        for k, c in STENCIL) / (12.0 * h)
    return out


def fd_force(beam, rel=1e-3, **kwargs):
    """d tip_position / d (F_x, F_z) (3, 2) of ``elastica_static(..., **kwargs)``."""
    F0 = beam.tip_force_N
    h = rel * np.hypot(F0[0], F0[2])
    out = np.zeros((3, 2))
    for col, comp in enumerate((0, 2)):
        e = np.zeros(3)
        e[comp] = h
        out[:, col] = sum(c * elastica_static(beam, F0 + k * e, tol=TOL,
                                              **kwargs).tip_position_m
                          for k, c in STENCIL) / (12.0 * h)
    return out


def check(analytic, reference, rel=REL):
    """Every column of ``analytic`` within ``rel`` of ``reference`` (relative to the column's
    largest reference component)."""
    scale = np.abs(reference).max(axis=0)
    assert np.all(scale > 0.0)
    err = np.abs(analytic - reference).max(axis=0) / scale
    assert err.max() < rel, err
