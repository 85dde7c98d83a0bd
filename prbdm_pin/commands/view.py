"""``prbdm view``: see a model: its mode shapes beside the truth's, its motion, ParaView files."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from . import add_common

EXAMPLES = """\
examples:
  prbdm view runs/ref/fit.json --out runs/ref/view
  prbdm view runs/ref/fit.json --modes 4 --response step --frames 40 --out view
  prbdm view ref.urdf --force 0,0,-2 --no-truth --out view
  prbdm view runs/ref/fit.json --meshcat --out view

Writes into OUT: modes.png (one panel per mode: the model's shape beside the truth's, both
scaled to a largest magnitude of 1, the frequencies and the signed error
100 (f_model/f_truth - 1) % in each title; bending as the deflection w, in-plane as y, torsion
as the twist), model_modes.vtu (the chain as line cells; per mode the full displacement vector
and the twist at the root, nodes and tip), truth_modes.vtu (the truth's mesh with its modes'
nodal z displacement, when the truth is available), response.gif (or .mp4 with --format mp4,
where ffmpeg is installed), and the response as a VTU series, trajectory.pvd with
trajectory_NNNN.vtu (displacement from the straight pose, twist), for ParaView.

Truth: a fit.json's, from the truth cache (computed there when absent, as --compare-truth does);
a model JSON or URDF only knows the truth frequencies its export recorded (no shapes); without
any, the model is drawn alone and the summary says so. The pairs are the fit's (by kind and, for
a spatial fit, by shape), else in order.

Response: release (default) starts at rest in the static pose under --force and lets go (a
free vibration); step starts straight and applies --force at t = 0. --force defaults to the
beam's tip force; --duration to 3 periods of mode 1; damping --damping-ratio (modal, every mode).
A model on a hub has no static pose: use --response step.

