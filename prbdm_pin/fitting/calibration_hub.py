"""The ring-down least-squares problem of a chain on a hub of known inertia: E and rho apart.

On a hub the mass matrix splits as M(s_rho) = s_rho M_beam + M_hub: every link's mass and
inertia scale with rho, the hub's own inertia J_h (on the hub coordinate, index 0) does not; the
stiffness K(s_E) = s_E K_beam (the hub joint has no spring, so K's hub row is zero). The coupled
modes then depend on the beam's mass relative to J_h, not on s_E / s_rho alone, which is what
separates E from rho.

The flexible modes come from the generalized eigenproblem K phi = lambda M phi at every
evaluation; the rigid mode is taken out exactly (K's hub row is zero, so it is e_hub with
lambda = 0, and every flexible mode is M-orthogonal to it). Free and undamped, the rigid mode's
coordinate moves as a + b t: in a position channel that reads Cq_h (a + b t), in a rate channel
Cv_h b; (a, b) join the flexible modes' amplitudes in the linear (variable projection) part.
The flexible modes ring as :func:`~.calibration_basis.ring_basis` with the ratio ``damping[k]``
of flexible mode k + 1 (the rigid mode is undamped: the hub form of ``damping="modal"``).

Derivatives of the modes in p = s_E, s_rho (mass-normalised, distinct eigenvalues; Nelson 1976,
by modal expansion over the complete set, the rigid mode included):

    dlambda_k = phi_k^T (K' - lambda_k M') phi_k,
    dphi_k = -1/2 (phi_k^T M' phi_k) phi_k
             + sum_{j != k} phi_j phi_j^T (K' - lambda_k M') phi_k / (lambda_k - lambda_j),

with K' = K_beam, M' = 0 for s_E and K' = 0, M' = M_beam for s_rho.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..chain.eigen import generalized_eigh
from ..errors import BeamInputError
from .calibration_basis import ring_basis
from .calibration_problem import DAMPING, RAYLEIGH

__all__ = ["HubProblem", "hub_matrices"]

# a relative eigenvalue gap below this makes 1 / (lambda_k - lambda_j) lose half the digits
_GAP_MIN = float(np.sqrt(np.finfo(float).eps))


def hub_matrices(model, channels: tuple[str, ...]):
    """Return K_beam, M_beam, M_hub (n+1, n+1) and the outputs' Cq, Cv (c, n+1) of a hub chain.

    K in N m/rad, M in kg m^2 at the straight pose, the hub coordinate first; Cq reads the
    coordinates, Cv their rates (the channels' units per rad, per rad/s).
    """
    from ..plant.linearize import linearize

    if model.beam is None:
        raise BeamInputError("model: has no beam (a URDF): E and rho are scaled on the beam; "
                             "give a model JSON or a fit.json")
    try:
        lin = linearize(model, inputs=("hub_torque",), outputs=channels, damping_ratio=0.0)
    except BeamInputError as exc:  # the channels are linearize's outputs: say it is the data's
        raise BeamInputError(f"data: the channels ({', '.join(channels)}) are outputs: "
                             f"{exc}") from None
    Ca = lin.output_map_acceleration
    if Ca is not None and np.any(Ca):
        bad = [c for c, row in zip(channels, Ca, strict=True) if np.any(row)]
        raise BeamInputError(f"data: channel {bad[0]!r} reads the acceleration; a ring-down "
                             "channel must be a position or a rate")
    M = np.array(lin.mass_kg_m2, dtype=float)
    M_hub = np.zeros_like(M)
    M_hub[0, 0] = model.hub.inertia_kg_m2  # the hub body alone: rho does not scale it
    n1 = M.shape[0]
    C = np.asarray(lin.C)
    return (np.asarray(lin.stiffness_Nm_per_rad, dtype=float), M - M_hub, M_hub,
            C[:, :n1], C[:, n1:])


@dataclass(frozen=True)
class HubProblem:
    """One hub calibration's data and model, weighted (each channel by 1 / its deviation).

    ``names`` the nonlinear parameters (``E``, ``rho``, ``damping[k]``, ``rayleigh_*``);
    ``zeta0`` the ratio of each of the ``n_modes`` lowest flexible modes when not fitted.
    """

    names: tuple[str, ...]
    t: np.ndarray
    yw: np.ndarray  # weighted data, flattened (N c,), sample-major
    weights: np.ndarray  # (c,)
    K_beam: np.ndarray
    M_beam: np.ndarray
    M_hub: np.ndarray
    Cq: np.ndarray  # (c, n + 1)
    Cv: np.ndarray
    zeta0: np.ndarray  # (n_modes,)
    offsets: tuple[int, ...] = ()

    @property
    def n_modes(self) -> int:
        """The flexible modes in the response."""
        return self.zeta0.size

    def scales(self, x) -> tuple[float, float]:
        """Return s_E and s_rho at x (1 for one not fitted)."""
        d = dict(zip(self.names, x, strict=True))
        return float(d.get("E", 1.0)), float(d.get("rho", 1.0))

    def modes(self, sE: float, sR: float, derivatives: bool = False):
        """Return omega (n_modes,), rad/s, and the modal Cq, Cv (c, n_modes) at (sE, sR).

        With ``derivatives`` also d omega (2, n_modes) and d Cq, d Cv (2, c, n_modes) in
        (s_E, s_rho) (module notes). Shapes are mass-normalised, their largest flexible
        coordinate positive (a sign fixed along a path, for the derivatives).
        """
        K = sE * self.K_beam
        M = sR * self.M_beam + self.M_hub
        lam, Phi = generalized_eigh(K, M, "calibrate (hub)")
        lam[0] = 0.0  # the rigid mode exactly (module notes)
        Phi[:, 0] = 0.0
        Phi[0, 0] = 1.0 / np.sqrt(M[0, 0])
        big = np.argmax(np.abs(Phi[1:]), axis=0) + 1
        Phi *= np.where(Phi[big, np.arange(lam.size)] < 0.0, -1.0, 1.0)
        k = slice(1, self.n_modes + 1)
        w = np.sqrt(lam[k])
        out = (w, self.Cq @ Phi[:, k], self.Cv @ Phi[:, k])
        if not derivatives:
            return out
        gap = np.diff(lam[1:]) / lam[2:] if lam.size > 2 else np.ones(1)
        if np.any(gap < _GAP_MIN):
            raise BeamInputError("model: two flexible modes on the hub have nearly equal "
                                 "frequencies: their derivatives are not defined")
        dw, dcq, dcv = [], [], []
        for dK, dM in ((self.K_beam, None), (None, self.M_beam)):
            G = Phi.T @ dK @ Phi if dK is not None else np.zeros_like(M)
            H = Phi.T @ dM @ Phi if dM is not None else np.zeros_like(M)
            F = G - H * lam[None, :]  # F[j, k] = phi_j^T (K' - lambda_k M') phi_k
            diff = lam[None, :] - lam[:, None]
            np.fill_diagonal(diff, 1.0)
            coef = F / diff
            np.fill_diagonal(coef, -0.5 * np.diag(H))
            dPhi = Phi @ coef[:, k]
            dw.append(np.diag(F)[k] / (2.0 * w))
            dcq.append(self.Cq @ dPhi)
            dcv.append(self.Cv @ dPhi)
        return (*out, np.array(dw), np.array(dcq), np.array(dcv))

    def ratios(self, x, w: np.ndarray) -> np.ndarray:
        """Return each flexible mode's ratio at x (frequencies ``w``, rad/s)."""
        d = dict(zip(self.names, x, strict=True))
        if RAYLEIGH[0] in d or RAYLEIGH[1] in d:
            return d.get(RAYLEIGH[0], 0.0) / (2.0 * w) + d.get(RAYLEIGH[1], 0.0) * w / 2.0
        z = self.zeta0.copy()
        for name, v in d.items():
            m = DAMPING.match(name)
            if m is not None:
                z[int(m.group(1))] = v
        return z

    def fixed_columns(self) -> np.ndarray:
        """Return the rigid mode's a and b columns the data sees, then the offsets' (N c, .)."""
        N, c = self.t.size, self.weights.size
        qh, vh = self.Cq[:, 0] * self.weights, self.Cv[:, 0] * self.weights
        cols = []
        if np.any(qh):
            cols.append(np.broadcast_to(qh, (N, c)))
        if np.any(qh) or np.any(vh):
            cols.append(self.t[:, None] * qh[None, :] + vh[None, :])
        for ch in self.offsets:
            col = np.zeros((N, c))
            col[:, ch] = self.weights[ch]  # weighted: the coefficient is in data units
            cols.append(col)
        return np.stack(cols, axis=-1).reshape(N * c, len(cols)) if cols \
            else np.zeros((N * c, 0))

    def basis(self, x) -> np.ndarray:
        """Return B(x) (N c, 2 n_modes + rigid + offsets)."""
        w, cq, cv = self.modes(*self.scales(x))
        wt = self.weights[:, None]
        Bm = ring_basis(self.t, w, self.ratios(x, w), cq * wt, cv * wt)
        return np.hstack([Bm.reshape(-1, 2 * w.size), self.fixed_columns()])

    def coefficients(self, B):
        """Return the least-squares linear coefficients for basis B."""
        return np.linalg.lstsq(B, self.yw, rcond=None)[0]

    def residual(self, x):
        """Return the weighted residual, data less its projection (N c,)."""
        B = self.basis(x)
        return self.yw - B @ self.coefficients(B)

    def model_jacobian(self, x):
        """Return B, the coefficients and dy/dx (N c, p) at those coefficients."""
        sE, sR = self.scales(x)
        w, cq, cv, dw, dcq, dcv = self.modes(sE, sR, derivatives=True)
        z = self.ratios(x, w)
        wt = self.weights[:, None]
        n = w.size
        Bm, dBw, dBz = (a.reshape(-1, 2 * n) for a in
                        ring_basis(self.t, w, z, cq * wt, cv * wt, derivatives=True))
        B = np.hstack([Bm, self.fixed_columns()])
        c = self.coefficients(B)
        cm = c[:2 * n]
        per_w = (dBw * cm).reshape(-1, n, 2).sum(axis=2)  # d y / d omega_k (N c, n)
        per_z = (dBz * cm).reshape(-1, n, 2).sum(axis=2)  # d y / d zeta_k (N c, n)
        d = dict(zip(self.names, x, strict=True))
        ab = (d.get(RAYLEIGH[0], 0.0), d.get(RAYLEIGH[1], 0.0))
        rayleigh = RAYLEIGH[0] in d or RAYLEIGH[1] in d
        if rayleigh:  # zeta_k moves with omega_k too
            per_w = per_w + per_z * (-ab[0] / (2.0 * w**2) + ab[1] / 2.0)
        cols = []
        for name in self.names:
            if name in ("E", "rho"):
                i = 0 if name == "E" else 1
                # the shapes move too: ring_basis is linear in (Cq, Cv)
                shape = ring_basis(self.t, w, z, dcq[i] * wt, dcv[i] * wt).reshape(-1, 2 * n)
                cols.append(per_w @ dw[i] + shape @ cm)
            elif name == RAYLEIGH[0]:
                cols.append(per_z @ (1.0 / (2.0 * w)))
            elif name == RAYLEIGH[1]:
                cols.append(per_z @ (w / 2.0))
            else:
                k = int(DAMPING.match(name).group(1))
                cols.append(dBz[:, 2 * k:2 * k + 2] @ cm[2 * k:2 * k + 2])
        return B, c, np.column_stack(cols)

    def projected_jacobian(self, x):
        """Return Kaufman's Jacobian of :meth:`residual` (N c, p)."""
        B, _, dy = self.model_jacobian(x)
        Q = np.linalg.qr(B)[0]
        return -(dy - Q @ (Q.T @ dy))
