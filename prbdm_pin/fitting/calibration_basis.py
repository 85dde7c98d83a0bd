"""The free ring-down of a clamped chain's modes and its derivatives in the parameters.

Scaling E by s_E scales every spring (K -> s_E K); scaling rho by s_rho scales every link's
mass and inertia (M -> s_rho M). The modes of (s_E K, s_rho M) are those of (K, M) with
omega_k = omega0_k sqrt(s_E / s_rho) and mass-normalised shapes Phi0 / sqrt(s_rho). Free, the
modal coordinate k rings as

    eta_k(t) = exp(-sigma t) (a_k cos(w_d t) + b_k sin(w_d t)),
    sigma = zeta_k omega_k,  w_d = omega_k sqrt(1 - zeta_k^2),

so a measured output y_c = Cq_c Phi eta + Cv_c Phi eta' is linear in (a_k, b_k): the unknown
initial state. The shapes' 1/sqrt(s_rho) goes into (a, b), so a ring-down sees s_E / s_rho
alone.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ring_basis"]


def _waves(t, sigma, wd):
    e = np.exp(-sigma * t)
    return e * np.cos(wd * t), e * np.sin(wd * t)


def ring_basis(t_s: np.ndarray, omega_rad_s: np.ndarray, zeta: np.ndarray, cq: np.ndarray,
               cv: np.ndarray, derivatives: bool = False):
    """Return the ring-down basis and, with ``derivatives``, its derivatives.

    Parameters
    ----------
    t_s : ndarray (N,)
        Times, s.
    omega_rad_s, zeta : ndarray (n,)
        Undamped frequencies, rad/s, and damping ratios of the n modes.
    cq, cv : ndarray (c, n)
        Each channel's reading of the modal coordinates and of their rates (modal C).

    Returns
    -------
    B : ndarray (N, c, 2 n)
        Column 2k: channel response to a_k = 1; column 2k+1: to b_k = 1.
    dB_domega, dB_dzeta : ndarray (N, c, 2 n)
        With ``derivatives``: column 2k(+1) differentiated in omega_k (1/(rad/s)) and zeta_k.
    """
    t = np.asarray(t_s, dtype=float)[:, None]
    w, z = np.asarray(omega_rad_s, float), np.asarray(zeta, float)
    root = np.sqrt(1.0 - z**2)
    sigma, wd = z * w, w * root
    g, h = _waves(t, sigma, wd)  # (N, n)
    # the rates: g' = -sigma g - wd h, h' = -sigma h + wd g
    gp, hp = -sigma * g - wd * h, -sigma * h + wd * g
    N, n, c = t.shape[0], w.size, cq.shape[0]

    def assemble(pos_a, rate_a, pos_b, rate_b):
        out = np.empty((N, c, 2 * n))
        out[:, :, 0::2] = pos_a[:, None, :] * cq[None] + rate_a[:, None, :] * cv[None]
        out[:, :, 1::2] = pos_b[:, None, :] * cq[None] + rate_b[:, None, :] * cv[None]
        return out

    B = assemble(g, gp, h, hp)
    if not derivatives:
        return B
    # in sigma and wd: dg/dsigma = -t g, dg/dwd = -t h, dh/dsigma = -t h, dh/dwd = t g
    g_s, g_w, h_s, h_w = -t * g, -t * h, -t * h, t * g
    gp_s = -g - sigma * g_s - wd * h_s
    gp_w = -sigma * g_w - h - wd * h_w
    hp_s = -h - sigma * h_s + wd * g_s
    hp_w = -sigma * h_w + g + wd * g_w
    # chain rule: sigma = zeta w, wd = w sqrt(1 - zeta^2)
    ds_dw, dwd_dw, ds_dz, dwd_dz = z, root, w, -w * z / root

    def d(ds, dwd):
        return assemble(g_s * ds + g_w * dwd, gp_s * ds + gp_w * dwd,
                        h_s * ds + h_w * dwd, hp_s * ds + hp_w * dwd)

    return B, d(ds_dw, dwd_dw), d(ds_dz, dwd_dz)
