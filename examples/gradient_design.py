"""Gradient-based design with the PRBDM in the loop: the lightest panel that is stiff enough.
==========================================================================================

The problem::

    minimise    m(p)                    panel mass; p = thickness, root and tip half-widths
    subject to  omega_1(p) >= 130 rad/s the PRBDM's first natural frequency
                delta(p) <= 90 mm       |z| of the PRBDM's large-deflection tip under the load
                p in a box              3-6 mm sheet, half-widths 10-60 mm

Each design goes truth -> fit -> model (``prbdm_pin.codesign_point``): the 1D beam truth's
frequencies with their design gradient (``truth_gradient``), the ``unique="nearest"`` 3R fit
that matches them (one smooth model per design) and the PRBDM's frequencies and
large-deflection tip, each with its gradient chained through all three. SLSQP takes those
gradients. The optimum is then checked against the truth itself. The fuller study (more
half-widths, COBYLA for comparison, the plate in the loop) is ``scripts/codesign_gradient.py``.

Full mode: as quick, plus the plate truth at the optimum and the figure.
Quick mode (``--quick``): the optimisation and the 1D beam truth's check.

Run it with::

    python examples/gradient_design.py [--quick] [--out results/examples/gradient_design]
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.optimize import minimize

import prbdm_pin as pp
from prbdm_pin.commands.script_cli import run_example
from prbdm_pin.io.paths import check_out_dir
from prbdm_pin.views.plots import new_figure, save_png

# sphinx-gallery runs the script without __file__, from the examples folder
ROOT = Path(globals().get("__file__", "gradient_design.py")).resolve().parents[1]
OMEGA_MIN = 130.0  # rad/s
DELTA_MAX = 0.09  # m
LOWER = np.array([0.003, 0.010, 0.010])  # thickness, root and tip half-width, m
UPPER = np.array([0.006, 0.060, 0.060])


class Chain:
    """truth -> fit -> PRBDM at scaled designs y = p / p_start, one evaluation per design."""

    def __init__(self, design: pp.Design):
        self.design, self.scale = design, np.array(design.values)
        self.points: dict[bytes, pp.CodesignPoint] = {}
        self.history: list[tuple[float, float, float]] = []  # mass, omega_1, delta

    def point(self, y: np.ndarray) -> pp.CodesignPoint:
        """Return the chain's point at y (one truth, fit and model per new design)."""
        key = np.asarray(y, dtype=float).tobytes()
        if key not in self.points:
            p = np.clip(y * self.scale, LOWER, UPPER)  # SLSQP may step a rounding past a bound
            c = pp.codesign_point(self.design, p, joints=3, truth_model="beam")
            self.points[key] = c
            self.history.append((c.mass_kg, float(c.omega_rad_s[0]), c.tip_deflection_m))
        return self.points[key]

    # mass and relative constraint margins (>= 0 feasible) with their gradients in y
    def mass(self, y):
        """Return the panel mass (kg)."""
        return self.point(y).mass_kg

    def mass_jac(self, y):
        """Return the mass gradient in y (kg)."""
        return self.point(y).d_mass_kg * self.scale

    def margins(self, y):
        """Return the relative constraint margins (>= 0 feasible)."""
        c = self.point(y)
        return np.array([c.omega_rad_s[0] / OMEGA_MIN - 1.0,
                         1.0 - c.tip_deflection_m / DELTA_MAX])

    def margins_jac(self, y):
        """Return the margins' gradients in y."""
        c = self.point(y)
        return np.vstack([c.d_omega_rad_s[0] / OMEGA_MIN,
                          -c.d_tip_deflection_m / DELTA_MAX]) * self.scale


def truth_at(beam: pp.Beam, model: str) -> tuple[float, float]:
    """Return the truth's first frequency (rad/s) and large-deflection tip ``|z|`` (m)."""
    truth = pp.compute_truth(beam, model=model, modes=3)
    target = pp.target_from_truth(truth, beam.tip_force_N)
    return float(target.omega_truth_rad_s[0]), abs(float(target.tip_displacement_m[2]))


def main(quick: bool = False,
         out: Path = ROOT / "results" / "examples" / "gradient_design") -> dict:
    """Optimise; returns the optimum (SI units), the PRBDM's and the truths' values there."""
    out = check_out_dir("out", out)  # refused before any work, as --out
    out.mkdir(parents=True, exist_ok=True)
    beam = pp.load_beam(ROOT / "examples" / "beams" / "tapered.json")
    design = pp.Design(beam, ("thickness", "half_width[0]", "half_width[1]"))
    chain = Chain(design)
    res = minimize(chain.mass, np.ones(3), jac=chain.mass_jac, method="SLSQP",
                   bounds=list(zip(LOWER / chain.scale, UPPER / chain.scale, strict=True)),
                   constraints=[{"type": "ineq", "fun": chain.margins,
                                 "jac": chain.margins_jac}],
                   options={"maxiter": 60, "ftol": 1e-7})
    best = chain.point(res.x)
    p = np.asarray(best.values)
    print(f"SLSQP: {res.message} after {len(chain.history)} truth evaluations; "
          f"t = {1e3 * p[0]:.3f} mm, half-widths {1e3 * p[1]:.2f} -> {1e3 * p[2]:.2f} mm, "
          f"mass {best.mass_kg:.4f} kg (start {beam.mass_kg:.4f} kg)")
    print(f"  PRBDM: omega_1 {best.omega_rad_s[0]:.3f} rad/s, tip {1e3 * best.tip_deflection_m:.2f}"
          f" mm")
    checks = {m: truth_at(design.beam_at(p), m) for m in (("beam",) if quick else
                                                            ("beam", "plate"))}
    for m, (w, d) in checks.items():
        print(f"  {m} truth: omega_1 {w:.3f} rad/s, tip {1e3 * d:.2f} mm")

    h = np.array(chain.history)
    fig = new_figure((9.0, 3.2))
    ax = fig.subplots(1, 3)
    n = np.arange(1, h.shape[0] + 1)
    for a, col, limit, label in ((ax[0], 0, None, "panel mass (kg)"),
                                 (ax[1], 1, OMEGA_MIN, "PRBDM omega_1 (rad/s)"),
                                 (ax[2], 2, DELTA_MAX, "PRBDM tip |z| (m)")):
        a.plot(n, h[:, col], ".-")
        if limit is not None:
            a.axhline(limit, color="k", ls=":", lw=1)
        a.set(xlabel="truth evaluations", ylabel=label)
    ax[1].set_title("SLSQP on the chained gradients", fontsize=9)
    fig.tight_layout()
    figure = save_png(fig, out / "gradient_design.png")
    return {"result": res, "optimum": p, "point": best, "design": design, "checks": checks,
            "evaluations": len(chain.history), "figure": figure}


if __name__ == "__main__":
    # no SystemExit on success: sphinx-gallery runs this block in the build's process
    if code := run_example(__doc__, ROOT / "results" / "examples" / "gradient_design",
                           main, "no plate check, seconds"):
        raise SystemExit(code)
