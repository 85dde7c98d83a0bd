"""The least-squares problem of :func:`~prbdm_pin.fitting.calibrate.calibrate`.

Nonlinear parameters x (``E`` and ``rho`` scales, ``damping[k]`` ratios); linear ones: each
mode's ring-down amplitudes (a_k, b_k) and each asked sensor offset ``offset[CHANNEL]`` (a
constant added to that channel, in its unit). The linear ones are eliminated by variable
projection: the residual is the data less its projection on the basis B(x), and the search uses
Kaufman's Jacobian (the projection of dy/dx at the optimal coefficients).
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError
from .calibration_basis import ring_basis

__all__ = ["DAMPING", "OFFSET", "RAYLEIGH", "COND_MAX", "Problem", "parameter_columns",
           "rank_check", "start"]

# C = alpha M + beta K: mode k gets zeta_k = alpha / (2 omega_k) + beta omega_k / 2
RAYLEIGH = ("rayleigh_alpha", "rayleigh_beta")

DAMPING = re.compile(r"^damping\[(\d+)\]$")
OFFSET = re.compile(r"^offset\[(.+)\]$")
COND_MAX = 1.0 / np.sqrt(np.finfo(float).eps)  # 6.7e7: beyond it half the digits are lost


@dataclass(frozen=True)
class Problem:
    """One calibration's data and model, weighted (each channel by 1 / its data's deviation)."""

    names: tuple[str, ...]  # the nonlinear parameters
    t: np.ndarray
    yw: np.ndarray  # weighted data, flattened (N c,), sample-major
    weights: np.ndarray  # (c,)
    omega0: np.ndarray
    cq: np.ndarray
    cv: np.ndarray
    zeta0: np.ndarray
    offsets: tuple[int, ...] = ()  # the channels with an offset

    def rayleigh(self, x) -> tuple[float, float] | None:
        """Return (alpha 1/s, beta s) at x, or None without Rayleigh damping."""
        d = dict(zip(self.names, x, strict=True))
        if RAYLEIGH[0] not in d and RAYLEIGH[1] not in d:
            return None
        return float(d.get(RAYLEIGH[0], 0.0)), float(d.get(RAYLEIGH[1], 0.0))

    def unpack(self, x):
        """Return s_E, s_rho and the ratio of every mode at x."""
        sE = sR = 1.0
        z = self.zeta0.copy()
        for name, v in zip(self.names, x, strict=True):
            if name == "E":
                sE = v
            elif name == "rho":
                sR = v
            elif name not in RAYLEIGH:
                z[int(DAMPING.match(name).group(1))] = v
        ab = self.rayleigh(x)
        if ab is not None:
            w = self.omega0 * np.sqrt(sE / sR)
            z = ab[0] / (2.0 * w) + ab[1] * w / 2.0
        return sE, sR, z

    def _offset_columns(self) -> np.ndarray:
        c = self.weights.size
        cols = np.zeros((self.t.size, c, len(self.offsets)))
        for j, ch in enumerate(self.offsets):
            cols[:, ch, j] = self.weights[ch]  # weighted: the coefficient is in data units
        return cols.reshape(self.t.size * c, len(self.offsets))

    def basis(self, x, derivatives=False):
        """Return B(x) (N c, 2 n + offsets).

        With ``derivatives``: s_E, s_rho, omega and the modal basis with its omega and zeta
        derivatives (N, c, 2 n).
        """
        sE, sR, z = self.unpack(x)
        w = self.omega0 * np.sqrt(sE / sR)
        out = ring_basis(self.t, w, z, self.cq * self.weights[:, None],
                         self.cv * self.weights[:, None], derivatives)
        if derivatives:
            return sE, sR, w, out
        return np.hstack([out.reshape(-1, 2 * w.size), self._offset_columns()])

    def coefficients(self, B):
        """Return the least-squares linear coefficients for basis B."""
        return np.linalg.lstsq(B, self.yw, rcond=None)[0]

    def residual(self, x):
        """Return the weighted residual, data less the projection (N c,)."""
        B = self.basis(x)
        return self.yw - B @ self.coefficients(B)

    def model_jacobian(self, x):
        """Return B (Nc, 2n + o), the coefficients and dy/dx (Nc, p) at those coefficients."""
        sE, sR, w, (Bm, dBw, dBz) = self.basis(x, True)
        n = w.size
        Bm, dBw, dBz = (a.reshape(-1, 2 * n) for a in (Bm, dBw, dBz))
        B = np.hstack([Bm, self._offset_columns()])
        c = self.coefficients(B)
        per_w = (dBw * c[:2 * n]).reshape(-1, n, 2).sum(axis=2)  # d y / d omega_k (Nc, n)
        per_z = (dBz * c[:2 * n]).reshape(-1, n, 2).sum(axis=2)  # d y / d zeta_k (Nc, n)
        return B, c, parameter_columns(self.names, x, w, sE, sR, per_w, per_z)

    def projected_jacobian(self, x):
        """Return Kaufman's Jacobian of :meth:`residual` (N c, p)."""
        B, _, dy = self.model_jacobian(x)
        Q = np.linalg.qr(B)[0]
        return -(dy - Q @ (Q.T @ dy))


