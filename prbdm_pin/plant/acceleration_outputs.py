"""Outputs that read the acceleration, folded into the state space.

An output y = C_q dq + C_v dv + C_a dv' + D_u du (the root reaction, the strain near the root:
:mod:`prbdm_pin.model.load_outputs`) reads the acceleration of the plant's own dynamics,
dv' = M^-1 (-K_e dq - C_d dv + B_q du), so

    C = [C_q - C_a M^-1 K_e, C_v - C_a M^-1 C_d],   D = C_a M^-1 B_q + D_u.

Outputs without an acceleration or direct input path keep C = [C_q, C_v] and D = 0 exactly.
"""

from __future__ import annotations

import numpy as np

from ..model.inputs import parse_inputs
from ..model.load_outputs import load_output_rows
from ..model.outputs import parse_outputs

__all__ = ["load_rows", "output_matrices"]


def load_rows(model, q: np.ndarray, out_names, in_names, n_actuators: int,
              load_N: np.ndarray, gravity_m_s2: np.ndarray | None, spans: tuple = ()):
    """Return (C_q, C_v, C_a, D_u) of the load outputs at pose ``q`` (rad); zero elsewhere.

    ``spans``: the DistributedLoad spans of indexed distributed-force inputs.
    """
    hub = model.hub is not None
    return load_output_rows(model, q, parse_outputs(out_names, model.n_springs, hub),
                            parse_inputs(in_names, model.n_springs, n_actuators, hub,
                                         len(spans)),
                            load_N, gravity_m_s2, tuple(spans))


def output_matrices(Cq: np.ndarray, Cv: np.ndarray, Ca: np.ndarray, Du: np.ndarray,
                    X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return the state space's (C, D) from the output rows and X = M^-1 [K_e, C_d, B_q].

    Shapes: rows (p, nv), ``Du`` (p, m), ``X`` (nv, 2 nv + m).
    """
    nv = Cq.shape[1]
    CaX = Ca @ X
    C = np.hstack([Cq - CaX[:, :nv], Cv - CaX[:, nv:2 * nv]])
    return C, CaX[:, 2 * nv:] + Du
