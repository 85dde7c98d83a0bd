"""The equations of motion of B planar clamped designs, evaluated together.

    M_b(q_b) a_b + h_b(q_b, v_b) + K_b q_b + C_b v_b = J_b(q_b)^T F_b(t) + B_b u_b

for every design b at once: M, h and J^T F in closed form (:mod:`prbdm_pin.chain.planar_batch`),
the damping matrix of each design frozen at its start pose as ``simulate`` freezes it
(:mod:`.system`), the inputs' constant map B_0 and tip forces as :mod:`.inputs` builds them, and
u = u_0 (+ a shared function of time) - G x for constants and state-feedback gains.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..chain.planar_batch import PlanarLinks, batch_mass, design_links
from ..errors import BeamInputError
from .damping import damping_matrix, damping_ratios, spring_modal_damping
from .inputs import Controller, StateFeedback, input_force
from .system import force_function

__all__ = ["BatchPlant", "vectorised_plant"]


@dataclass(frozen=True, eq=False)
class BatchPlant:
    """B designs' equations of motion as one right-hand side over the batch axis.

    Attributes
    ----------
    links : PlanarLinks
    stiffness_Nm_per_rad : ndarray (B, n)
    damping_Nms_per_rad : ndarray (B, n, n) or None
    force_N : ndarray (B, 3), callable t -> (3,), or None
        The tip load, N (world).
    input_map : ndarray (B, n, m) or None
        B_0 of the inputs (torques, strain actuators), N m per input unit.
    tip_rows : tuple of (column, axis)
        The inputs that are tip forces.
    u0 : ndarray (B, m) or None
        The inputs' constant part (u_ref + G x_ref).
    u_time : callable t -> (m,) or None
        A shared function of time added to ``u0``.
    gain : ndarray (B, m, 2n) or None
        State-feedback gains G.
    """

    links: PlanarLinks
    stiffness_Nm_per_rad: np.ndarray
    damping_Nms_per_rad: np.ndarray | None
    force_N: np.ndarray | Callable[[float], np.ndarray] | None
    input_map: np.ndarray | None = None
    tip_rows: tuple = ()
    u0: np.ndarray | None = None
    u_time: Callable[[float], np.ndarray] | None = None
    gain: np.ndarray | None = None

    @property
    def timed(self) -> bool:
        """Whether a tip force or the inputs are a function of time."""
        return callable(self.force_N) or self.u_time is not None

    def stiffness_order(self, y0: np.ndarray) -> np.ndarray:
        """Return the designs (B,) sorted by their highest natural frequency at y0's pose.

        What bounds an explicit step on a lightly damped chain: designs of like frequency
        share a block, whose step its stiffest design sets.
        """
        n = self.stiffness_Nm_per_rad.shape[1]
        M = batch_mass(self.links, y0[:, :n])
        w2 = np.linalg.eigvals(np.linalg.solve(M, self.stiffness_Nm_per_rad[:, :, None]
                                               * np.eye(n))).real.max(axis=1)
        return np.argsort(w2, kind="stable")

    def block_constants(self, W: int, order: np.ndarray) -> tuple:
        """Return the designs' constants, in ``order``, in blocks of W, and the stages' flags.

        (P (blocks, R, W), n, m, damped, gained, T (3, m)): P the rows of
        :func:`prbdm_pin.chain.planar_batch_kernel.param_rows`, the last block padded with
        copies of its first design; T maps the inputs that are tip forces onto the force's
        axes.
        """
        from ..chain.planar_batch_kernel import mass_rows, param_rows
        from .batch_rk import blocks

        B, n = self.stiffness_Nm_per_rad.shape
        m = 0 if self.input_map is None else self.input_map.shape[2]
        damped, gained = self.damping_Nms_per_rad is not None, self.gain is not None
        rows = param_rows(n, m, damped, gained)
        P = np.zeros((B, rows["end"]))
        lk = self.links
        Ma, Mb = mass_rows(lk)
        parts = [("L", lk.lengths_m), ("mass", lk.mass_kg), ("off", lk.com_offset_m),
                 ("Ma", Ma), ("Mb", Mb), ("k", self.stiffness_Nm_per_rad)]
        if self.force_N is not None and not callable(self.force_N):
            parts.append(("F", self.force_N))
        if m:
            parts += [("u0", self.u0), ("B0", self.input_map.reshape(B, n * m))]
        if damped:
            parts.append(("C", self.damping_Nms_per_rad.reshape(B, n * n)))
        if gained:
            parts.append(("G", self.gain.reshape(B, 2 * n * m)))
        for name, a in parts:
            P[:, rows[name]:rows[name] + a.shape[1]] = a
        T = np.zeros((3, m))
        for col, axis in self.tip_rows:
            T[axis, col] += 1.0
        return blocks(P[order], W), n, m, damped, gained, T

    def stage_inputs(self, times: np.ndarray, stages: int) -> tuple[np.ndarray, np.ndarray]:
        """Return the shared functions of time at the stage times (s): force (S, 3), u (S, m)."""
        m = 0 if self.input_map is None else self.input_map.shape[2]
        FT, UT = np.zeros((stages, 3)), np.zeros((stages, m))
        for s, t in enumerate(times if self.timed else ()):
            if callable(self.force_N):
                FT[s] = self.force_N(t)
            if self.u_time is not None:
                UT[s] = self.u_time(t)
        return FT, UT


def vectorised_plant(models: list, Q0: np.ndarray, options, inputs: tuple, signals: list,
                     actuators: tuple, force) -> BatchPlant | None:
    """Return the :class:`BatchPlant` of the designs, or None when a chain is not planar.

    ``force`` is the tip load: None, (B, 3) N, or a shared function of time; ``signals`` the
    designs' input signals (constants, StateFeedback gains or one shared function of time, as
    :func:`.batch._vectorisable` admits them); the damping matrices are frozen at ``Q0``.
    """
    links = design_links(models)
    if links is None:
        return None
    B, n = Q0.shape
    k = np.array([m.stiffness_Nm_per_rad for m in models], dtype=float)
    ratio = options.damping_ratio
    xi = damping_ratios(np.asarray(ratio, dtype=float) if isinstance(ratio, tuple) else ratio,
                        n)
    C = None
    if np.any(xi > 0.0):
        Mc = batch_mass(links, Q0)
        if options.damping == "modal":  # one stacked eigensolve (the joints all have springs)
            C = spring_modal_damping(Mc, k, xi)
        else:
            C = np.stack([damping_matrix(Mc[b], np.diag(k[b]), xi, options.damping)
                          for b in range(B)])
    if callable(force):
        force = force_function(force)[0]
    plant = BatchPlant(links, k, C, force)
    if not inputs:
        return plant
    per_design = any(s is not signals[0] for s in signals)
    forces = []
    for b, (model, s) in enumerate(zip(models, signals, strict=True)):
        try:
            forces.append(input_force(model, inputs, s, actuators, None))
        except BeamInputError as exc:
            raise BeamInputError(f"u[{b}]: {exc}" if per_design else str(exc)) from None
    zero = np.zeros(n)
    timed = [s for s in signals if callable(s) and not isinstance(s, (Controller,
                                                                      StateFeedback))]
    u_time = None
    if timed:  # one shared function of time (the batch refuses others)
        u_time = (lambda f: lambda t: f(t, zero, zero))(forces[0].signal)
    # u = u_0 - G x: a constant or a feedback's u_ref - G (x - x_ref) read at x = 0
    u0 = np.array([np.zeros(len(f.names)) if timed else f.signal(0.0, zero, zero)
                   for f in forces])
    gains = [f.gain for f in forces]
    gain = None if all(g is None for g in gains) else np.array(
        [np.zeros((len(f.names), 2 * n)) if g is None else g for f, g in zip(forces, gains,
                                                                               strict=True)])
    return BatchPlant(links, k, C, force, np.array([f.b0 for f in forces]),
                      forces[0].tip_rows, u0, u_time, gain)
