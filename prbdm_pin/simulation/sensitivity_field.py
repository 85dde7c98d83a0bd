"""The vector field of a planar chain's closed loop, with its state and design derivatives.

    M(q, s) a + h(q, v, s) + K q + (beta K + diag(c)) v = J(q, s)^T F + B(s) u,
    u = u_ref(t) - G (x - x_ref),  x = (q, v),

with K = diag(k) the joint springs (N m/rad), beta a stiffness-proportional damping (s), c
per-joint dampers (N m s/rad), F a constant world tip force (N), B the inputs' constant map
(joint torques, strain patches) and G a state-feedback gain; s are the joint stations (m: the
link lengths on their simplex, :mod:`prbdm_pin.chain.sections_derivatives`).

The state derivative comes from Pinocchio's ABA derivatives plus the torque's own, analytic:
d tau/dq = -K + d(J^T F)/dq - B G_q, d tau/dv = -(beta K + diag(c)) - B G_v. The design
derivative is analytic for k, beta, c and G (each enters tau linearly: d a/dp = M^-1 d tau/dp).
The stations move the links' masses, centres and inertias and the joints' placements; their
derivative is a central difference of this vector field (not of a trajectory) between two
chains rebuilt by ``build_model`` with the station moved by +-h, h = EPS^(1/3) L (L the
beam length): truncation h^2/6 |a'''| and rounding EPS |a| / h balance there, about 1e-10
relative to a on a member whose planform varies over its length.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..chain.planar import chains_at_pose, tip_terms
from ..model.build import build_model

EPS = float(np.finfo(float).eps)
STATION_STEP = EPS ** (1.0 / 3.0)  # times the beam length, m: see the module's docstring


class Chain:
    """One chain of the field: its Pinocchio model, workspace, lengths and input map."""

    def __init__(self, model, b0: np.ndarray):
        self.pm = model.pin_model
        self.data = self.pm.createData()
        self.tip_frame = int(model.tip_frame_id)
        self.lengths = np.asarray(model.lengths_m, dtype=float)
        self.b0 = b0

    def tip(self, q: np.ndarray, force: np.ndarray):
        """Return the tip (3,) m, its Jacobian (3, n) and d(J^T F)/dq (n, n)."""
        return tip_terms(self.lengths, q, force)[:3]


class FieldDesign:
    """The design parameters of the field and the columns each group fills.

    ``k`` (n,) N m/rad, ``beta`` s, ``c`` (n,) N m s/rad, ``gain`` G (m, 2 n), ``x_ref``
    (2 n,), ``signal`` u(t, q, v) (the feedback law itself).
    """

    def __init__(self, k, beta, c, gain, x_ref, signal, groups: tuple[str, ...], n: int,
                 m: int):
        self.k, self.beta, self.c, self.gain, self.x_ref = k, beta, c, gain, x_ref
        self.signal = signal
        self.n, self.m = n, m
        sizes = {"springs": n, "stations": n, "beta": 1, "dampers": n, "gain": m * 2 * n,
                 "initial": 2 * n}
        self.slices, start = {}, 0
        for g in groups:
            self.slices[g] = slice(start, start + sizes[g])
            start += sizes[g]
        self.size = start


class Field:
    """The vector field f(t, x) of the closed loop and, on demand, df/dx and df/dp.

    Parameters
    ----------
    chain : Chain
        The nominal chain.
    variants : list of (Chain, Chain, float)
        Per station: the chains with it moved by -h and +h, and h (m).
    design : FieldDesign
    force : ndarray (3,)
        Constant world tip force, N.
    """

    def __init__(self, chain: Chain, variants, design: FieldDesign, force: np.ndarray):
        self.chain, self.variants, self.d, self.force = chain, variants, design, force
        n, d = design.n, design
        BG = chain.b0 @ d.gain
        # d tau/dx without the load stiffness (constant over the run)
        self.dtau_dx = np.hstack((-np.diag(d.k) - BG[:, :n], -np.diag(d.beta * d.k + d.c)
                                  - BG[:, n:]))
        self.loaded = bool(force.any())
        # the moved chains side by side: (lo_1, hi_1, lo_2, ...), all evaluated in one call
        moved = [ch for lo, hi, _ in variants for ch in (lo, hi)]
        self.moved_lengths = np.array([ch.lengths for ch in moved]).reshape(len(moved), n + 1)
        self.two_h = np.array([2.0 * h for _, _, h in variants])
        self.stations = None
        if moved:
            from .sensitivity_stations import MovedChains  # numba loads with the stations

            self.stations = MovedChains([(ch.pm, ch.tip_frame, ch.b0) for ch in moved],
                                        self.two_h)
        self.evaluations = 0

    def _torque(self, chain: Chain, q, v, u):
        tip, J, T = chain.tip(q, self.force)
        d = self.d
        tau = -d.k * (q + d.beta * v) - d.c * v + J.T @ self.force
        if d.m:
            tau += chain.b0 @ u
        return tau, tip[2], J[2], T

    def value(self, t: float, x: np.ndarray):
        """Return (a (n,), u (m,), z m, dz/dq (n,)) at time t (s) and state x."""
        n = self.d.n
        q, v = x[:n], x[n:]
        u = self.d.signal(t, q, v)
        tau, z, dz, _ = self._torque(self.chain, q, v, u)
        c = self.chain
        self.evaluations += 1
        return pin.aba(c.pm, c.data, q, v, tau), u, z, dz

    def derivatives(self, t: float, x: np.ndarray):
        """Return what :meth:`value` does plus df/dx's lower half (n, 2 n) and the design terms.

        The design terms: d a/dp (n, P) and the tip's dz/dp (P,) at fixed state (nonzero on
        the stations only); with u, dz/dq, d u/dp is -(x - x_ref) on the gain's columns.
        """
        d, c = self.d, self.chain
        n = d.n
        q, v = x[:n], x[n:]
        u = d.signal(t, q, v)
        tau, z, dz, T = self._torque(c, q, v, u)
        dq, dv, Minv = pin.computeABADerivatives(c.pm, c.data, q, v, tau)
        a = c.data.ddq.copy()
        dtau = self.dtau_dx.copy()
        if self.loaded:
            dtau[:, :n] += T
        A = np.hstack((dq, dv)) + Minv @ dtau
        Fp = np.empty((n, d.size))
        dzp = np.zeros(d.size)
        s = d.slices
        if "springs" in s:
            Fp[:, s["springs"]] = Minv * -(q + d.beta * v)
        if "beta" in s:
            Fp[:, s["beta"]] = (Minv @ (-d.k * v))[:, None]
        if "dampers" in s:
            Fp[:, s["dampers"]] = Minv * -v
        if "gain" in s:
            MB = Minv @ c.b0
            Fp[:, s["gain"]] = (MB[:, :, None] * -(x - d.x_ref)).reshape(n, -1)
        if "initial" in s:  # the start state enters through S(0) alone
            Fp[:, s["initial"]] = 0.0
        if "stations" in s:
            self.stations.columns(q, v, u, d.k, d.beta, d.c, self.force, self.loaded, Fp, dzp,
                                  s["stations"].start)
        self.evaluations += 1
        return a, u, z, dz, A, Fp, dzp

    def tip_station_derivative(self, q: np.ndarray) -> np.ndarray:
        """Return dz/dp (P,) of the tip height at pose q: the stations' central difference."""
        out = np.zeros(self.d.size)
        s = self.d.slices.get("stations")
        if s is not None:
            z = chains_at_pose(self.moved_lengths, q, self.force)[0]
            out[s] = (z[1::2] - z[0::2]) / self.two_h
        return out


def station_variants(model, k: np.ndarray, input_map) -> list:
    """Return the chains with each station moved by -h and +h, and h (m).

    ``input_map(model)`` gives a chain's inputs map B (n, m) (strain patches move with the
    stations).
    """
    beam = model.beam
    L = np.asarray(model.lengths_m, dtype=float)
    h = STATION_STEP * float(L.sum())
    out = []
    for j in range(1, L.size):
        pair = []
        for sign in (-1.0, 1.0):
            Lj = L.copy()
            Lj[j - 1] += sign * h  # station j = L_0 + ... + L_(j-1)
            Lj[j] -= sign * h
            # the nominal chain passed its own bound; the moved one need only stay a chain
            mj = build_model(beam, Lj, k, min_fraction=0.5 * float(Lj.min() / Lj.sum()))
            pair.append(Chain(mj, input_map(mj)))
        out.append((pair[0], pair[1], h))
    return out
