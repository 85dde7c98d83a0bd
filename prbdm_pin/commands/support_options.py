"""``prbdm simulate``'s supports other than the clamp and the hub: ``--bus`` and ``--base-motion``.

The options, their checks before any work (one line naming the option, exit 2) and what a run
adds for them: the model on its bus, the prescribed motion, the world tip's columns.
"""

from __future__ import annotations

import argparse

from ..errors import BeamInputError
from .bus_option import add_bus_option, bus_option, with_bus

__all__ = ["add_support_options", "check_support_options", "supported_model", "base_motion_of",
           "world_tip_columns"]


def add_support_options(p: argparse.ArgumentParser) -> None:
    """Add ``--bus`` and ``--base-motion`` to ``prbdm simulate``."""
    add_bus_option(p)
    p.add_argument("--base-motion", default=None, metavar="FILE.csv",
                   help="a prescribed motion of the clamp (a robot flange): columns t_s,x_m,y_m,"
                        "z_m and optionally roll_rad,pitch_rad,yaw_rad (cubic-spline "
                        "interpolated; their derivatives give the rates and accelerations); "
                        "the joint angles, tip, outputs and --tip-force are then in the base "
                        "frame (--gravity stays in the world's), and trajectory.csv adds the "
                        "world tip tip_world_x_m, tip_world_y_m, tip_world_z_m; clamped models "
                        "only")


def check_support_options(args: argparse.Namespace) -> None:
    """Check ``--bus`` and ``--base-motion`` (reading its file); keep them on ``args``."""
    args.bus_spec = bus_option(args.bus)
    for given, name in ((args.hub, "--hub"), (args.base_motion, "--base-motion"),
                        (args.compare_truth, "--compare-truth")):
        if args.bus_spec is not None and given:
            raise BeamInputError(f"--bus: not with {name} (one support at a time; the truth is "
                                 "clamped)")
    args.base_motion_samples = None
    if args.base_motion is not None:
        from .base_motion_file import read_base_motion

        for given, name in ((args.compare_truth, "--compare-truth"), (args.hub, "--hub")):
            if given:
                raise BeamInputError(f"--base-motion: not with {name} (it moves the clamp of a "
                                     "clamped model)")
        args.base_motion_samples = read_base_motion(args.base_motion)


def supported_model(model, args: argparse.Namespace):
    """Return ``model`` on the ``--bus`` (itself without one)."""
    return model if args.bus_spec is None else with_bus(model, args.bus_spec)


def base_motion_of(args: argparse.Namespace):
    """Return the ``--base-motion`` samples as a BaseMotion (None without the option)."""
    if args.base_motion_samples is None:
        return None
    from ..simulation.base_motion import BaseMotion

    return BaseMotion.from_samples(*args.base_motion_samples)


def world_tip_columns(model, motion, tr) -> dict | None:
    """Return the world tip's trajectory columns of a run on a moving base (None without)."""
    if motion is None:
        return None
    from ..simulation.base_motion import world_tip_positions

    tip = world_tip_positions(model, motion, tr.t_s, tr.q_rad)
    return {f"tip_world_{a}_m": tip[:, i] for i, a in enumerate("xyz")}
