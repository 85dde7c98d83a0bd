"""The least-squares problem of a calibration to an FRF or to a driven trajectory.

The model's response is a forced part F(x) (:mod:`.calibration_forced`: the transfer functions
of every chain mode, or the trajectory from rest under the held inputs) plus, for a driven
trajectory, linear terms B(x) c: the free response of the lowest modes from a fitted initial
state (:mod:`.calibration_basis`, as a ring-down's) and sensor offsets. Variable projection
eliminates c as for a ring-down: the residual is (y - F) less its projection on B, and
Kaufman's Jacobian is -(I - P_B)(dF/dx + dB/dx c).

Rows are weighted per channel (1 / the data's deviation, or for an FRF 1 / the RMS of its
magnitude on both the real and the imaginary rows).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .calibration_basis import ring_basis
from .calibration_forced import frf_response, zoh_response
from .calibration_problem import Problem, parameter_columns

__all__ = ["ForcedProblem"]


@dataclass(frozen=True)
class ForcedProblem(Problem):
    """:class:`~.calibration_problem.Problem` with a forced response (module notes).

    ``t`` holds the times from the first sample (s) or, for an FRF, the frequencies (Hz);
    ``omega0``, ``zeta0``, ``cq``, ``cv`` cover every chain mode and every output.
    """

    frf: bool = False
    u: np.ndarray | None = None  # (N, m) held inputs, a driven trajectory
    b: np.ndarray | None = None  # (n, m) modal force per unit input
    rho_power: np.ndarray | None = None  # (m,) e_j: 1 for a base acceleration, else 0
    out_in: tuple = ()  # FRF: (output row, input column) per transfer function
    n_free: int = 0  # the lowest modes whose free response (initial state) is fitted

    def forced(self, x, derivatives: bool = False):
        """Return the weighted forced response F (R,) at x.

        With ``derivatives`` also dF/domega_k, dF/dzeta_k (R, n) and dF/ds_rho at fixed
        frequencies (R,), and s_E, s_rho, omega.
        """
        sE, sR, z = self.unpack(x)
        w = self.omega0 * np.sqrt(sE / sR)
        e = self.rho_power
        gain = sR ** (e - 1.0)
        if self.frf:
            out = frf_response(self.t, w, z, self.cq, self.cv, self.b, self.out_in, gain,
                               derivatives)
            H = out[0] if derivatives else out
            i = np.array([p[1] for p in self.out_in])
            parts = [H] + ([out[1], out[2], H * ((e[i] - 1.0) / sR)] if derivatives else [])
            # complex (N, c[, n]) -> real rows (N, c, re/im[, n]), weighted per channel
            flat = []
            for a in parts:
                r = np.stack([a.real, a.imag], axis=2)
                wt = self.weights[None, :, None] if a.ndim == 2 else self.weights[None, :,
                                                                                   None, None]
                flat.append((r * wt).reshape(r.shape[0] * r.shape[1] * 2, *r.shape[3:]))
        else:
            out = zoh_response(self.t, self.u, w, z, self.cq, self.cv, self.b, gain,
                               derivatives)
            Y = out[0] if derivatives else out  # (N, p, m): each input's part
            parts = [Y.sum(axis=2)]
            if derivatives:
                parts += [out[1], out[2], Y @ ((e - 1.0) / sR)]
            flat = []
            for a in parts:
                wt = self.weights[None, :] if a.ndim == 2 else self.weights[None, :, None]
                flat.append((a * wt).reshape(a.shape[0] * a.shape[1], *a.shape[2:]))
        if not derivatives:
            return flat[0]
        return flat[0], flat[1], flat[2], flat[3], sE, sR, w

    def basis(self, x, derivatives=False):
        """Return the weighted linear terms B (R, 2 n_free + offsets).

        With ``derivatives`` also the free part's derivatives in omega and zeta (R, 2 n_free).
        """
        k = self.n_free
        R = self.yw.size
        if k:
            sE, sR, z = self.unpack(x)
            w = self.omega0[:k] * np.sqrt(sE / sR)
            out = ring_basis(self.t, w, z[:k], self.cq[:, :k] * self.weights[:, None],
                             self.cv[:, :k] * self.weights[:, None], derivatives)
            parts = list(out) if derivatives else [out]
            parts = [a.reshape(R, 2 * k) for a in parts]
        else:
            parts = [np.zeros((R, 0))] * (3 if derivatives else 1)
        B = np.hstack([parts[0], self._offset_columns()]) if self.offsets else parts[0]
        return (B, parts[1], parts[2]) if derivatives else B

    def residual(self, x):
        """Return the weighted residual: data less the forced response and the projection."""
        d = self.yw - self.forced(x)
        B = self.basis(x)
        return d - B @ self.coefficients_of(B, d) if B.shape[1] else d

    @staticmethod
    def coefficients_of(B, d):
        """Return the least-squares coefficients of ``d`` on ``B``."""
        return np.linalg.lstsq(B, d, rcond=None)[0]

    def model_jacobian(self, x):
        """Return B, the coefficients c and dy/dx (R, p) of y = F + B c at x."""
        F, pw, pz, prho, sE, sR, w = self.forced(x, derivatives=True)
        B, dBw, dBz = self.basis(x, derivatives=True)
        k = self.n_free
        c = self.coefficients_of(B, self.yw - F) if B.shape[1] else np.zeros(0)
        if k:  # the free response moves with its modes' omega and zeta at fixed amplitudes
            pw = pw.copy()
            pz = pz.copy()
            pw[:, :k] += (dBw * c[:2 * k]).reshape(-1, k, 2).sum(axis=2)
            pz[:, :k] += (dBz * c[:2 * k]).reshape(-1, k, 2).sum(axis=2)
        return B, c, parameter_columns(self.names, x, w, sE, sR, pw, pz, prho)

    def projected_jacobian(self, x):
        """Return Kaufman's Jacobian of :meth:`residual` (R, p)."""
        B, _, dy = self.model_jacobian(x)
        if not B.shape[1]:
            return -dy
        Q = np.linalg.qr(B)[0]
        return -(dy - Q @ (Q.T @ dy))