--meshcat opens Pinocchio's meshcat visualiser (links as boxes) and plays the response; it
needs meshcat (pip install meshcat) and a browser. Progress bars only on a terminal.
"""

VIEW_FILES = ("modes.png", "model_modes.vtu", "truth_modes.vtu", "response.gif",
              "response.mp4", "trajectory.pvd")
# frames of an animation and of a VTU series; the owned trajectory_NNNN.vtu names
MAX_FRAMES = 2000
RESPONSES = ("release", "step", "none")


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``view`` subparser."""
    p = subparsers.add_parser(
        "view",
        help="draw mode shapes against the truth, animate a response, write ParaView files",
        description="See a PRBDM (fit.json, model JSON or URDF): mode shapes beside the "
                    "truth's, an animated response (GIF/MP4) and VTU files.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("model", metavar="MODEL", help="fit.json, model JSON or URDF")
    p.add_argument("--beam", metavar="BEAM.json",
                   help="the beam a fit.json was fitted to (default: the one it carries)")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    p.add_argument("--modes", type=int, default=None, metavar="N",
                   help="modes drawn and written (default all flexible modes, at most 6)")
    p.add_argument("--no-truth", action="store_true",
                   help="draw the model alone (no truth from the cache)")
    p.add_argument("--cache-dir", default=None, metavar="DIR",
                   help="truth cache folder, shared with `prbdm fit` (default $PRBDM_CACHE or "
                        "~/.cache/prbdm_pin)")
    p.add_argument("--response", choices=RESPONSES, default="release",
                   help="release from the static pose under --force (default), a step of "
                        "--force from straight, or none (no animation, no series)")
    p.add_argument("--force", default=None, metavar="FX,FY,FZ",
                   help="tip force, N, world (default the beam's tip force)")
    p.add_argument("--duration", type=float, default=None, metavar="S",
                   help="simulated time, s (default 3 periods of mode 1)")
    p.add_argument("--damping-ratio", type=float, default=0.02, metavar="ZETA",
                   help="modal damping ratio of every mode (default 0.02)")
    p.add_argument("--frames", type=int, default=60, metavar="N",
                   help="frames of the animation and of the VTU series (default 60)")
    p.add_argument("--fps", type=float, default=20.0, help="frames per second (default 20)")
    p.add_argument("--format", choices=("gif", "mp4"), default="gif",
                   help="the animation's format (mp4 needs ffmpeg; default gif)")
    p.add_argument("--meshcat", action="store_true",
                   help="also open Pinocchio's meshcat visualiser (needs meshcat, a browser)")
    add_common(p)
    p.set_defaults(func=run)
    return p


def check_options(args: argparse.Namespace) -> None:
    """Refuse bad ``prbdm view`` options before the model is read (nothing written)."""
    from ..io.paths import writable_dir
    from .checks import in_range, xyz_option

    in_range("--modes", args.modes, 1, None, integer=True)
    in_range("--duration", args.duration, 0.0, None, lo_open=True, unit="s")
    in_range("--damping-ratio", args.damping_ratio, 0.0, 1.0, hi_open=True)
    in_range("--frames", args.frames, 1, MAX_FRAMES, integer=True)
    in_range("--fps", args.fps, 0.0, 100.0, lo_open=True, unit="frames per second")
    if args.force is not None:
        xyz_option(args.force, "--force", "N")
    if args.format == "mp4" and args.response != "none":
        from matplotlib.animation import FFMpegWriter

        from ..errors import BeamInputError

        if not FFMpegWriter.isAvailable():
            raise BeamInputError("--format mp4: needs ffmpeg, which is not installed here; "
                                 "use --format gif")
    if args.meshcat:
        from ..views.meshcat_view import check_meshcat

        check_meshcat()
    if args.cache_dir is not None or not args.no_truth:
        from .fit_checks import check_cache_dir

        check_cache_dir(args)
    writable_dir(args.out, "--out")


def _force(args, model) -> np.ndarray:
    from ..errors import BeamInputError
    from .checks import xyz_option

    if args.force is not None:
        return np.array(xyz_option(args.force, "--force", "N"))
    if model.beam is None:
        raise BeamInputError(f"--force: MODEL {args.model!r} carries no beam, so no tip force; "
                             "give --force FX,FY,FZ (N)")
    return np.asarray(model.beam.tip_force_N, dtype=float)


def _check_response(args, model) -> np.ndarray | None:
    """Return the tip force (N) of the response asked for (None: none); refuse what cannot run.

    Run before the truth is read, so that a refusal costs nothing.
    """
    from ..errors import BeamInputError

    if args.response == "none":
        return None
    if args.response == "release" and model.hub is not None:
        raise BeamInputError("--response release: a model on a hub has no static pose under a "
                             "tip force; use --response step")
    return _force(args, model)


def _response(args, model, n_modes: int, force: np.ndarray | None):
    """Simulate the response ``--response`` asks for under ``force`` (N); None for ``none``."""
    from ..simulation.driver import simulate

    if force is None:
        return None
    omega = model.modes()[0]
    w1 = float(omega[omega > 0.0][0])
    duration = args.duration or 3.0 * 2.0 * np.pi / w1
    # samples enough for the frames and for the fastest mode drawn (10 per period)
    w_top = float(omega[omega > 0.0][min(n_modes, omega[omega > 0.0].size) - 1])
    samples = max(args.frames, int(np.ceil(10.0 * duration * w_top / (2.0 * np.pi))), 2)
    opts = {"damping_ratio": args.damping_ratio, "damping": "modal",
            "output_dt_s": duration / (samples - 1)}
    if args.response == "release":
        q0, _ = model.static_deflection(force)
        return simulate(model, duration, q0=q0, progress=_tty(args), **opts)
    return simulate(model, duration, tip_force=force, progress=_tty(args), **opts)


def _tty(args) -> bool:
    return not args.quiet and sys.stderr.isatty()


def run(args: argparse.Namespace) -> int:
    """Run ``prbdm view``."""
    from ..files.model_source import load_model
    from ..io.output_folder import output_folder
    from ..truth.vtu import write_modes_vtu
    from ..views.animate import animate_response
    from ..views.chain_geometry import chain_modes
    from ..views.modes import plot_mode_shapes
    from ..views.vtu_model import write_model_modes_vtu, write_trajectory_vtu
    from .fit_checks import cache_dir
    from .view_truth import view_truth

    check_options(args)
    source = load_model(args.model, args.beam)
    model = source.model
    n_all = chain_modes(model).omega_rad_s.size
    if args.modes is not None and args.modes > n_all:
        from ..errors import BeamInputError

        raise BeamInputError(f"--modes = {args.modes}: the model has {n_all} flexible modes")
    n_modes = args.modes or min(n_all, 6)
    force = _check_response(args, model)
    seen = view_truth(source, n_modes, cache_dir(args) if not args.no_truth else None,
                      not args.no_truth, args.quiet)
    tr = _response(args, model, n_modes, force)
    owned = VIEW_FILES + tuple(f"trajectory_{i:04d}.vtu" for i in range(MAX_FRAMES))
    written = []
    with output_folder(args.out, owned, marker="modes.png") as stage:
        written.append("model_modes.vtu")
        write_model_modes_vtu(model, stage / "model_modes.vtu", n_modes)
        if seen.truth is not None and seen.truth.modal.nodes_m is not None:
            write_modes_vtu(seen.truth.modal, stage / "truth_modes.vtu", seen.truth.mode_index)
            written.append("truth_modes.vtu")
        if tr is not None:
            anim = f"response.{args.format}"
            animate_response(model, tr, stage / anim, frames=args.frames, fps=args.fps,
                             title=f"{model.n_joints}R PRBDM: {args.response} under "
                                   f"{force.tolist()} N, zeta = {args.damping_ratio}",
                             progress=_tty(args))
            write_trajectory_vtu(model, tr, stage, frames=args.frames)
            written += [anim, "trajectory.pvd", f"trajectory_NNNN.vtu ({args.frames})"]
        plot_mode_shapes(model, n_modes, seen.shapes, path=stage / "modes.png")
        written.insert(0, "modes.png")
    if not args.quiet:
        print(seen.note, file=sys.stderr)
        print(f"wrote {args.out}: {', '.join(written)}", file=sys.stderr)
    if args.meshcat:
        from ..views.meshcat_view import open_meshcat

        viz = open_meshcat(model, tr)
        print(f"meshcat: {viz.viewer.url()}", file=sys.stderr)
    return 0
