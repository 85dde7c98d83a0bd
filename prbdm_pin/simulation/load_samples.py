"""What the load outputs (root reaction, strain) read along a time response.

The accelerations of the samples, a = M^-1 (tau - h) by Pinocchio's ABA with the run's own
forces (springs, damping, tip force, inputs, weight), and the applied loads at each sample.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..model.names import split_name
from ..model.reaction import input_loads

__all__ = ["sample_accelerations", "sample_loads"]


def sample_accelerations(system, t: np.ndarray, Q: np.ndarray, V: np.ndarray) -> np.ndarray:
    """Return the accelerations (rad/s^2, (s, nv)) at the samples (t s, Q rad, V rad/s)."""
    C = system.damping_Nms_per_rad
    A = np.empty_like(Q)
    for i, (ti, q, v) in enumerate(zip(t, Q, V, strict=True)):
        tau = -system.springs(q) * q
        if C is not None:
            tau = tau - C @ v
        te = system.tau_external(q, float(ti), v)
        if te is not None:
            tau = tau + te
        A[i] = pin.aba(system.pin_model, system.data, q, v, tau)
    return A


def sample_loads(model, system, force, t: np.ndarray, U: np.ndarray, spans: tuple = ()
                 ) -> list[dict]:
    """Return the applied loads at each sample, as the load outputs take them.

    ``force`` the run's tip force of time (N, world; None for none), ``U`` the inputs' values
    (s, m) in the order of ``system.inputs.names``, ``spans`` the DistributedLoad spans of
    indexed distributed forces.
    """
    f = system.inputs
    # the names were checked when the run was set up: their bases and indices are all that is
    # read here
    parsed = () if f is None else tuple((n, *split_name(n, "inputs")) for n in f.names)
    return [input_loads(parsed, u, None if force is None else force(float(ti)), spans)
            for ti, u in zip(t, U, strict=True)]
