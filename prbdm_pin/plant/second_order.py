"""Any linear plant of the package in its second-order form, with its responses.

The plant is split into its rigid-body and flexible parts, with its frequency and step
responses.

    M q'' + C_d q' + K q = B_q u,   y = C_q q + C_v q'

A PRBDM ``LinearModel`` and the truth's ``HybridModel`` and ``ClampedModel`` all have this form
(state x = [q, q'], y = C x with C = [C_q, C_v], D = 0). On a hub plant coordinate 0 is the hub
angle, on a free bus's the first r coordinates are the bus's: free of any spring (K's first r
rows and columns are zero) and undamped (C_d E_R = 0, E_R those coordinates' unit vectors), so
Phi_R = E_R M_RR^-1/2 are mass-normalised rigid-body modes. Their modal coordinates
r = Phi_R^T M q obey r'' = Phi_R^T B_q u exactly, and q_f = q - Phi_R r stays in the
M-orthogonal complement, spanned by T = [-M_RR^-1 M_Rf; I]; there

    T^T M T z'' + T^T C_d T z' + T^T K T z = T^T B_q u,   y_f = C_q T z + C_v T z'

is positive definite, so the flexible part has a finite static gain and decaying transients:
y = y_rigid + y_f with y_rigid = (C_q + s C_v) E_R M_RR^-1 E_R^T B_q / s^2
(Phi_R Phi_R^T = E_R M_RR^-1 E_R^T).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from ..errors import BeamInputError, InputTypeError

__all__ = ["SecondOrderPlant", "second_order"]


@dataclass(frozen=True, eq=False)
class SecondOrderPlant:
    """M q'' + C_d q' + K q = B_q u, y = C_q q + C_v q' (units of the source plant).

    Attributes
    ----------
    mass, damping, stiffness : ndarray (nq, nq)
    input_map : ndarray (nq, m)
    output_map_position, output_map_rate : ndarray (p, nq)
    input_names, output_names : tuple of str
    rigid : int
        How many leading coordinates are free (0 clamped, 1 a hub, 6 a free bus's base): as
        many rigid-body modes (module notes).
    """

    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    input_map: np.ndarray
    output_map_position: np.ndarray
    output_map_rate: np.ndarray
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    rigid: int

    def flexible(self) -> SecondOrderPlant:
        """Return the flexible part in the coordinates z (q_f = T z, see the module notes).

        The plant itself when it has no rigid mode.
        """
        if not self.rigid:
            return self
        M, r = self.mass, self.rigid
        T = np.vstack([-sla.solve(M[:r, :r], M[:r, r:], assume_a="pos"),
                       np.eye(M.shape[0] - r)])

        def sym(a):
            a = T.T @ a @ T
            return 0.5 * (a + a.T)

        return SecondOrderPlant(sym(M), sym(self.damping), sym(self.stiffness),
                                T.T @ self.input_map, self.output_map_position @ T,
                                self.output_map_rate @ T, self.input_names, self.output_names,
                                rigid=0)

    def rigid_gains(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the coefficients of 1/s^2 and 1/s of the rigid-body mode's transfer matrix.

        They are C_q E_R M_RR^-1 E_R^T B_q and C_v E_R M_RR^-1 E_R^T B_q, shape (p, m); zero
        without a rigid mode.
        """
        p, m = self.output_map_position.shape[0], self.input_map.shape[1]
        r = self.rigid
        if not r:
            return np.zeros((p, m)), np.zeros((p, m))
        b = sla.solve(self.mass[:r, :r], self.input_map[:r], assume_a="pos")
        return self.output_map_position[:, :r] @ b, self.output_map_rate[:, :r] @ b

    def modes(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the frequencies (rad/s, ascending) and damping ratios of the flexible modes.

        The ratios are diag(Phi^T C_d Phi) / (2 omega) with Phi the mass-normalised undamped
        modes of the flexible part.
        """
        f = self.flexible()
        lam, Phi = sla.eigh(f.stiffness, f.mass)
        omega = np.sqrt(np.clip(lam, 0.0, None))
        c = np.einsum("ik,ij,jk->k", Phi, f.damping, Phi)
        with np.errstate(divide="ignore", invalid="ignore"):
            zeta = np.where(omega > 0.0, c / (2.0 * np.where(omega > 0.0, omega, 1.0)), 0.0)
        return omega, zeta

    def frequency_response(self, omega_rad_s: np.ndarray) -> np.ndarray:
        """Return the FRF (C_q + i w C_v)(K - w^2 M + i w C_d)^-1 B_q at each w (rad/s).

        Complex, shape (f, p, m); on a rigid plant w = 0 is singular (use ``flexible()``).
        """
        w = np.asarray(omega_rad_s, dtype=float)[:, None, None]
        Z = self.stiffness[None] - w**2 * self.mass[None] + 1j * w * self.damping[None]
        X = np.linalg.solve(Z, np.broadcast_to(self.input_map, (w.shape[0],)
                                               + self.input_map.shape).astype(complex))
        return (self.output_map_position[None] + 1j * w * self.output_map_rate[None]) @ X

    def step_response(self, t_s: np.ndarray) -> np.ndarray:
        """Output (T, p, m) at times ``t_s`` (s) under a unit step of each input from rest.

        Only for a plant without a rigid mode (``flexible()``): x(t) = A^-1 (e^(A t) - I) B over
        the eigenvectors of A, exact at every sample.
        """
        if self.rigid:
            raise BeamInputError("step_response: the plant has a rigid mode; use flexible()")
        n = self.mass.shape[0]
        MinvK, MinvC, MinvB = np.hsplit(sla.solve(self.mass, np.hstack(
            [self.stiffness, self.damping, self.input_map]), assume_a="pos"), [n, 2 * n])
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-MinvK, -MinvC]])
        B = np.vstack([np.zeros_like(MinvB), MinvB])
        C = np.hstack([self.output_map_position, self.output_map_rate])
        lam, V = np.linalg.eig(A)
        left = C @ V
        right = np.linalg.solve(V, B)
        t = np.asarray(t_s, dtype=float)[:, None]
        g = np.expm1(lam[None, :] * t) / lam[None, :]  # (T, 2n)
        y = np.einsum("pk,tk,km->tpm", left, g, right)
        return y.real


def _check_plant(name: str, plant) -> None:
    for attr in ("A", "B", "C", "D", "input_names", "output_names"):
        if not hasattr(plant, attr):
            raise InputTypeError(f"{name} = {type(plant).__name__}: must be a linear plant "
                                 "(prbdm_pin.linearize, or the truth's hybrid_model or "
                                 "clamped_model)")
    if np.any(np.asarray(plant.D)):
        raise BeamInputError(f"{name}: has a feedthrough D != 0; the plants here have none")


def second_order(plant, name: str = "plant") -> SecondOrderPlant:
    """Return the second-order form of a PRBDM or truth linear plant.

    ``plant`` is a PRBDM ``LinearModel`` or a truth ``HybridModel`` / ``ClampedModel``; ``name``
    names the argument in errors.
    """
    _check_plant(name, plant)
    if hasattr(plant, "mass_kg_m2"):  # a LinearModel
        M, Cd, K = plant.mass_kg_m2, plant.damping_Nms_per_rad, plant.stiffness_Nm_per_rad
        Bq = plant.input_map
    else:
        M, Cd, K, Bq = plant.mass, plant.damping, plant.stiffness, plant.input_matrix
    M, Cd, K, Bq = (np.asarray(a, dtype=float) for a in (M, Cd, K, Bq))
    nq = M.shape[0]
    C = np.asarray(plant.C, dtype=float)
    if C.shape[1] != 2 * nq or Bq.shape != (nq, len(plant.input_names)):
        raise BeamInputError(f"{name}: its state is not [q, dq/dt] with {nq} coordinates")
    free = [not np.any(K[i]) and not np.any(K[:, i]) for i in range(nq)]
    rigid = int(np.argmin(free)) if not all(free) else nq  # the leading spring-free coordinates
    return SecondOrderPlant(M, Cd, K, Bq, C[:, :nq], C[:, nq:], tuple(plant.input_names),
                            tuple(plant.output_names), rigid)
