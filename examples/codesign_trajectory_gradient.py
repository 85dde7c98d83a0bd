"""Co-design by trajectory gradients: a strain patch's feedback gain and the panel's stiffness.
============================================================================================

A panel bent at the end of a manoeuvre (its static pose under a 5 N tip load) is released and
must settle. A strain patch at the root (0-0.35 m) feeds back the joint angles and rates of the
3R PRBDM, u = -G x, and the panel's modulus is a design choice too: every spring scales with
it, k = s k_0, at the same mass (a stiffer material), for a price; a softer panel also starts
more bent. The problem::

    minimise    F(G, s) = J(G, s) + w_s s
    J           = integral over [0, T] of (w_z z^2 + r u^2) dt   tip height z, patch moment u
    bounds      |G_q| <= 200 N m/rad, |G_v| <= 20 N m s/rad, 0.5 <= s <= 3

L-BFGS-B takes F's gradient from :func:`prbdm_pin.trajectory_gradient`: dJ/dG, dJ/dk and
dJ/dq0 by forward sensitivities stepped with the run (fixed-step RK4), one run per evaluation,
where central differences would take 2 x 7 runs. The modulus enters twice, dJ/ds = k_0 . dJ/dk
+ dJ/dq0 . dq0/ds, the start pose's derivative from :func:`prbdm_pin.model_gradient`.

Full mode: 1 s of settling, up to 30 iterations. Quick mode (``--quick``): 0.15 s, up to 6
iterations. Both print the cost at each evaluation and the final design, and draw the cost's
fall and the tip's settling before and after.

Run it with::

    python examples/codesign_trajectory_gradient.py [--quick] [--out DIR]
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
ROOT = Path(globals().get("__file__", "codesign_trajectory_gradient.py")).resolve().parents[1]
BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.03, 0.02], thickness_m=0.01)
LENGTHS = np.array([0.2, 0.3, 0.3, 0.2])  # m
PATCH = pp.StrainActuator(x_start_m=0.0, x_end_m=0.35)
LOAD_N = np.array([0.0, 0.0, -5.0])  # the load the panel is bent by at the start
COST = pp.QuadraticCost(tip_weight_per_m2=1e4, effort_weight=1e-2)  # per m^2, per (N m)^2
W_S = 1e-3  # the stiffness's price, cost units per unit of s
BETA_S = 1e-4  # s: the panel's own light damping, C = beta K
SCALE = np.array([100.0] * 3 + [5.0] * 3 + [1.0])  # y = (G_q, G_v, s) / SCALE
LOWER = np.array([-200.0] * 3 + [-20.0] * 3 + [0.5]) / SCALE
UPPER = np.array([200.0] * 3 + [20.0] * 3 + [3.0]) / SCALE


class Problem:
    """F(y) and its gradient, one trajectory gradient per new design (cached)."""

    def __init__(self, duration_s: float):
        self.T = duration_s
        self.k0 = pp.finite_segment_stiffness(BEAM, LENGTHS)  # N m/rad
        self.history: list[float] = []
        self._last: tuple[bytes, float, np.ndarray] | None = None

    def start(self, s: float) -> tuple[np.ndarray, np.ndarray]:
        """Return the bent start q0 (rad), the static pose under the load, and dq0/ds."""
        g = pp.model_gradient(BEAM, LENGTHS, s * self.k0, tip_force_N=LOAD_N)
        n = LENGTHS.size - 1
        return g.static_pose_rad, g.d_static_pose_rad[:, n:] @ self.k0  # springs' columns

    def run(self, y: np.ndarray) -> tuple[pp.TrajectoryGradient, np.ndarray]:
        """Return the trajectory gradient of the design y (scaled), and dq0/ds."""
        p = np.asarray(y, dtype=float) * SCALE
        model = pp.build_model(BEAM, LENGTHS, p[6] * self.k0)
        q0, dq0 = self.start(p[6])
        return pp.trajectory_gradient(model, self.T, COST, q0=q0, inputs=("strain[0]",),
                                      actuators=(PATCH,), feedback=pp.StateFeedback(p[None, :6]),
                                      beta_s=BETA_S, parameters=("springs", "gain", "initial"),
                                      steps_per_period=20.0), dq0

    def __call__(self, y: np.ndarray) -> tuple[float, np.ndarray]:
        """Return F(y) and dF/dy."""
        key = np.asarray(y, dtype=float).tobytes()
        if self._last is None or self._last[0] != key:
            g, dq0 = self.run(y)
            n = dq0.size
            f = g.cost + W_S * float(y[6] * SCALE[6])
            # s moves the springs and, through the static pose, the start
            dJ_ds = self.k0 @ g.gradient[:n] + g.gradient[-2 * n:-n] @ dq0
            dF = np.concatenate((g.gradient[n:-2 * n], [dJ_ds + W_S])) * SCALE
            self.history.append(f)
            print(f"  evaluation {len(self.history):2d}: F = {f:.6f} (J = {g.cost:.6f})")
            self._last = (key, f, dF)
        return self._last[1], self._last[2]


def main(quick: bool = False,
         out: Path = ROOT / "results" / "examples" / "codesign_trajectory_gradient") -> dict:
    """Optimise; returns the start and final designs, costs and runs (SI units)."""
    out = check_out_dir("out", out)  # refused before any work, as --out
    out.mkdir(parents=True, exist_ok=True)
    problem = Problem(0.15 if quick else 1.0)
    y0 = np.zeros(7)
    y0[6] = 1.0  # no feedback, the nominal modulus
    res = minimize(problem, y0, jac=True, method="L-BFGS-B",
                   bounds=list(zip(LOWER, UPPER, strict=True)),
                   options={"maxiter": 6 if quick else 30})
    start, final = problem.run(y0)[0], problem.run(res.x)[0]
    p = res.x * SCALE
    print(f"L-BFGS-B: {res.message} after {len(problem.history)} evaluations")
    print(f"  F {problem.history[0]:.6f} -> {res.fun:.6f}; J {start.cost:.6f} -> "
          f"{final.cost:.6f}")
    print(f"  G_q = {np.round(p[:3], 2).tolist()} N m/rad, G_v = {np.round(p[3:6], 3).tolist()} "
          f"N m s/rad, stiffness scale s = {p[6]:.3f}")

    fig = new_figure((9.0, 3.2))
    ax = fig.subplots(1, 2)
    ax[0].plot(np.arange(1, len(problem.history) + 1), problem.history, ".-")
    ax[0].set(xlabel="evaluations (runs with their gradient)", ylabel="F = J + w_s s",
              title="L-BFGS-B on the trajectory gradient")
    for run, label in ((start.trajectory, "start: no feedback, s = 1"),
                       (final.trajectory, f"final: s = {p[6]:.2f}")):
        ax[1].plot(run.t_s, 1e3 * run.tip_position_m[:, 2], label=label)
    ax[1].set(xlabel="time (s)", ylabel="tip height z (mm)", title="release and settling")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    figure = save_png(fig, out / "codesign_trajectory_gradient.png")
    return {"result": res, "start": start, "final": final, "design": p,
            "history": problem.history, "problem": problem, "figure": figure}


if __name__ == "__main__":
    # no SystemExit on success: sphinx-gallery runs this block in the build's process
    if code := run_example(__doc__, ROOT / "results" / "examples" / "codesign_trajectory_gradient",
                           main, "0.15 s of settling, 6 iterations"):
        raise SystemExit(code)