def parameter_columns(names, x, w: np.ndarray, sE: float, sR: float, per_w: np.ndarray,
                      per_z: np.ndarray, per_rho: np.ndarray | None = None) -> np.ndarray:
    """Return dy/dx (R, p) from the response's derivatives in each mode's omega and zeta.

    ``per_w``, ``per_z`` (R, n): dy/domega_k and dy/dzeta_k; ``per_rho`` (R,): the response's
    own dependence on s_rho beyond the frequencies (a forced response's gain), if any.
    """
    d = dict(zip(names, x, strict=True))
    if RAYLEIGH[0] in d or RAYLEIGH[1] in d:  # Rayleigh: zeta_k moves with omega_k too
        a, b = d.get(RAYLEIGH[0], 0.0), d.get(RAYLEIGH[1], 0.0)
        per_w = per_w + per_z * (-a / (2.0 * w**2) + b / 2.0)
    cols = []
    for name in names:
        if name == "E":
            cols.append(per_w @ (w / (2.0 * sE)))  # omega ~ sqrt(sE / sR)
        elif name == "rho":
            cols.append(per_w @ (-w / (2.0 * sR)) + (0.0 if per_rho is None else per_rho))
        elif name == RAYLEIGH[0]:
            cols.append(per_z @ (1.0 / (2.0 * w)))
        elif name == RAYLEIGH[1]:
            cols.append(per_z @ (w / 2.0))
        else:
            cols.append(per_z[:, int(DAMPING.match(name).group(1))])
    return np.column_stack(cols)


def rank_check(labels, J_full) -> None:
    """Refuse a Jacobian whose scaled columns are near dependent, naming the parameters.

    ``labels`` names each column of ``J_full`` (None for the initial state's).
    """
    norms = np.linalg.norm(J_full, axis=0)
    dead = [lab for lab, v in zip(labels, norms, strict=True) if lab and v == 0.0]
    if dead:
        raise BeamInputError(f"parameters: {dead[0]} does not change the model's response to "
                             "this data: it cannot be determined")
    U = J_full / np.where(norms > 0.0, norms, 1.0)
    s, Vt = np.linalg.svd(U, full_matrices=False)[1:]
    if s[-1] <= s[0] / COND_MAX:
        v = Vt[-1]
        which = [lab for lab, vi in zip(labels, v, strict=True) if lab and abs(vi) > 0.1]
        hint = (" (a free ring-down, or a response to a base acceleration, sees E/rho only: "
                "frequencies scale with sqrt(E/rho), and the unknown amplitudes or the load's "
                "own rho take the rest; fit one of them)"
                if {"E", "rho"} <= set(which) else "")
        raise BeamInputError(f"parameters: {', '.join(which) or 'the initial state'} not "
                             f"determined by this data (the Jacobian's condition "
                             f"{s[0] / max(s[-1], 1e-300):.3g} > {COND_MAX:.3g}){hint}")


def start(prob: Problem, x0: np.ndarray) -> np.ndarray:
    """Return x0 with the E or rho scale from a grid over E/rho (mode 1 alone)."""
    names = prob.names
    if "E" not in names and "rho" not in names:
        return x0
    T = prob.t[-1] - prob.t[0]
    # steps of 1 rad of mode 1's drift over T, ratio in [1/3, 3] (omega within -42 %, +73 %)
    step = 1.0 / max(prob.omega0[0] * T, 1.0)
    r = np.exp(np.arange(np.log(1 / 3), np.log(3.0), 2.0 * step))
    one = dataclasses.replace(prob, omega0=prob.omega0[:1], cq=prob.cq[:, :1],
                              cv=prob.cv[:, :1], zeta0=prob.zeta0[:1],
                              names=tuple(n for n in names if n in ("E", "rho")))
    x1 = np.ones(len(one.names))
    cost = []
    for ri in r:
        x1[0] = ri if one.names[0] == "E" else 1.0 / ri
        cost.append(float(np.sum(one.residual(x1) ** 2)))
    best = r[int(np.argmin(cost))]
    x = x0.copy()
    i = names.index(one.names[0])
    x[i] = best if one.names[0] == "E" else 1.0 / best
    return x
