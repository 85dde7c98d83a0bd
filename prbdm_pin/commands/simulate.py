"""``prbdm simulate``: time response of a PRBDM (from a fit.json or an exported URDF)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import BeamInputError
from . import add_common
from .truth_comparison import TRUTH_MODELS, compare_truth, comparison_figure, comparison_request

if TYPE_CHECKING:
    import numpy as np

EXAMPLES = """\
examples:
  prbdm simulate runs/ref/fit.json \\
      --duration 1 --tip-force 0,0,-2500 --out runs/ref/sim
  prbdm simulate beam.urdf --duration 0.5 --tip-force 0,0,-100 --damping 0.05 --out sim/
  prbdm simulate runs/ref/fit.json \\
      --duration 1 --tip-force 0,0,-10 --compare-truth --out runs/ref/sim
  prbdm simulate runs/ref/fit.json --duration 0.1 --compare-truth --truth-model beam \\
      --out runs/ref/sim

Writes OUT/trajectory.csv (t, joint angles, joint rates, tip position) and OUT/response.png.
--compare-truth adds OUT/truth_comparison.json and OUT/truth_comparison.png: the tip response to
a unit step tip force over the first second and the tip FRF over [0, 1.2 omega_n] (n = joints)
of the model linearised at the straight pose, against the finite-element truth's modal
superposition at the same modal damping ratio. The truth is the one a fit.json was fitted to
(its model, mode selection and mesh level, found in the cache `prbdm fit` filled), else the
Kirchhoff plate (every plate mode up to the n-th selected bending mode, exact finite-element modal
masses); --truth-model beam asks for the 1D Euler-Bernoulli beam (milliseconds).
"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``simulate`` subparser."""
    p = subparsers.add_parser(
        "simulate",
        help="simulate a PRBDM's response to a tip force (trajectory CSV and plot)",
        description="Integrate the PRBDM's equations of motion through Pinocchio with its "
        "joint springs, modal damping and a step tip force.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("model", metavar="MODEL", help="fit.json, model JSON or URDF")
    p.add_argument("--beam", metavar="BEAM.json",
                   help="the beam a fit.json was fitted to (default: the one it carries)")
    p.add_argument("--duration", type=float, required=True, metavar="S",
                   help="simulated time, s")
    p.add_argument("--tip-force", default="0,0,0", metavar="FX,FY,FZ",
                   help="step tip force in world axes, N (default 0,0,0)")
    p.add_argument("--initial-angle", type=float, default=0.0, metavar="RAD",
                   help="start with every joint at this angle, rad (default 0)")
    p.add_argument("--damping", type=float, default=0.02, metavar="ZETA",
                   help="damping ratio: of every mode (modal), of mode 1 (stiffness), per-joint "
                        "factor (eq5c) (default 0.02)")
    p.add_argument("--damping-form", choices=("modal", "eq5c", "stiffness"), default="modal",
                   help="modal damping (default: every mode gets ZETA), the paper's Eq. 5c, or "
                        "stiffness-proportional C = beta K (mode 1 of the straight pose gets "
                        "ZETA, mode k ZETA omega_k/omega_1: what MJCF/URDF exports carry, so a "
                        "run matches MuJoCo's). Modal and eq5c are computed at the initial pose")
    p.add_argument("--method", default="exponential",
                   help="exponential (default: exact linear modes, step T1/10), gauss "
                        "(symplectic; long undamped runs, violent starts), trapezoidal, or a "
                        "solve_ivp method: DOP853, Radau, BDF ...")
    p.add_argument("--dt", type=float, default=None, metavar="S",
                   help="trapezoidal step, s (default: lowest period / 100)")
    p.add_argument("--output-dt", type=float, default=None, metavar="S",
                   help="sample interval of the CSV, s (default: duration / 2000)")
    p.add_argument("--compare-truth", action="store_true",
                   help="also compare step response and FRF with the truth (needs the beam: "
                        "a fit.json or a model JSON)")
    p.add_argument("--truth-model", default=None, choices=TRUTH_MODELS,
                   help="truth of --compare-truth: plate (finite elements, cached) or beam (1D "
                        "Euler-Bernoulli, milliseconds); default: the truth a fit.json was "
                        "fitted to (its model, mode selection and mesh level), else plate")
    p.add_argument("--cache-dir", default=None, metavar="DIR",
                   help="truth cache folder, shared with `prbdm fit` (default $PRBDM_CACHE or "
                        "~/.cache/prbdm_pin)")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    add_common(p)
    p.set_defaults(func=run)
    return p


def parse_force(text: str) -> np.ndarray:
    """``"FX,FY,FZ"`` -> array (3,) in N; BeamInputError otherwise."""
    import numpy as np

    parts = text.split(",")
    try:
        f = np.array([float(v) for v in parts])
    except ValueError:
        f = np.array([])
    if f.size != 3 or not np.all(np.isfinite(f)):
        raise BeamInputError(f"--tip-force = {text!r}: must be three numbers FX,FY,FZ (N)")
    return f


def load_model(path: str, beam_path: str | None = None):
    """A PrbdmModel from a URDF, a model JSON (export) or a fit.json (with its beam file)."""
    return load_model_and_fit(path, beam_path)[0]


def load_model_and_fit(path: str, beam_path: str | None = None):
    """:func:`load_model`, and the ``FitResult`` when ``path`` is a fit.json (else None)."""
    from ..beam_file import load_beam
    from ..jsonfile import read_json
    from ..model import build_model, load_urdf
    from ..model_files import LINK_FLOOR_FRACTION, file_kind

    p = Path(path)
    if not p.is_file():
        raise BeamInputError(f"MODEL {path!r}: not found")
    if p.suffix.lower() == ".urdf":
        return load_urdf(p), None
    d = read_json(p, "MODEL")
    kind = file_kind(d)
    if kind == "model":
        from ..export import read_model_json

        return read_model_json(p), None
    if kind == "beam":
        raise BeamInputError(f"MODEL {path!r}: is a beam file, not a fit.json or model: run "
                             f"`prbdm fit {path} --joints N --out DIR` first and pass "
                             "DIR/fit.json")
    if kind != "fit":
        what = f"a {kind} file" if kind != "unknown" else (
            f"a JSON object with keys {sorted(d)[:8]}" if isinstance(d, dict)
            else f"a JSON {type(d).__name__}")
        raise BeamInputError(f"MODEL {path!r}: is {what}, not a fit.json, a model JSON "
                             "(prbdm export --format json) or a URDF")
    from ..fit_file import fit_beam
    from ..results import FitResult

    what = f"MODEL {path!r}"
    beam = load_beam(beam_path) if beam_path is not None else fit_beam(d, what)
    if beam is None:
        raise BeamInputError(f"{what}: this fit.json carries no beam; give --beam "
                             "BEAM.json (the beam it was fitted to)")
    fp = d.get("beam_fingerprint")
    if isinstance(fp, str) and fp and fp != beam.fingerprint():
        if beam_path is None:  # the beam stored in the file: the file itself was edited
            raise BeamInputError(f"{what}: its beam does not match its beam_fingerprint = "
                                 f"{fp!r} (the beam stored in it has {beam.fingerprint()!r})")
        raise BeamInputError(f"--beam {beam_path!r}: is not the beam {path!r} was fitted to "
                             f"({d.get('beam_name')!r:.60})")
    fit = FitResult.from_dict(d, beam=beam, what=what)
    model = build_model(beam, fit.lengths_m, fit.stiffness_Nm_per_rad,
                        min_fraction=LINK_FLOOR_FRACTION)
    return model, fit


def _csv(tr) -> str:
    import numpy as np

    n = tr.q_rad.shape[1]
    head = (["t_s"] + [f"q{j + 1}_rad" for j in range(n)] + [f"v{j + 1}_rad_s" for j in range(n)]
            + ["tip_x_m", "tip_y_m", "tip_z_m"])
    rows = np.column_stack([tr.t_s, tr.q_rad, tr.v_rad_s, tr.tip_position_m])
    return ",".join(head) + "\n" + "\n".join(",".join(repr(float(v)) for v in r)
                                             for r in rows) + "\n"


SIMULATE_FILES = ("trajectory.csv", "response.png", "truth_comparison.png",
                  "truth_comparison.json")


# the CSV's default sampling: duration / DEFAULT_SAMPLES
DEFAULT_SAMPLES = 2000


def check_options(args: argparse.Namespace) -> np.ndarray:
    """Refuse bad ``prbdm simulate`` options before the model is read or ``--out`` created;
    returns the tip force (N)."""
    import math

    from ..limits import check_cap
    from ..simulation import FIXED_STEP_METHODS, IVP_METHODS
    from .checks import in_range, writable_dir

    force = parse_force(args.tip_force)
    in_range("--duration", args.duration, 0.0, lo_open=True, unit="s")
    in_range("--initial-angle", args.initial_angle, -math.pi, math.pi, unit="rad")
    # the integrators and the truth comparison take underdamped modes (over-damped runs: an
    # equivalent viscous model is out of the PRBDM's scope)
    in_range("--damping", args.damping, 0.0, 1.0, hi_open=True,
             why="a damping ratio of an underdamped response" if not args.compare_truth else
             "--compare-truth needs an underdamped step response")
    methods = FIXED_STEP_METHODS + IVP_METHODS
    if args.method not in methods:
        raise BeamInputError(f"--method = {args.method!r}: must be one of {', '.join(methods)}")
    for name, dt in (("--dt", args.dt), ("--output-dt", args.output_dt)):
        in_range(name, dt, 0.0, args.duration, lo_open=True, unit="s",
                 why=f"a step within --duration {args.duration:g} s")
    if args.output_dt is not None:
        samples = math.floor(args.duration / args.output_dt + 1e-9) + 1
        check_cap(f"output samples (--duration {args.duration:g} / --output-dt "
                  f"{args.output_dt:g} + 1)", samples, "max_output_samples")
    writable_dir(args.out, "--out")
    if args.compare_truth:
        from .fit_checks import check_cache_dir

        check_cache_dir(args)
    return force


def simulation_options(args, output_dt_s: float):
    """The SimulationOptions of a ``prbdm simulate`` command line (``output_dt_s``: the
    sample interval, s, ``--output-dt`` or its default)."""
    from ..options import SimulationOptions

    return SimulationOptions(method=args.method, dt_s=args.dt, output_dt_s=output_dt_s,
                             damping_ratio=args.damping, damping=args.damping_form)


def run(args: argparse.Namespace) -> int:
    """Run ``prbdm simulate``."""
    import numpy as np

    from ..io import atomic_write_text
    from ..output_folder import output_folder
    from ..plots import save_png
    from ..simulation import simulate

    force = check_options(args)
    model, fitted = load_model_and_fit(args.model, args.beam)
    if args.compare_truth and model.beam is None:
        raise BeamInputError("--compare-truth: needs the beam (give a fit.json or a model JSON; "
                             "a URDF does not carry it)")
    out = Path(args.out)
    output_dt = args.output_dt or args.duration / DEFAULT_SAMPLES
    # the stiffness form's beta from the straight pose, as the MJCF/URDF exports set it; the
    # other forms are exact about the initial pose
    damping_pose = np.zeros(model.n_joints) if args.damping_form == "stiffness" else None
    tr = simulate(model, args.duration, q0=np.full(model.n_joints, args.initial_angle),
                  tip_force=force if np.any(force) else None,
                  options=simulation_options(args, output_dt), damping_pose=damping_pose)
    # every file replaces an earlier simulation's as one set (output_folder)
    with output_folder(out, SIMULATE_FILES, marker="trajectory.csv") as stage:
        atomic_write_text(stage / "trajectory.csv", _csv(tr))

        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
        rest = model.tip_position()
        ax[0].plot(tr.t_s, (tr.tip_position_m[:, 2] - rest[2]) * 1e3, label="z")
        ax[0].plot(tr.t_s, (tr.tip_position_m[:, 0] - rest[0]) * 1e3, label="x")
        ax[0].set_ylabel("tip displacement (mm)")
        ax[0].legend()
        ax[1].plot(tr.t_s, tr.q_rad)
        ax[1].set_xlabel("t (s)")
        ax[1].set_ylabel("joint angles (rad)")
        fig.suptitle(f"{model.n_joints}R PRBDM, F = {force.tolist()} N, zeta = {args.damping}")
        fig.tight_layout()
        save_png(fig, stage / "response.png")
        plt.close(fig)
        if not args.quiet:
            print(f"{tr.steps} steps ({tr.method}) in {tr.wall_time_s:.3f} s for "
                  f"{args.duration} s simulated; wrote {out / 'trajectory.csv'}", file=sys.stderr)

        if args.compare_truth:
            from .fit_checks import cache_dir

            request = comparison_request(model, fitted, args.truth_model, quiet=args.quiet)
            cmp = compare_truth(model, request, args.damping, cache_dir(args),
                                quiet=args.quiet)
            fig = comparison_figure(cmp, plt)
            save_png(fig, stage / "truth_comparison.png")
            plt.close(fig)
            # the JSON last: its presence marks a complete comparison
            atomic_write_text(stage / "truth_comparison.json",
                              json.dumps(cmp.to_dict(Path(args.model).name), indent=2) + "\n")
            if not args.quiet:
                print(f"against the {request.model} truth: step error "
                      f"{100 * cmp.accuracy.step_error:.3g} %, FRF error "
                      f"{100 * cmp.accuracy.frf_error:.3g} %; "
                      f"wrote {out / 'truth_comparison.json'}", file=sys.stderr)
    return 0
