"""Members and calibration: a thickness-tapered panel, a tube boom, E and rho from a ring-down.
=============================================================================================

Three tasks a user of the package meets with members that are not flat strips of one thickness:

1. A panel tapering in width and in thickness (a trapezoid planform, 6 mm thick at the root and
   2 mm at the tip, beam JSON ``"thickness": [0.006, 0.002]``): its truth and a 5R joint-spring
   fit, the error of every mode.
2. A tube boom (``"section": {"kind": "round", "outer_diameter": [...], "inner_diameter":
   [...]}``): its 1D truth against the tube's closed form beta_n L = 1.8751, 4.6941, 7.8548
   with I = pi (D^4 - d^4) / 64, and a 5R fit.
3. Calibration of E, rho and the damping ratios of the first two flexible modes of the panel's
   chain, on a hub of known inertia, from a 10 s ring-down sampled at 250 Hz. The data are made
   by an independent model: the 1D beam truth of the panel with E x 1.05 and rho x 0.97 on the
   same hub (Likins' hybrid coordinates), ratios 0.010 and 0.004, released from rest in a bent
   shape, with 2 % noise. A clamped member's ring-down sees E / rho only; on a hub of known
   inertia the beam's own mass shows, so E and rho come apart. Absolute E and rho need a chain
   whose modal masses are right, not only its frequencies: the 5R eigen fit is calibrated beside
   the 5R fit that also matches the truth's tip amplitudes (``gain_points=("tip",)``).

Full mode: the panel's plate truth for parts 1 and 3's fits, 8 starts. Quick mode
(``--quick``): 1D beam truths, 2 starts. The figure: the ring-down against both calibrated chains.

Run it with::

    python examples/members_and_calibration.py [--quick] [--out results/examples/members]
"""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path

import numpy as np
import scipy.linalg as sla

import prbdm_pin as pp
from prbdm_pin.commands.script_cli import run_example
from prbdm_pin.fitting.calibration_data import ring_down
from prbdm_pin.io.paths import check_out_dir
from prbdm_pin.truth.plant import hybrid_matrices, truth_modal_gains

# sphinx-gallery runs the script without __file__, from the examples folder
ROOT = Path(globals().get("__file__", "members_and_calibration.py")).resolve().parents[1]
S_E, S_RHO, ZETA = 1.05, 0.97, np.array([0.010, 0.004])
HUB = pp.Hub(0.5, 0.05)  # kg m^2, m: twice the panel's own inertia about the hub axis
PARAMETERS = ("E", "rho", "damping[0]", "damping[1]")
BETA_L = np.array([1.875104068711961, 4.694091132974175, 7.854757438237613])


def tapered_panel() -> pp.Beam:
    """Return the panel: half-width 60 to 30 mm, thickness 6 to 2 mm over 1 m, aluminium."""
    return pp.beam_from_dict({
        "name": "tapered-panel", "x": [0.0, 1.0], "half_width": [0.06, 0.03],
        "thickness": [0.006, 0.002],
        "material": {"name": "aluminium 6061", "E": 68.9e9, "rho": 2700.0, "nu": 0.33},
        "tip_force": [0.0, 0.0, -20.0]})


def tube_boom() -> pp.Beam:
    """Return the boom: a 1.5 m aluminium tube, 40 mm outer and 36 mm inner diameter."""
    return pp.beam_from_dict({
        "name": "tube-boom", "x": [0.0, 1.5],
        "section": {"kind": "round", "outer_diameter": [0.04, 0.04],
                    "inner_diameter": [0.036, 0.036]},
        "material": {"name": "aluminium 6061", "E": 68.9e9, "rho": 2700.0, "nu": 0.33},
        "tip_force": [0.0, 0.0, -50.0]})


def _fit(beam, truth, starts, gains=False):
    target = pp.target_from_truth(truth, beam.tip_force_N)
    if gains:  # the truth's tip amplitudes beside its frequencies
        from prbdm_pin.fitting.spatial_gains import with_point_gains

        target = with_point_gains(target, truth, beam)
    return pp.fit(beam, target, 5, stiffness="joint", objective="eigen", starts=starts,
                  gain_points=("tip",) if gains else (), progress=False)


def _errors(result) -> str:
    return " ".join(f"{e:+.2e}" for e in np.asarray(result.omega_errors_pct).ravel())


