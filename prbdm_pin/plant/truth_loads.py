"""The loads of a PRBDM plant on the truth's side: a tip moment about y and a uniform line load.

The truth plants (``truth.plant``: clamped, on a hub, on a free bus) take the tip force, the
strain actuators and the clamp's acceleration; :func:`with_truth_loads` appends the columns of

- ``tip_moment_y`` and ``tip_moment_follower_y`` (N m about y at the tip; at first order about
  the straight pose the dead and follower moments are one load): its virtual work is M times
  the tip section's rotation, which is a strain actuator's over (0, L) on the modes (the PRBDM's
  ``tip_moment_y`` column equals its ``strain`` column over (0, L) exactly), plus the rigid
  turn about y of a hub about y or a bus;
- ``distributed_force_z`` (N/m along z, uniform over the span, spread over the width): mode k
  receives int phi_k dx, which on a member of uniform width 2w is int rho t phi_k dA / (rho t 2w)
  (the modes' ``translation``); a hub about y receives -(r L + L^2 / 2) of it, a bus L on its
  translation and -(r L + L^2 / 2) on its turn. A member whose width varies has no such column
  here, and the comparison says so.

The tip moment's modal column comes from the plant built with one more actuator over (0, L)
(its last ``strain`` column), which this module renames.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.linalg as sla

__all__ = ["TIP_MOMENTS", "LINE_LOAD", "with_truth_loads"]

TIP_MOMENTS = ("tip_moment_y", "tip_moment_follower_y")
LINE_LOAD = "distributed_force_z"


def _rigid(plant, L: float) -> tuple[np.ndarray, np.ndarray, int]:
    """(rigid part of the tip moment's column, of the line load's, number of rigid coordinates)."""
    if hasattr(plant, "bus_mass_kg"):  # [z_b, theta_b, eta]
        r = plant.root_m
        return np.array([0.0, 1.0]), np.array([L, -(r * L + 0.5 * L**2)]), 2
    if hasattr(plant, "hub_radius_m"):  # [theta, eta]; a hub about x or z is uncoupled
        coupled = bool(np.any(plant.participation_sqrt_kg_m))
        r = plant.hub_radius_m
        if coupled:
            return np.array([1.0]), np.array([-(r * L + 0.5 * L**2)]), 1
        return np.zeros(1), np.zeros(1), 1
    return np.zeros(0), np.zeros(0), 0


def with_truth_loads(plant, beam, wanted, tip_column: str | None):
    """Return ``plant`` with the load inputs ``wanted`` names appended (module notes).

    Parameters
    ----------
    plant : ClampedModel, HybridModel or BusModel
        Built with the PRBDM's actuators and, when a tip moment is wanted, one more over
        (0, L): its input ``tip_column``.
    beam : Beam
        The member (its length, width, thickness and density).
    wanted : iterable of str
        The PRBDM plant's input names; those of ``TIP_MOMENTS`` and ``LINE_LOAD`` are added.
    tip_column : str or None
        The name of the actuator column over (0, L), dropped from the result.

    Returns
    -------
    The same kind of plant, with the columns appended to ``input_matrix`` and ``B``.
    """
    names = list(plant.input_names)
    Bq = np.asarray(plant.input_matrix, dtype=float)
    L = float(beam.length_m)
    rigid_m, rigid_q, n_r = _rigid(plant, L)
    cols, new = [], []
    for name in wanted:
        if name in TIP_MOMENTS and tip_column is not None:
            c = Bq[:, names.index(tip_column)].copy()
            c[:n_r] = rigid_m
            cols.append(c)
            new.append(name)
        elif name == LINE_LOAD and np.ptp(beam.half_width_m) == 0.0:
            M = np.asarray(plant.mass, dtype=float)
            t = M[0, n_r:] if n_r == 2 else -Bq[n_r:, names.index("base_accel_z")]
            t_u = beam.uniform_thickness_m("the truth's line load")
            rho_t_width = beam.material.rho_kg_m3 * t_u * 2 * beam.half_width_m[0]
            cols.append(np.concatenate([rigid_q, t / rho_t_width]))
            new.append(name)
    keep = [i for i, n in enumerate(names) if n != tip_column]
    Bq = np.column_stack([Bq[:, keep], *cols]) if cols else Bq[:, keep]
    B = np.vstack([np.zeros_like(Bq), sla.solve(plant.mass, Bq, assume_a="pos")])
    for a in (Bq, B):
        a.setflags(write=False)
    D = np.zeros((np.asarray(plant.C).shape[0], Bq.shape[1]))
    D.setflags(write=False)
    return dataclasses.replace(plant, input_matrix=Bq, B=B, D=D,
                               input_names=tuple(names[i] for i in keep) + tuple(new))
