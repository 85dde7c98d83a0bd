"""Outputs that read the loads the member carries: the root reaction and the surface strain.

They depend on the acceleration and on the applied loads as well as on the pose, so their
linear rows are y = C_q dq + C_v dv + C_a dv' + D_u du (the plant folds the acceleration in,
:func:`prbdm_pin.plant.linearize`), and a time response needs its accelerations and loads at
each sample. :mod:`prbdm_pin.model.reaction` and :mod:`prbdm_pin.model.strain` define them.
"""

from __future__ import annotations

import numpy as np

from .reaction import (
    REACTION_OUTPUTS,
    applied_wrench,
    applied_wrench_columns,
    inertial_wrench,
    inertial_wrench_derivatives,
)
from .strain import strain_terms

__all__ = ["LOAD_OUTPUTS", "is_load_output", "load_output_rows", "load_output_values",
           "load_output_samples"]

LOAD_OUTPUTS = (*REACTION_OUTPUTS, "strain")
_MY = REACTION_OUTPUTS["root_moment_y"]


def is_load_output(base: str) -> bool:
    """Whether outputs of base name ``base`` read the loads (acceleration and inputs)."""
    return base in LOAD_OUTPUTS


def _tip_y_axis(model, q: np.ndarray) -> np.ndarray:
    return model.tip_pose(q)[1][:, 1]


def load_output_rows(model, q: np.ndarray, parsed_outputs, parsed_inputs,
                     load_N: np.ndarray | None = None,
                     gravity_m_s2: np.ndarray | None = None, spans: tuple = ()):
    """Return (C_q, C_v, C_a, D_u) of the load outputs at rest at pose ``q`` (rad).

    Shapes (p, nv) three times and (p, m); the rows of the other outputs are zero.
    ``parsed_outputs`` and ``parsed_inputs`` as the parsers return them; ``load_N`` the dead
    tip force held at equilibrium (N, world), ``gravity_m_s2`` (m/s^2, world), ``spans`` the
    DistributedLoad spans of indexed distributed-force inputs.
    """
    nv, p, m = model.pin_model.nv, len(parsed_outputs), len(parsed_inputs)
    Cq, Cv, Ca, Du = (np.zeros((p, nv)), np.zeros((p, nv)), np.zeros((p, nv)), np.zeros((p, m)))
    if not any(is_load_output(b) for _, b, _ in parsed_outputs):
        return Cq, Cv, Ca, Du
    z = np.zeros(nv)
    dq, dv, da = inertial_wrench_derivatives(model, q, z, z, gravity_m_s2)
    F = np.zeros(3) if load_N is None else np.asarray(load_N, dtype=float)
    dWq = applied_wrench(model, q, {"tip_force": F}, derivative=True)[1]
    reaction = (dq - dWq, dv, da, -applied_wrench_columns(model, q, parsed_inputs,
                                                          spans=spans))
    tip_y = None
    for r, (name, base, idx) in enumerate(parsed_outputs):
        if base in REACTION_OUTPUTS:  # what the member exerts on its support: -R
            k = REACTION_OUTPUTS[base]
            for out, src in zip((Cq, Cv, Ca, Du), reaction, strict=True):
                out[r] = -src[k]
        elif base == "strain":
            scale, w_root, joints, w_tip = strain_terms(model, idx[0], name)
            for out, src in zip((Cq, Cv, Ca, Du), reaction, strict=True):
                out[r] = -scale * w_root * src[_MY]  # M(0) = -R_my
            for c, w in joints:
                Cq[r, c] += scale * w * model.stiffness_matrix()[c, c]
            if w_tip:  # M(L) = m . (tip y axis); no tip moment at the equilibrium
                tip_y = _tip_y_axis(model, q) if tip_y is None else tip_y
                for c, (_, b, _) in enumerate(parsed_inputs):
                    if b == "tip_moment_follower_y":  # about the tip's own y axis
                        Du[r, c] += scale * w_tip
                    elif b in ("tip_moment_x", "tip_moment_y", "tip_moment_z"):
                        Du[r, c] += scale * w_tip * tip_y["xyz".index(b[-1])]
    return Cq, Cv, Ca, Du


def load_output_values(model, q: np.ndarray, v: np.ndarray, a: np.ndarray, parsed_outputs,
                       loads: dict[str, np.ndarray],
                       gravity_m_s2: np.ndarray | None = None) -> np.ndarray:
    """Return the load outputs' values in the state (q rad, v rad/s, a rad/s^2), shape (p,).

    ``loads`` the applied loads as :func:`prbdm_pin.model.reaction.applied_wrench` takes them
    (its ``tip_moment`` also makes the strain's moment at the tip); 0 for other outputs.
    """
    return load_output_samples(model, np.asarray(q)[None], np.asarray(v)[None],
                               np.asarray(a)[None], parsed_outputs, [loads], gravity_m_s2)[0]


def load_output_samples(model, Q: np.ndarray, V: np.ndarray, A: np.ndarray, parsed_outputs,
                        loads, gravity_m_s2: np.ndarray | None = None) -> np.ndarray:
    """Return the load outputs' values at the states (Q rad, V rad/s, A rad/s^2), (s, p).

    ``loads`` one dict per state, as :func:`load_output_values` takes it; 0 for the other
    outputs. Each strain's composition is found once for all the states.
    """
    out = np.zeros((len(Q), len(parsed_outputs)))
    rows = [(r, base, strain_terms(model, idx[0], name) if base == "strain" else None)
            for r, (name, base, idx) in enumerate(parsed_outputs) if is_load_output(base)]
    if not rows:
        return out
    k = np.diag(model.stiffness_matrix())
    for i, (q, v, a, ld) in enumerate(zip(Q, V, A, loads, strict=True)):
        R = inertial_wrench(model, q, v, a, gravity_m_s2) - applied_wrench(model, q, ld)
        m_tip, tip_y = ld.get("tip_moment"), None
        for r, base, terms in rows:
            if terms is None:  # what the member exerts on its support: -R
                out[i, r] = -R[REACTION_OUTPUTS[base]]
                continue
            scale, w_root, joints, w_tip = terms
            moment = -w_root * R[_MY] + sum(w * k[c] * q[c] for c, w in joints)
            if w_tip and m_tip is not None and np.any(m_tip):
                tip_y = _tip_y_axis(model, q) if tip_y is None else tip_y
                moment += w_tip * float(np.dot(m_tip, tip_y))
            if w_tip:  # a follower moment about the tip's own y axis
                moment += w_tip * sum(val for b, _, val in ld.get("extra", ())
                                      if b == "tip_moment_follower_y")
            out[i, r] = scale * moment
    return out