def hub_ring_down(beam: pp.Beam, t_s: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Tip z and hub angle of the scaled 1D truth on the hub, released bent from rest, noisy."""
    mat = dataclasses.replace(beam.material, E_Pa=beam.material.E_Pa * S_E,
                              rho_kg_m3=beam.material.rho_kg_m3 * S_RHO)
    scaled = dataclasses.replace(beam, material=mat)
    truth = pp.compute_truth(scaled, model="beam", modes=8, static=False)
    M, K, _, Cq = hybrid_matrices(truth_modal_gains(truth, scaled), HUB.inertia_kg_m2,
                                  HUB.radius_m)
    lam, Phi = sla.eigh(K, M)  # the hub's rigid rotation first (lambda = 0)
    q0 = np.zeros(M.shape[0])
    q0[1], q0[2] = 0.02, 0.004  # clamped-mode coordinates: a bent shape, at rest
    eta0 = Phi.T @ M @ q0
    Q = np.outer(np.full(t_s.size, eta0[0]), Phi[:, 0])
    for k, z in enumerate(ZETA, start=1):  # each flexible mode rings with its own ratio
        w = np.sqrt(lam[k])
        wd = w * np.sqrt(1.0 - z**2)
        ring = np.exp(-z * w * t_s) * (np.cos(wd * t_s) + z * w / wd * np.sin(wd * t_s))
        Q += np.outer(eta0[k] * ring, Phi[:, k])
    y = Q @ Cq.T
    return y + 0.02 * np.abs(y).max(axis=0) * rng.standard_normal(y.shape)


def main(quick: bool = False, out: Path = ROOT / "results" / "examples" / "members") -> dict:
    """Fit the panel and the boom, calibrate the panel's chains; returns what the tests check."""
    out = check_out_dir("out", out)  # refused before any work, as --out
    out.mkdir(parents=True, exist_ok=True)
    model, starts = ("beam", 2) if quick else ("plate", 8)

    panel = tapered_panel()
    truth = pp.compute_truth(panel, model=model, modes=5, static=False,
                             cache_dir=out / "cache")
    eigen_fit = _fit(panel, truth, starts)
    print(f"1. {panel.name} ({model} truth), 5R joint springs, errors per mode (%): "
          f"{_errors(eigen_fit)}")

    boom = tube_boom()
    boom_truth = pp.compute_truth(boom, model="beam", modes=5, static=False)
    sec = pp.section_properties(boom, np.array([0.0]))
    closed = (BETA_L / boom.length_m) ** 2 * np.sqrt(sec.EI_y_Nm2[0] / sec.rhoA_kg_m[0])
    truth_err = 100 * (np.asarray(boom_truth.omega_rad_s[:3]) / closed - 1)
    boom_fit = _fit(boom, boom_truth, starts)
    print(f"2. {boom.name}: 1D truth against beta_n L (%): "
          + " ".join(f"{e:+.1e}" for e in truth_err)
          + f"; 5R errors per mode (%): {_errors(boom_fit)}")

    # part 3 on the 1D truth's chain in both modes: the data are the 1D truth's
    beam_truth = truth if quick else pp.compute_truth(panel, model="beam", modes=5,
                                                      static=False)
    chains = {"5R eigen fit": eigen_fit if quick else _fit(panel, beam_truth, starts),
              "5R eigen + tip amplitudes": _fit(panel, beam_truth, starts, gains=True)}
    t = np.arange(2500) / 250.0
    y = hub_ring_down(panel, t, np.random.default_rng(7))
    data = ring_down(t, y, ["tip_z", "hub_angle"])
    want = np.r_[panel.material.E_Pa * S_E, panel.material.rho_kg_m3 * S_RHO, ZETA]
    calibrated = {}
    for name, fit in chains.items():
        # light on purpose, so that the beam's mass shows beside the hub's: the warning that
        # a clamped fit errs on a light hub is what this part measures
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", pp.LightHubWarning)
            chain = pp.build_model(panel, fit.lengths_m, fit.stiffness_Nm_per_rad, hub=HUB)
            res = pp.calibrate(chain, data, PARAMETERS)
        calibrated[name] = res
        print(f"3. {name}: " + ", ".join(
            f"{p} {v:.5g} +/- {s:.2g} (truth {w:.5g})"
            for p, v, s, w in zip(PARAMETERS, res.values, res.std_errors, want, strict=True)))
    figure = out / "members_and_calibration.png"
    _plot(t, y, calibrated, figure)
    return {"panel": panel, "truth": truth, "eigen_fit": eigen_fit, "boom": boom,
            "boom_truth": boom_truth, "boom_closed_form_rad_s": closed, "boom_fit": boom_fit,
            "calibrated": calibrated, "want": want, "figure": figure}


def _plot(t, y, calibrated, path: Path) -> Path:
    from prbdm_pin.views.plots import new_figure, save_figure

    fig = new_figure((7.5, 5.0))
    for j, (label, unit) in enumerate((("tip z", "m"), ("hub angle", "rad"))):
        ax = fig.add_subplot(2, 1, j + 1)
        ax.plot(t, y[:, j], ".", ms=1.5, color="0.6", label="data (1D truth on the hub, 2 % noise)")
        for (name, res), style in zip(calibrated.items(), ("--", "-"), strict=True):
            ax.plot(t, res.fitted[:, j], style, lw=0.8, label=f"calibrated {name}")
        ax.set_xlim(0.0, 2.0)
        ax.set_ylabel(f"{label} ({unit})")
        if j == 0:
            ax.legend(loc="upper right", fontsize=7)
    ax.set_xlabel("time (s)")
    fig.suptitle("ring-down on a hub of known inertia: E, rho and two damping ratios")
    return save_figure(fig, path)


if __name__ == "__main__":
    # no SystemExit on success: sphinx-gallery runs this block in the build's process
    if code := run_example(__doc__, ROOT / "results" / "examples" / "members", main):
        raise SystemExit(code)
