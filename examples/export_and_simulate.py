"""Export a fitted PRBDM as URDF and MJCF and run it in Pinocchio and MuJoCo.
==========================================================================

The model is fitted (joint springs), bent by the beam's tip force (large-deflection statics)
and released. The same release runs three ways: ``prbdm_pin.simulate`` with the damping the
files carry (``damping="stiffness"``: C = beta K, mode 1 at 2 %); plain Pinocchio on the URDF
(``buildModelFromUrdf`` with gravity set to zero, the springs read from the file's Gazebo tags,
the joint damping from ``<dynamics damping>``, ``pinocchio.aba`` integrated by DOP853); and
MuJoCo on the MJCF (its own springs, damping and RK4 step). The tip's z of the three runs is
compared sample by sample.

Full mode: the reference panel, plate truth, 4R combined fit, 1 s. Quick mode (``--quick``):
the uniform strip, 1D beam truth, 3R eigen fit, three periods of mode 1.

Run it with::

    python examples/export_and_simulate.py [--quick] [--out results/examples/export_and_simulate]
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
from scipy.integrate import solve_ivp

import prbdm_pin as pp
from prbdm_pin.commands.script_cli import run_example
from prbdm_pin.io.paths import check_out_dir
from prbdm_pin.model.urdf import read_springs
from prbdm_pin.views.plots import new_figure, save_png

# sphinx-gallery runs the script without __file__, from the examples folder
ROOT = Path(globals().get("__file__", "export_and_simulate.py")).resolve().parents[1]
DAMPING_RATIO = 0.02  # mode 1; the files carry C = beta K


def fitted_model(quick: bool, cache_dir: Path) -> tuple[pp.Beam, pp.PrbdmModel]:
    """Fit a joint-spring PRBDM of a shipped beam (see the module notes for the two modes)."""
    if quick:
        beam = pp.load_beam(ROOT / "examples" / "beams" / "uniform-narrow.json")
        truth = pp.compute_truth(beam, model="beam", modes=3)
        joints, options = 3, pp.FitOptions(stiffness="joint", objective="eigen", starts=4)
    else:
        beam = pp.load_beam(ROOT / "examples" / "beams" / "reference-random.json")
        truth = pp.compute_truth(beam, model="plate", modes=4, cache_dir=cache_dir)
        joints, options = 4, pp.FitOptions(stiffness="joint", objective="combined", starts=8)
    result = pp.fit(beam, pp.target_from_truth(truth, beam.tip_force_N), joints, options,
                    progress=False)
    return beam, pp.build_model(beam, result.lengths_m, result.stiffness_Nm_per_rad)


def run_pinocchio(urdf: Path, q0: np.ndarray, t_s: np.ndarray) -> np.ndarray:
    """Tip z (m) at ``t_s`` of a release from ``q0`` by plain Pinocchio on the URDF."""
    model = pin.buildModelFromUrdf(str(urdf))
    model.gravity = pin.Motion.Zero()  # the URDF parser sets -9.81 m/s^2; the PRBDM has none
    data = model.createData()
    springs = read_springs(urdf.read_text(), list(model.names)[1:])  # N m/rad
    damping = np.array(model.damping)  # N m s/rad, from <dynamics damping>
    tip = model.getFrameId("tip")
    n = model.nq

    def rhs(_t, x):
        q, v = x[:n], x[n:]
        return np.r_[v, pin.aba(model, data, q, v, -springs * q - damping * v)]

    sol = solve_ivp(rhs, (t_s[0], t_s[-1]), np.r_[q0, np.zeros(n)], method="DOP853",
                    t_eval=t_s, rtol=1e-10, atol=1e-12)
    z = np.empty(t_s.size)
    for k, q in enumerate(sol.y[:n].T):
        pin.framesForwardKinematics(model, data, q)
        z[k] = data.oMf[tip].translation[2]
    return z


def run_mujoco(mjcf: Path, q0: np.ndarray, duration_s: float, every: int):
    """Release the MJCF from ``q0`` in MuJoCo and return the sample times (s) and tip z (m).

    One sample every ``every`` steps of the file's own step and integrator.
    """
    m = mujoco.MjModel.from_xml_path(str(mjcf))
    d = mujoco.MjData(m)
    d.qpos[:] = q0
    mujoco.mj_forward(m, d)
    steps = int(round(duration_s / m.opt.timestep))
    t, z = [0.0], [d.site_xpos[0, 2]]
    for i in range(1, steps + 1):
        mujoco.mj_step(m, d)
        if i % every == 0:
            mujoco.mj_kinematics(m, d)  # the site at the stepped state
            t.append(d.time)
            z.append(d.site_xpos[0, 2])
    return np.array(t), np.array(z)


def main(quick: bool = False,
         out: Path = ROOT / "results" / "examples" / "export_and_simulate") -> dict:
    """Export, release in three engines; returns the sample times and the three tip z (m)."""
    out = check_out_dir("out", out)  # refused before any work, as --out
    out.mkdir(parents=True, exist_ok=True)
    beam, model = fitted_model(quick, out / "cache")
    urdf = pp.export_model(model, out / "model.urdf", "urdf", DAMPING_RATIO)
    mjcf = pp.export_model(model, out / "model.xml", "mjcf", DAMPING_RATIO)

    q0, _ = model.static_deflection(beam.tip_force_N)  # bent by the tip force, then released
    period = 2.0 * np.pi / model.natural_frequencies()[0]
    duration = 3.0 * period if quick else 1.0
    t_mj, z_mj = run_mujoco(mjcf, q0, duration, every=10)
    z_pin = run_pinocchio(urdf, q0, t_mj)
    ours = pp.simulate(model, t_mj[-1], q0=q0, damping="stiffness",
                       damping_ratio=DAMPING_RATIO, output_dt_s=t_mj[1] - t_mj[0])
    z_pp = np.interp(t_mj, ours.t_s, ours.tip_position_m[:, 2])

    peak = np.abs(z_pin - model.tip_position()[2]).max()
    for name, z in (("MuJoCo", z_mj), ("prbdm_pin.simulate", z_pp)):
        print(f"{name} against Pinocchio ABA: max tip z difference "
              f"{np.abs(z - z_pin).max() / peak:.2e} of the peak deflection")

    fig = new_figure((7.0, 3.2))
    ax = fig.subplots()
    ax.plot(t_mj, 1e3 * z_pin, "k", lw=2.5, label="Pinocchio ABA (URDF), DOP853")
    ax.plot(t_mj, 1e3 * z_mj, "C1", lw=1.2, label="MuJoCo (MJCF), RK4")
    ax.plot(t_mj, 1e3 * z_pp, "C0--", lw=1.0, label="prbdm_pin.simulate")
    ax.set(xlabel="t (s)", ylabel="tip z (mm)",
           title=f"{beam.name}: {model.n_joints}R released from its tip-load deflection")
    ax.legend(fontsize=8)
    fig.tight_layout()
    figure = save_png(fig, out / "export_and_simulate.png")
    return {"t_s": t_mj, "tip_z_mujoco_m": z_mj, "tip_z_pinocchio_m": z_pin,
            "tip_z_simulate_m": z_pp, "peak_m": peak, "model": model, "q0_rad": q0,
            "figure": figure}


if __name__ == "__main__":
    # no SystemExit on success: sphinx-gallery runs this block in the build's process
    if code := run_example(__doc__, ROOT / "results" / "examples" / "export_and_simulate",
                           main):
        raise SystemExit(code)
