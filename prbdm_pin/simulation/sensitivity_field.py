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
relative to a on a member whose planform varies over its length. Every moved chain is
evaluated in one compiled call per stage (:mod:`.sensitivity_stations`).

Everything but Pinocchio's ABA and its derivatives runs compiled (:mod:`.sensitivity_kernel`).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..chain.planar import chains_at_pose
from ..model.build import build_model

EPS = float(np.finfo(float).eps)
STATION_STEP = EPS ** (1.0 / 3.0)  # times the beam length, m: see the module's docstring


class Chain:
    """One chain of the field: its Pinocchio model, workspace, lengths and input map."""

    def __init__(self, model, b0: np.ndarray):
        self.pm = model.pin_model
        self.data = self.pm.createData()
        self.model = model
        self.tip_frame = int(model.tip_frame_id)
        self.lengths = np.array(model.lengths_m, dtype=float)  # a writable copy: one numba type
        self.b0 = b0


class FieldDesign:
    """The design parameters of the field and the columns each group fills.

    ``k`` (n,) N m/rad, ``beta`` s, ``c`` (n,) N m s/rad, ``gain`` G (m, 2 n), ``x_ref``
    (2 n,), ``signal`` u(t, q, v) (the feedback law itself).
    """

    def __init__(self, k, beta, c, gain, x_ref, signal, groups: tuple[str, ...], n: int,
                 m: int):
        # writable float copies: the compiled stage takes one array type
        self.k, self.c = np.array(k, dtype=float), np.array(c, dtype=float)
        self.beta, self.gain, self.x_ref = float(beta), gain, np.array(x_ref, dtype=float)
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

    The torque, the tip terms and everything around Pinocchio's ABA and its derivatives run
    compiled (:mod:`.sensitivity_kernel`), on workspace arrays this object keeps: the arrays
    its methods return are overwritten by the next call.

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
        from . import sensitivity_kernel  # numba loads with a gradient's first use

        self.kernel = sensitivity_kernel
        self.chain, self.variants, self.d = chain, variants, design
        self.force = np.ascontiguousarray(force, dtype=float)
        n, d = design.n, design
        BG = chain.b0 @ d.gain
        # d tau/dx without the load stiffness (constant over the run)
        self.dtau_dx = np.hstack((-np.diag(d.k) - BG[:, :n], -np.diag(d.beta * d.k + d.c)
                                  - BG[:, n:]))
        self.loaded = bool(force.any())
        self.B = np.ascontiguousarray(chain.b0, dtype=float).reshape(n, d.m)
        self.gain = np.ascontiguousarray(d.gain, dtype=float).reshape(d.m, 2 * n)
        self.starts = np.array([d.slices[g].start if g in d.slices else -1
                                for g in ("springs", "beta", "dampers", "gain")], dtype=np.int64)
        self.rc, self.rs, self.tau = np.empty(n), np.empty(n), np.empty(n)
        self.A = np.empty((n, 2 * n))
        self.Fp = np.zeros((n, d.size))  # the start state's columns stay zero
        self.dzp = np.zeros(d.size)  # nonzero on the stations only
        self._minv = None
        # the moved chains side by side: (lo_1, hi_1, lo_2, ...), all evaluated in one call
        moved = [ch for lo, hi, _ in variants for ch in (lo, hi)]
        self.moved_lengths = np.array([ch.lengths for ch in moved]).reshape(len(moved), n + 1)
        self.two_h = np.array([2.0 * h for _, _, h in variants])
        self.stations = _moved_chains(moved, design.k, self.force, self.two_h) if moved \
            else None
        self.evaluations = 0

    def _torque(self, t: float, x: np.ndarray):
        """Return (q, v, u, z m) with the torque and lever arms in the workspace."""
        d, n = self.d, self.d.n
        q, v = x[:n], x[n:]
        u = np.asarray(d.signal(t, q, v), dtype=float)
        z = self.kernel.closed_loop_torque(self.chain.lengths, q, v, u, d.k, d.beta, d.c,
                                           self.B, self.force, self.rc, self.rs, self.tau)
        return q, v, u, z

    def tip_x(self) -> float:
        """Return the tip's x (m) of the last evaluation, L_0 + c_0 (z is its return value)."""
        return float(self.chain.lengths[0] + self.rc[0])

    def value(self, t: float, x: np.ndarray):
        """Return (a (n,), u (m,), z m, dz/dq (n,)) at time t (s) and state x."""
        q, v, u, z = self._torque(t, x)
        c = self.chain
        self.evaluations += 1
        return pin.aba(c.pm, c.data, q, v, self.tau), u, z, -self.rc

    def sensitivity_stage(self, t: float, x: np.ndarray):
        """Return (a (n,), u (m,), z m) and keep df/dx's parts for :meth:`stage_rates`."""
        q, v, u, z = self._torque(t, x)
        c, d = self.chain, self.d
        self._dq, self._dv, self._minv = pin.computeABADerivatives(c.pm, c.data, q, v, self.tau)
        if self.stations is not None:
            self.stations.columns(q, v, u, d.k, d.beta, d.c, self.force, self.loaded,
                                  c.data.ddq, self._minv, self.Fp, self.dzp,
                                  d.slices["stations"].start)
        self.evaluations += 1
        return c.data.ddq, u, z

    def stage_rates(self, x, S, lx, lu, lz: float, dS, dg) -> bool:
        """Write S' (2 n, P) into dS and the gradient's rate (P,) into dg.

        At the state of the last :meth:`sensitivity_stage`, with the cost's partials there;
        False when a partial is NaN or infinite.
        """
        d = self.d
        return self.kernel.stage_rates(self._dq, self._dv, self._minv, self.dtau_dx, self.rc,
                                       self.rs, self.force, self.loaded, self.B, x, d.x_ref,
                                       d.k, d.beta, self.gain, self.starts, S, lx, lu, lz,
                                       self.dzp, self.A, self.Fp, dS, dg)

    def state_jacobian(self, t: float, x: np.ndarray) -> np.ndarray:
        """Return df/dx's lower half (n, 2 n) at time t (s) and state x."""
        q, v, _, _ = self._torque(t, x)
        c = self.chain
        dq, dv, minv = pin.computeABADerivatives(c.pm, c.data, q, v, self.tau)
        A = np.empty((self.d.n, 2 * self.d.n))
        self.kernel.state_jacobian(dq, dv, minv, self.dtau_dx, self.rc, self.rs, self.force,
                                   self.loaded, A)
        return A

    def tip_station_derivative(self, q: np.ndarray) -> np.ndarray:
        """Return dz/dp (P,) of the tip height at pose q: the stations' central difference."""
        out = np.zeros(self.d.size)
        s = self.d.slices.get("stations")
        if s is not None:
            z = chains_at_pose(self.moved_lengths, q, self.force)[0]
            out[s] = (z[1::2] - z[0::2]) / self.two_h
        return out


def _moved_chains(moved: list, k: np.ndarray, force: np.ndarray, two_h: np.ndarray):
    """Return the stations' evaluator: the planar closed forms when every moved chain has them.

    That is a clamped planar chain without gravity and with its centres of mass on the links'
    axes (what ``build_model`` gives); otherwise the general kernel's residual.
    """
    from ..chain.planar_batch import design_links
    from .sensitivity_stations import MovedChains, PlanarMovedChains  # numba loads here

    links = design_links([ch.model for ch in moved])
    if links is not None and not any(ch.pm.gravity.linear.any() for ch in moved):
        return PlanarMovedChains(links, np.array([ch.b0 for ch in moved]), k, force, two_h)
    return MovedChains([(ch.pm, ch.tip_frame, ch.b0) for ch in moved], two_h)


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
