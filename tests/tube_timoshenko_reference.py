"""Timoshenko cantilever frequencies of a round member, independent of the package.

Two-node elements (w and the section rotation psi linear), shear energy with one Gauss point
(reduced, which frees the element of shear locking), bending energy and both inertias (rho A for
w, rho I for psi) exact; section laws D(x), d(x) linear, so A and I are taken at each element's
midpoint. The error is O(h^2): Richardson extrapolation of n and 2n elements removes it.
Shear coefficient: Cowper's for a hollow circle (m = d / D; m = 0 the solid circle).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def cowper_kappa(nu: float, ratio: float) -> float:
    """Cowper's shear coefficient of a circular tube of diameter ratio d / D = ``ratio``."""
    m2 = ratio**2
    return 6.0 * (1 + nu) * (1 + m2) ** 2 / ((7 + 6 * nu) * (1 + m2) ** 2 + (20 + 12 * nu) * m2)


def timoshenko_omegas(L, D0, D1, d0, d1, E, G, rho, nu, n_modes=3, n=400):
    """Lowest bending frequencies (rad/s) of the clamped-free Timoshenko member, n elements.

    Outer and inner diameters linear from (D0, d0) at the clamp to (D1, d1) at the tip, m.
    """
    h = L / n
    xm = (np.arange(n) + 0.5) * h
    D = D0 + (D1 - D0) * xm / L
    d = d0 + (d1 - d0) * xm / L
    A = np.pi * (D**2 - d**2) / 4.0
    I_ = np.pi * (D**4 - d**4) / 64.0
    kappa = np.array([cowper_kappa(nu, di / Di) for di, Di in zip(d, D, strict=True)])
    # DOFs per node: w, psi; element DOFs (w1, psi1, w2, psi2)
    rows, cols, kv, mv = [], [], [], []
    for e in range(n):
        dofs = np.array([2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3])
        ei, ga = E * I_[e], kappa[e] * G * A[e]
        kb = ei / h * np.array([[0, 0, 0, 0], [0, 1, 0, -1], [0, 0, 0, 0], [0, -1, 0, 1]])
        # shear strain w' - psi at the midpoint: (w2 - w1) / h - (psi1 + psi2) / 2
        b = np.array([-1.0 / h, -0.5, 1.0 / h, -0.5])
        ks = ga * h * np.outer(b, b)
        lin = h / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])  # int N_i N_j of linear shapes
        me = np.zeros((4, 4))
        me[np.ix_([0, 2], [0, 2])] = rho * A[e] * lin
        me[np.ix_([1, 3], [1, 3])] = rho * I_[e] * lin
        ke = kb + ks
        rows.append(np.repeat(dofs, 4))
        cols.append(np.tile(dofs, 4))
        kv.append(ke.ravel())
        mv.append(me.ravel())
    N = 2 * n + 2
    r, c = np.concatenate(rows), np.concatenate(cols)
    K = sp.csc_matrix((np.concatenate(kv), (r, c)), shape=(N, N))[2:, 2:]
    M = sp.csc_matrix((np.concatenate(mv), (r, c)), shape=(N, N))[2:, 2:]
    lam = spla.eigsh(K, k=n_modes, M=M, sigma=0.0, which="LM", return_eigenvectors=False)
    return np.sqrt(np.sort(lam))


def timoshenko_richardson(*args, n=400, **kw):
    """Richardson extrapolation (O(h^2)) of n and 2n elements, and |extrapolated - finest|."""
    a = timoshenko_omegas(*args, n=n, **kw)
    b = timoshenko_omegas(*args, n=2 * n, **kw)
    ext = b + (b - a) / 3.0
    return ext, np.abs(ext - b)
