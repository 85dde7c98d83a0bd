"""The forced response of a clamped chain's modes, and its derivatives in each mode's omega, zeta.

With E scaled by s_E and rho by s_rho (:mod:`.calibration_basis`), mode k has omega_k =
omega0_k sqrt(s_E / s_rho) and shape phi_k / sqrt(s_rho). An input's generalised force is
B_q u: a force or a moment does not depend on rho, a base acceleration's inertial load -m a
scales with it (e_j = 1, else 0). So output c per input j reads

    y_c = s_rho^(e_j - 1) sum_k b_kj (cq_ck eta_kj + cv_ck eta_kj'),
    eta_kj'' + 2 zeta_k omega_k eta_kj' + omega_k^2 eta_kj = u_j(t),

with the unscaled modal gains b = Phi^T B_q, cq = C_q Phi, cv = C_v Phi. An FRF is the same sum
with eta_kj = 1 / (omega_k^2 - omega^2 + 2 i zeta_k omega_k omega) and eta' = i omega eta.

A driven trajectory holds each input sample over the next step (a zero-order hold), which the
exact discretisation of each mode's state (matrix exponential of the augmented system) steps
without error; the derivatives in omega_k and zeta_k are the states of the sensitivity system
(d/dp of the mode's equation), stepped with it, so they too are exact for the held input.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

__all__ = ["frf_response", "zoh_response"]


def frf_response(f_hz: np.ndarray, w: np.ndarray, z: np.ndarray, cq: np.ndarray,
                 cv: np.ndarray, b: np.ndarray, out_in: tuple[tuple[int, int], ...],
                 gain: np.ndarray, derivatives: bool = False):
    """Return the transfer functions H (N, c) and, with ``derivatives``, dH/domega, dH/dzeta.

    Parameters
    ----------
    f_hz : ndarray (N,)
        Frequencies, Hz.
    w, z : ndarray (n,)
        Undamped frequencies (rad/s) and damping ratios of the modes.
    cq, cv : ndarray (p, n)
        Outputs per modal coordinate and per modal rate.
    b : ndarray (n, m)
        Modal force per unit input.
    out_in : tuple of (output row, input column)
        Each transfer function's output and input.
    gain : ndarray (m,)
        Each input's factor s_rho^(e_j - 1) (module notes).

    Returns
    -------
    H : ndarray (N, c), complex
    dH_domega, dH_dzeta : ndarray (N, c, n), complex
        With ``derivatives``: per mode, in 1/(rad/s) and per unit ratio.
    """
    om = 2.0 * np.pi * np.asarray(f_hz, dtype=float)[:, None]  # (N, 1)
    den = w**2 - om**2 + 2j * z * w * om  # (N, n)
    o = np.array([p[0] for p in out_in])
    i = np.array([p[1] for p in out_in])
    # per transfer function and mode: (cq + i omega cv) b, times the input's rho factor
    num = (cq[o][None] + 1j * om[:, :, None] * cv[o][None]) * (b[:, i].T * gain[i][:, None])
    terms = num / den[:, None, :]  # (N, c, n)
    H = terms.sum(axis=2)
    if not derivatives:
        return H
    dH_dw = -terms * ((2.0 * w + 2j * z * om) / den)[:, None, :]
    dH_dz = -terms * ((2j * w * om) / den)[:, None, :]
    return H, dH_dw, dH_dz


def _mode_system(w: float, z: float, derivatives: bool) -> np.ndarray:
    """Return [[F, g], [0, 0]] of one unit-forced mode (and its sensitivities)."""
    s = 6 if derivatives else 2
    M = np.zeros((s + 1, s + 1))
    for a in range(0, s, 2):  # each (value, rate) pair: x' = v, v' = -w^2 x - 2 z w v + ...
        M[a, a + 1] = 1.0
        M[a + 1, a] = -w * w
        M[a + 1, a + 1] = -2.0 * z * w
    M[1, s] = 1.0  # the input drives the mode
    if derivatives:  # d/dw: -(2 w x + 2 z v); d/dz: -2 w v
        M[3, 0], M[3, 1] = -2.0 * w, -2.0 * z
        M[5, 1] = -2.0 * w
    return M


def zoh_response(t_s: np.ndarray, u: np.ndarray, w: np.ndarray, z: np.ndarray,
                 cq: np.ndarray, cv: np.ndarray, b: np.ndarray, gain: np.ndarray,
                 derivatives: bool = False):
    """Return the outputs from rest under the held inputs, per input, and their derivatives.

    Parameters
    ----------
    t_s : ndarray (N,)
        Uniform times, s; the state is at rest at t_s[0].
    u : ndarray (N, m)
        Inputs, each held from its sample to the next.
    w, z, cq, cv, b, gain
        As :func:`frf_response`.

    Returns
    -------
    y : ndarray (N, p, m)
        Each output's response to each input (their sum is the output).
    dy_domega, dy_dzeta : ndarray (N, p, n)
        With ``derivatives``.
    """
    t = np.asarray(t_s, dtype=float)
    dt = float(np.mean(np.diff(t)))
    n, m = b.shape
    s = 6 if derivatives else 2
    # one block per (mode, input): the same mode's dynamics under each input's unit force
    steps = [sla.expm(_mode_system(w[k], z[k], derivatives) * dt) for k in range(n)]
    S = n * m * s
    Ad = np.zeros((S, S))
    Bd = np.zeros((S, m))
    for k in range(n):
        for j in range(m):
            r = (k * m + j) * s
            Ad[r:r + s, r:r + s] = steps[k][:s, :s]
            Bd[r:r + s, j] = steps[k][:s, s]
    drive = np.asarray(u, dtype=float) @ Bd.T  # (N, S)
    X = np.empty((t.size, S))
    x = np.zeros(S)
    for i in range(t.size):
        X[i] = x
        x = Ad @ x + drive[i]
    X = X.reshape(t.size, n, m, s)
    scale = b * gain[None, :]  # (n, m): b_kj s_rho^(e_j - 1)

    def read(pos, rate, per):  # (N, n, m) each -> (N, p, per mode or input)
        return (np.einsum(f"tkj,kj,pk->tp{per}", pos, scale, cq)
                + np.einsum(f"tkj,kj,pk->tp{per}", rate, scale, cv))

    y = read(X[..., 0], X[..., 1], "j")
    if not derivatives:
        return y
    return y, read(X[..., 2], X[..., 3], "k"), read(X[..., 4], X[..., 5], "k")
