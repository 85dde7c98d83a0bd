"""Gradient-based co-design with the PRBDM in the loop: minimum panel mass with a first
frequency floor and a large-deflection tip limit, read from the model.

The design problem (defaults: the tapered steel panel of examples/beams/tapered.json):

    minimise    m(p)                     panel mass, p = (thickness, root and tip half-widths)
    subject to  omega_1(p) >= omega_min  the PRBDM's first natural frequency
                delta(p)   <= delta_max  |z| of the PRBDM's large-deflection tip under the
                                         beam's tip force (geometrically nonlinear statics)
                p in a box               sheet thickness and half-widths a workshop can make

Each design goes truth -> fit -> model (``prbdm_pin.fitting.codesign.codesign_point``): the truth's
frequencies (1D Euler-Bernoulli beam by default: fast; ``--truth plate`` for the Kirchhoff
plate), the ``unique="nearest"`` 3R fit that matches them exactly (one smooth model per design)
and the PRBDM's frequencies and large-deflection tip. SLSQP uses the chained gradients; COBYLA
solves the same problem on the same model without them. Every new design costs one truth
evaluation (for SLSQP: the truth solve with its design gradient). The optimum of each is then
checked against the truth itself: the 1D beam's frequencies and its large-deflection (elastica)
tip, and the plate's, at the optimum.

    python scripts/codesign_gradient.py [--out results/codesign_gradient] [--truth beam]
        [--omega-min 160] [--delta-max 0.08] [--maxiter 60]

Writes codesign_gradient.md (the table), convergence.png (objective and constraint violation
of both optimisers against truth evaluations) and history.json, and prints the table.
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import dataclasses  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from scipy.optimize import minimize  # noqa: E402

import prbdm_pin as pp  # noqa: E402
from prbdm_pin.fitting.codesign import CodesignPoint, codesign_point  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the scripts' shared helpers
from docs_tables import write_table  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
BEAM = ROOT / "examples" / "beams" / "tapered.json"
VERTICES = 4  # planform vertices, equally spaced: their half-widths are design variables
THICKNESS_RANGE_M = (0.003, 0.006)  # sheet stock
HALF_WIDTH_RANGE_M = (0.010, 0.060)
OMEGA_MIN = 160.0  # rad/s (25.5 Hz)
DELTA_MAX = 0.08  # m
JOINTS = 3
FEAS_TOL = 1e-6  # relative constraint violation counted as feasible
# the model's outputs carry the fit's convergence noise (about 1e-8 relative on the tip): an
# SLSQP tolerance below it never stops (it keeps re-solving its subproblem at the optimum)
FTOL = 1e-7
RHOEND = 1e-6  # COBYLA's final trust-region radius (scaled variables)
REACH_REL = 1e-5  # "reached the optimum": feasible and mass within this of the best found


def planform(beam: pp.Beam, vertices: int) -> pp.Beam:
    """``beam`` with its outline through ``vertices`` equally spaced vertices (the same outline
    when it is straight between them): each half-width a design variable of its own."""
    x = np.linspace(0.0, beam.length_m, vertices)
    w = beam.half_width_at(x)
    return dataclasses.replace(beam, x_m=x, half_width_m=w)


def variables_of(beam: pp.Beam) -> tuple[str, ...]:
    """Thickness and every half-width."""
    return ("thickness",) + tuple(f"half_width[{i}]" for i in range(beam.x_m.size))


@dataclass(frozen=True)
class CodesignProblem:
    """The design problem: thickness and half-widths in their box, the two model constraints
    and the model (nR, the truth in the loop)."""

    beam: pp.Beam
    omega_min_rad_s: float = OMEGA_MIN
    delta_max_m: float = DELTA_MAX
    joints: int = JOINTS
    truth_model: str = "beam"
    thickness_range_m: tuple[float, float] = THICKNESS_RANGE_M
    half_width_range_m: tuple[float, float] = HALF_WIDTH_RANGE_M

    @property
    def variables(self) -> tuple[str, ...]:
        return variables_of(self.beam)

    @property
    def design(self) -> pp.Design:
        return pp.Design(self.beam, self.variables)

    @property
    def lower(self) -> np.ndarray:
        return np.r_[self.thickness_range_m[0],
                     np.full(self.beam.x_m.size, self.half_width_range_m[0])]

    @property
    def upper(self) -> np.ndarray:
        return np.r_[self.thickness_range_m[1],
                     np.full(self.beam.x_m.size, self.half_width_range_m[1])]

    @property
    def start(self) -> np.ndarray:
        """The start design (the beam's), SI units."""
        return np.array(self.design.values)


@dataclass
class Record:
    """One truth evaluation: the design and what the model read there."""

    truth_evals: int
    p: list[float]
    mass_kg: float
    omega_1_rad_s: float
    delta_m: float
    violation: float


class Evaluator:
    """The chain at scaled designs y = p / p_start, cached per design; counts truth evaluations
    and records each one (the optimisers' history)."""

    def __init__(self, problem: CodesignProblem, gradient: bool):
        self.problem = problem
        self.design = problem.design
        self.scale = problem.start
        self.gradient = gradient
        self.cache: dict[bytes, CodesignPoint] = {}
        self.history: list[Record] = []

    def point(self, y: np.ndarray) -> CodesignPoint:
        y = np.asarray(y, dtype=float)
        key = y.tobytes()
        if key not in self.cache:
            pr = self.problem
            p = np.clip(y * self.scale, pr.lower, pr.upper)  # the solvers may step onto a bound
            c = codesign_point(self.design, p, pr.joints, truth_model=pr.truth_model,
                               gradient=self.gradient)
            self.cache[key] = c
            g = constraints_of(pr, c)
            self.history.append(Record(len(self.history) + 1, p.tolist(), c.mass_kg,
                                       float(c.omega_rad_s[0]), c.tip_deflection_m,
                                       float(max(0.0, -g.min()))))
        return self.cache[key]

    # scaled objective and constraints (g >= 0 feasible), as scipy takes them
    def objective(self, y):
        return self.point(y).mass_kg / self.mass0

    def objective_jac(self, y):
        return self.point(y).d_mass_kg * self.scale / self.mass0

    def constraints(self, y):
        return constraints_of(self.problem, self.point(y))

    def constraints_jac(self, y):
        c, pr = self.point(y), self.problem
        return np.vstack([c.d_omega_rad_s[0] / pr.omega_min_rad_s,
                          -c.d_tip_deflection_m / pr.delta_max_m]) * self.scale

    @property
    def mass0(self) -> float:
        return float(self.problem.beam.mass_kg)


def constraints_of(problem: CodesignProblem, c: CodesignPoint) -> np.ndarray:
    """[omega_1 / omega_min - 1, 1 - delta / delta_max]: relative margins, >= 0 feasible."""
    return np.array([c.omega_rad_s[0] / problem.omega_min_rad_s - 1.0,
                     1.0 - c.tip_deflection_m / problem.delta_max_m])


def _bounds(problem: CodesignProblem) -> list[tuple[float, float]]:
    s = problem.start
    return list(zip(problem.lower / s, problem.upper / s, strict=True))


def run_slsqp(problem: CodesignProblem, maxiter: int = 60) -> tuple[Evaluator, object, float]:
    """SLSQP on the chained gradients; (evaluator, scipy result, wall time s)."""
    ev = Evaluator(problem, gradient=True)
    t0 = time.perf_counter()
    res = minimize(ev.objective, np.ones(len(problem.variables)), jac=ev.objective_jac,
                   method="SLSQP", bounds=_bounds(problem),
                   constraints=[{"type": "ineq", "fun": ev.constraints,
                                 "jac": ev.constraints_jac}],
                   options={"maxiter": maxiter, "ftol": FTOL})
    return ev, res, time.perf_counter() - t0


def run_cobyla(problem: CodesignProblem, maxiter: int = 300) -> tuple[Evaluator, object, float]:
    """COBYLA (derivative-free) on the same model; (evaluator, scipy result, wall time s)."""
    ev = Evaluator(problem, gradient=False)
    t0 = time.perf_counter()
    res = minimize(ev.objective, np.ones(len(problem.variables)), method="COBYLA",
                   bounds=_bounds(problem),
                   constraints=[{"type": "ineq", "fun": ev.constraints}],
                   options={"maxiter": maxiter, "rhobeg": 0.1, "tol": RHOEND})
    return ev, res, time.perf_counter() - t0


@dataclass(frozen=True)
class TruthCheck:
    """The truth itself at a design: first frequency and large-deflection tip |z|."""

    model: str
    omega_1_rad_s: float
    delta_m: float


def truth_check(problem: CodesignProblem, p: np.ndarray, model: str) -> TruthCheck:
    """``compute_truth`` at ``p``: its first bending frequency and its large-deflection tip
    (elastica for the 1D beam) under the beam's tip force."""
    beam = problem.design.beam_at(p)
    tr = pp.compute_truth(beam, model=model, modes=problem.joints, static=True,
                          error_tol_pct=None)
    tgt = pp.target_from_truth(tr, beam.tip_force_N)
    return TruthCheck(model, float(tgt.omega_truth_rad_s[0]),
                      abs(float(tgt.tip_displacement_m[2])))


def best_feasible(ev: Evaluator) -> Record | None:
    ok = [r for r in ev.history if r.violation <= FEAS_TOL]
    return min(ok, key=lambda r: r.mass_kg) if ok else None


def evaluations_to_reach(ev: Evaluator, best_mass_kg: float) -> int | None:
    """Truth evaluations until the first feasible design within REACH_REL of the best mass."""
    for r in ev.history:
        if r.violation <= FEAS_TOL and r.mass_kg <= best_mass_kg * (1.0 + REACH_REL):
            return r.truth_evals
    return None


def table(problem: CodesignProblem, runs: dict, checks: dict) -> str:
    """The markdown table: per optimiser, cost, optimum and its truth check."""
    best = min((r.mass_kg for ev, _, _ in runs.values() for r in ev.history
                if r.violation <= FEAS_TOL), default=np.inf)
    head = ("| optimiser | truth evaluations (to reach the optimum) | wall time (s) | t (mm) | "
            "half-widths root to tip (mm) | mass (kg) | PRBDM omega_1 (rad/s) | PRBDM delta (mm) "
            "| truth | truth omega_1 (rad/s) | truth delta (mm) | PRBDM error omega_1 / delta "
            "(%) |")
    lines = [head, "|" + "---|" * 12]
    for name, (ev, res, wall) in runs.items():
        c = ev.point(res.x)
        p = c.values
        widths = ", ".join(f"{1e3 * w:.2f}" for w in p[1:])
        for k, chk in enumerate(checks[name]):
            e_w = 100.0 * (c.omega_rad_s[0] / chk.omega_1_rad_s - 1.0)
            e_d = 100.0 * (c.tip_deflection_m / chk.delta_m - 1.0)
            lead = (f"| {name} | {len(ev.history)} ({evaluations_to_reach(ev, best)}) | "
                    f"{wall:.1f} | {1e3 * p[0]:.4f} | {widths} | "
                    f"{c.mass_kg:.5f} | {c.omega_rad_s[0]:.3f} | "
                    f"{1e3 * c.tip_deflection_m:.3f} |" if k == 0 else "| | | | | | | | |")
            lines.append(f"{lead} {chk.model} | {chk.omega_1_rad_s:.3f} | "
                         f"{1e3 * chk.delta_m:.3f} | {e_w:+.2g} / {e_d:+.3g} |")
    lines.append("")
    lines.append(f"Constraints: omega_1 >= {problem.omega_min_rad_s:g} rad/s, delta <= "
                 f"{1e3 * problem.delta_max_m:g} mm, both of the PRBDM ({problem.joints}R, "
                 f"unique='nearest' fit to the {problem.truth_model} truth's frequencies); "
                 f"thickness {1e3 * problem.thickness_range_m[0]:g} to "
                 f"{1e3 * problem.thickness_range_m[1]:g} mm, half-widths "
                 f"{1e3 * problem.half_width_range_m[0]:g} to "
                 f"{1e3 * problem.half_width_range_m[1]:g} mm at {problem.beam.x_m.size} "
                 f"equally spaced stations; start mass {problem.beam.mass_kg:.4f} kg. "
                 f"Reaching the optimum: the first design with a relative violation <= "
                 f"{FEAS_TOL:g} and a mass within {REACH_REL:g} of the best found by either.")
    return "\n".join(lines)


def convergence_figure(runs: dict, path: Path) -> None:
    """Objective and constraint violation against truth evaluations, both optimisers."""
    from prbdm_pin.views.plots import new_figure, save_png

    fig = new_figure((9.0, 3.6))
    ax1, ax2 = fig.add_subplot(121), fig.add_subplot(122)
    for name, (ev, _, _) in runs.items():
        n = [r.truth_evals for r in ev.history]
        ax1.plot(n, [r.mass_kg for r in ev.history], ".-", ms=3, lw=0.8, label=name)
        ax2.semilogy(n, [max(r.violation, 1e-12) for r in ev.history], ".-", ms=3, lw=0.8,
                     label=name)
    ax1.set_xlabel("truth evaluations")
    ax1.set_ylabel("panel mass (kg)")
    ax2.set_xlabel("truth evaluations")
    ax2.set_ylabel("max relative constraint violation")
    ax2.set_title("feasible designs drawn at 1e-12", fontsize=9)
    for ax in (ax1, ax2):
        ax.grid(True, lw=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    save_png(fig, path)


def solve(problem: CodesignProblem, maxiter: int = 60, cobyla_maxiter: int = 300,
          checks: tuple[str, ...] = ("beam", "plate")):
    """Both optimisers and the truth checks at their optima."""
    runs = {"SLSQP (chained gradients)": run_slsqp(problem, maxiter),
            "COBYLA (derivative-free)": run_cobyla(problem, cobyla_maxiter)}
    found = {name: [truth_check(problem, ev.point(res.x).values, m) for m in checks]
             for name, (ev, res, _) in runs.items()}
    return runs, found


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=str(ROOT / "results" / "codesign_gradient"))
    ap.add_argument("--beam", default=str(BEAM), help="beam JSON (its outline is resampled)")
    ap.add_argument("--vertices", type=int, default=VERTICES,
                    help="planform vertices, equally spaced (each half-width a variable)")
    ap.add_argument("--truth", default="beam", choices=["beam", "plate"],
                    help="truth in the loop: 1D beam (default, fast) or plate")
    ap.add_argument("--omega-min", type=float, default=OMEGA_MIN, help="rad/s")
    ap.add_argument("--delta-max", type=float, default=DELTA_MAX, help="m")
    ap.add_argument("--joints", type=int, default=JOINTS)
    ap.add_argument("--maxiter", type=int, default=60, help="SLSQP iterations")
    ap.add_argument("--cobyla-maxiter", type=int, default=300, help="COBYLA evaluations")
    args = ap.parse_args(argv)
    problem = CodesignProblem(planform(pp.load_beam(args.beam), args.vertices),
                              omega_min_rad_s=args.omega_min,
                              delta_max_m=args.delta_max, joints=args.joints,
                              truth_model=args.truth)
    runs, checks = solve(problem, args.maxiter, args.cobyla_maxiter)
    text = table(problem, runs, checks)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_table(out / "codesign_gradient.md", "# Gradient-based co-design\n\n" + text + "\n",
                Path(ap.get_default("out")) / "codesign_gradient.md",
                "codesign_gradient" if args.truth == "beam" else f"codesign_gradient_{args.truth}")
    convergence_figure(runs, out / "convergence.png")
    hist = {name: {"success": bool(res.success), "message": str(res.message),
                   "wall_time_s": wall, "history": [r.__dict__ for r in ev.history]}
            for name, (ev, res, wall) in runs.items()}
    atomic_write_text(out / "history.json", json.dumps(hist, indent=1) + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
