"""``trajectory.csv``: a simulated trajectory as comma-separated text (``prbdm simulate``)."""

from __future__ import annotations

import numpy as np

__all__ = ["trajectory_csv"]

_BUS_COORDS = ("bus_x_m", "bus_y_m", "bus_z_m", "bus_yaw_rad", "bus_pitch_rad", "bus_roll_rad")
_BUS_RATES = ("bus_x_m_s", "bus_y_m_s", "bus_z_m_s", "bus_yaw_rad_s", "bus_pitch_rad_s",
              "bus_roll_rad_s")


def trajectory_csv(tr, hub: bool = False, extra: dict[str, np.ndarray] | None = None,
                   bus: bool = False) -> str:
    """Return the CSV text of a :class:`~prbdm_pin.simulation.Trajectory`.

    Columns: ``t_s``; the coordinates (``hub_angle_rad`` first on a hub model, then ``q1_rad``
    ...) and their rates (rad/s); the tip position ``tip_x_m``, ``tip_y_m``, ``tip_z_m``; each
    input as ``u:NAME`` and each output as ``y:NAME`` in their units. One row per sample, every
    value written with ``repr`` so that it reads back exactly.

    Parameters
    ----------
    tr : Trajectory
        The simulated trajectory (times in s).
    hub : bool
        The model is on a hub: its first coordinate is the hub angle.
    extra : dict of str to ndarray (s,), optional
        More columns, by name, written last (the world tip of a run on a moving base).
    bus : bool
        The model is on a free bus: its six coordinates come first (``bus_x_m``, ``bus_y_m``,
        ``bus_z_m``, ``bus_yaw_rad``, ``bus_pitch_rad``, ``bus_roll_rad``, and their rates).
    """
    free = (["hub_angle_rad"] if hub else []) + (list(_BUS_COORDS) if bus else [])
    free_rates = (["hub_rate_rad_s"] if hub else []) + (list(_BUS_RATES) if bus else [])
    n = tr.q_rad.shape[1] - len(free)
    coords = free + [f"q{j + 1}_rad" for j in range(n)]
    rates = free_rates + [f"v{j + 1}_rad_s" for j in range(n)]
    head = (["t_s"] + coords + rates + ["tip_x_m", "tip_y_m", "tip_z_m"]
            + [f"u:{name}" for name in tr.input_names]
            + [f"y:{name}" for name in tr.output_names] + list(extra or {}))
    rows = np.column_stack([tr.t_s, tr.q_rad, tr.v_rad_s, tr.tip_position_m, tr.input_values,
                            tr.output_values, *(extra or {}).values()])
    return ",".join(head) + "\n" + "\n".join(",".join(repr(float(v)) for v in r)
                                             for r in rows) + "\n"
