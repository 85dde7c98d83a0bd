"""``prbdm linearize --spin``: its check against the hub and the loads, and its record fields."""

from __future__ import annotations

from ..errors import BeamInputError

__all__ = ["check_spin_option", "spin_record"]


def check_spin_option(spin: float | None, opts: dict) -> None:
    """Refuse ``--spin`` without ``--hub`` or with a ``--load``/``--gravity`` off the hub axis.

    ``opts`` holds the parsed ``hub``, ``load`` (N) and ``gravity`` (m/s^2).
    """
    from .checks import in_range

    if spin is None:
        return
    in_range("--spin", spin, unit="rad/s")
    if opts["hub"] is None:
        raise BeamInputError(f"--spin = {spin!r}: needs --hub INERTIA:RADIUS (the hub spins)")
    axis = opts["hub"].axis
    off = [i for i, a in enumerate("xyz") if a != axis]
    gravity = opts["gravity"] or (0.0, 0.0, 0.0)  # None: not given (the model's comes later)
    if any(opts["load"][i] for i in off) or any(gravity[i] for i in off):
        raise BeamInputError(f"--spin = {spin!r}: a spinning hub has no steady equilibrium "
                             f"under a --load or --gravity off its axis ({axis}: they turn "
                             "with the world, not the hub); give them along the hub axis, or "
                             "none")


def spin_record(spin: float | None, lin) -> dict:
    """Return the record fields ``spin_rad_s`` and ``spin_frequencies_rad_s`` (rad/s).

    The frequencies are the undamped flexible ones with the gyroscopic coupling
    (:func:`prbdm_pin.plant.spin.gyroscopic_frequencies`; the modal table leaves it out, zero
    at the straight pose but not at a coned one); None without a spin.
    """
    from ..plant.spin import gyroscopic_frequencies

    return {"spin_rad_s": 0.0 if spin is None else spin,
            "spin_frequencies_rad_s": gyroscopic_frequencies(lin).tolist() if spin else None}
