"""Damping and URDF exports checked in other tools: MuJoCo (MJCF), Pinocchio, MuJoCo, pybullet.

For 3R and 5R models of the reference beam (link lengths as in the tests, springs from the
finite-segment formula) this writes results/export_check.md with
- the modal damping ratios that the exported joint damping gives (MuJoCo's own M at qpos = 0,
  jnt_stiffness, dof_damping; generalized eigenproblem), for the stiffness form written today and
  for the diagonal of the modal damping matrix written before;
- the tip z difference between MuJoCo's step response of the MJCF export (the beam's tip force,
  data.xfrc_applied) and prbdm_pin.simulate with the damping the user would pair with it
  (stiffness form today; modal form before), as % of the peak, over the first period, 0.5 s and
  2 s; MuJoCo at RK4 with a 0.1 ms step, at the export's own settings (RK4, step T_n/20, rounded
  down to divide the 1 ms output interval) and with MuJoCo's default Euler at that step (what the
  export shipped before);
- the joint-space mass matrix of the URDF export read by Pinocchio, MuJoCo and pybullet against
  ours at three poses (largest relative difference);
- the same models on a hub (J_h = 2 kg m^2, r = 0.1 m) with a strain patch: MuJoCo's hub angle
  and tip z under a hub torque step and a patch sine (scripts/bench_mjcf_plant.py) against
  DOP853 of Pinocchio's ABA, at 0.1 ms and at the export's own step, as % of the peak; and the
  URDF consumers' mass matrices of the hub model.

usage: python scripts/export_check.py [--damping 0.02] [--out results/export_check.md]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import scipy.linalg as sla  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from prbdm_pin.chain.stiffness import finite_segment_stiffness  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.files.export import mjcf_text, urdf_text  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402
from prbdm_pin.simulation import simulate  # noqa: E402
from prbdm_pin.simulation.damping import modal_damping  # noqa: E402

LENGTHS = {3: [0.15, 0.3, 0.3, 0.25], 5: [0.1, 0.2, 0.2, 0.2, 0.15, 0.15]}
OUTPUT_DT_S = 1e-3


def mj_MKC(m, d):
    """MuJoCo's mass matrix at qpos = 0, joint stiffness and joint damping."""
    import mujoco

    d.qpos[:] = 0.0
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    return M, np.diag(np.array(m.jnt_stiffness)), np.diag(np.array(m.dof_damping))


def ratios(M, K, C):
    """Modal-projection ratios diag(Phi^T C Phi) / (2 omega), and the damped eigenvalue ratios
    -Re(s)/|s| of the underdamped pairs (NaN where a mode is overdamped)."""
    w2, phi = sla.eigh(K, M)
    omega = np.sqrt(w2)
    proj = np.diag(phi.T @ C @ phi) / (2 * omega)
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -C]])
    B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), M]])
    s = sla.eigvals(A, B)
    s = s[s.imag > 0]
    s = s[np.argsort(np.abs(s))]
    eig = np.full(n, np.nan)
    eig[: s.size] = -s.real / np.abs(s)
    return proj, eig


def mj_step(m, force, duration_s):
    """MuJoCo's tip positions every OUTPUT_DT_S under a constant world tip force."""
    import mujoco

    d = mujoco.MjData(m)
    body = m.nbody - 1
    every = int(round(OUTPUT_DT_S / m.opt.timestep))
    if abs(every * m.opt.timestep - OUTPUT_DT_S) > 1e-12:
        raise ValueError("timestep must divide the output interval")
    mujoco.mj_forward(m, d)
    tips = [d.site_xpos[0].copy()]
    for i in range(1, int(round(duration_s / m.opt.timestep)) + 1):
        d.xfrc_applied[body, :3] = force
        d.xfrc_applied[body, 3:] = np.cross(d.site_xpos[0] - d.xipos[body], force)
        mujoco.mj_step(m, d)
        if i % every == 0:
            mujoco.mj_kinematics(m, d)
            tips.append(d.site_xpos[0].copy())
    return np.array(tips)


def diffs(t, ours, theirs, rest_z, windows):
    """Largest |tip z difference| in each window [0, w], % of the peak of ours over it."""
    out = []
    for w in windows:
        sel = t <= w + 1e-12
        peak = np.abs(ours[sel, 2] - rest_z).max()
        out.append(100 * np.abs(ours[sel, 2] - theirs[sel, 2]).max() / peak)
    return out


def consumers(model, poses):
    """Largest relative mass-matrix difference of each URDF consumer against ours."""
    import mujoco
    import pinocchio as pin
    import pybullet as p

    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "beam.urdf"
        path.write_text(urdf_text(model, 0.02))
        ref = [model.mass_matrix(q) for q in poses]

        def worst(Ms):
            return max(np.abs(M - R).max() / np.abs(R).max() for M, R in zip(Ms, ref, strict=True))

        pm = pin.buildModelFromUrdf(str(path))
        pm.gravity = pin.Motion.Zero()
        pd = pm.createData()
        Ms = []
        for q in poses:
            M = pin.crba(pm, pd, q)
            Ms.append(np.triu(M) + np.triu(M, 1).T)
        out["Pinocchio buildModelFromUrdf"] = worst(Ms)
        m = mujoco.MjModel.from_xml_path(str(path))
        d = mujoco.MjData(m)
        Ms = []
        for q in poses:
            d.qpos[:] = q
            mujoco.mj_forward(m, d)
            M = np.zeros((m.nv, m.nv))
            mujoco.mj_fullM(m, d, M)
            Ms.append(M)
        out["MuJoCo (URDF import)"] = worst(Ms)
        cid = p.connect(p.DIRECT)
        try:
            b = p.loadURDF(str(path), useFixedBase=True, flags=p.URDF_USE_INERTIA_FROM_FILE,
                           physicsClientId=cid)
            out["pybullet (URDF_USE_INERTIA_FROM_FILE)"] = worst(
                [np.array(p.calculateMassMatrix(b, list(map(float, q)), physicsClientId=cid))
                 for q in poses])
        finally:
            p.disconnect(cid)
    return out


def hub_section(beam) -> list[str]:
    """The hub plant rows: MuJoCo against the nonlinear reference, URDF consumers' M."""
    import mujoco
    from bench_mjcf_plant import NAMES, XI, errors_pct, hub_plant, mujoco_run, reference_run

    lines = ["## On a hub (J_h = 2 kg m^2, r = 0.1 m), strain patch [0.05 L, 0.45 L]", "",
             "Hub torque step 40 N m and patch sine 300 N m at 30 rad/s, 0.5 s; MuJoCo RK4 "
             "(ctrl at each step's midpoint) against DOP853 (rtol 1e-10) of Pinocchio's ABA "
             "with the input map; damping: the plant's stiffness form, 2 % on the lowest "
             "flexible mode.", ""]
    for n in (3, 5):
        lines += ["| hub model | MuJoCo step | hub angle (% of peak) | tip z (% of peak) |",
                  "|---|---|---|---|"]
        model, acts = hub_plant(beam, n)
        m = mujoco.MjModel.from_xml_string(mjcf_text(model, XI, actuators=acts, inputs=NAMES))
        ref = reference_run(model, acts)
        for label, h in (("0.1 ms", 1e-4), ("as exported", m.opt.timestep)):
            m.opt.timestep = h
            e = errors_pct(ref, mujoco_run(m))
            lines.append(f"| {n}R | {label}, {1e6 * h:.0f} us | {e[0]:.3g} % | {e[1]:.3g} % |")
            print(f"{n}R hub, MuJoCo {label}: hub {e[0]:.3g} %, tip z {e[1]:.3g} %", flush=True)
        poses = [np.zeros(n + 1), np.linspace(0.1, 0.4, n + 1), np.linspace(-0.6, 0.5, n + 1)]
        lines += ["", f"| URDF consumer, {n}R hub model | largest relative M difference, "
                  "3 poses |", "|---|---|"]
        for name, v in consumers(model, poses).items():
            lines.append(f"| {name} | {v:.2g} |")
        lines.append("")
    return lines


def main() -> int:
    import mujoco

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--beam", default=str(ROOT / "examples" / "beams" / "reference-random.json"))
    ap.add_argument("--damping", type=float, default=0.02)
    ap.add_argument("--out", default=str(ROOT / "results" / "export_check.md"))
    args = ap.parse_args()
    beam = load_beam(args.beam)
    xi = args.damping
    force = np.asarray(beam.tip_force_N, dtype=float)
    lines = [
        f"# Export check: {beam.name}, damping {xi}, step tip force {force.tolist()} N",
        "",
        "Models: link lengths as in the tests, springs from the finite-segment formula. MuJoCo's "
        "own M (qpos = 0), jnt_stiffness and dof_damping of the MJCF export give the ratios; "
        "'projection' is diag(Phi^T C Phi)/(2 omega), 'eigenvalue' is -Re(s)/|s| of the damped "
        "pairs (differs when the modes do not diagonalise C; '-' = overdamped). Step: tip z of "
        "MuJoCo (tip force through data.xfrc_applied) against prbdm_pin.simulate (default "
        "settings, the damping form paired with the file), largest difference as % of the peak "
        "over [0, T1], [0, 0.5 s] and [0, 2 s]. 'as exported': the file's own integrator and "
        "step (T_n/20, rounded down to divide the 1 ms output interval).",
        "",
    ]
    windows = None
    t0 = time.perf_counter()
    for n in (3, 5):
        lengths = np.asarray(LENGTHS[n], dtype=float) * beam.length_m / sum(LENGTHS[n])
        model = build_model(beam, lengths, finite_segment_stiffness(beam, lengths))
        omega = model.natural_frequencies()
        T1 = 2 * np.pi / omega[0]
        windows = (T1, 0.5, 2.0)
        rest_z = model.tip_position()[2]
        text = mjcf_text(model, xi)
        m_new = mujoco.MjModel.from_xml_string(text)
        M, K, C_new = mj_MKC(m_new, mujoco.MjData(m_new))
        C_old = np.diag(np.diag(modal_damping(M, K, xi)))
        m_old = mujoco.MjModel.from_xml_string(text)
        m_old.dof_damping[:] = np.diag(C_old)
        new_proj, new_eig = ratios(M, K, C_new)
        old_proj, old_eig = ratios(M, K, C_old)

        def pct(a):
            return " / ".join("-" if not np.isfinite(v) else f"{100 * v:.3g}" for v in a)

        lines += [
            f"## {n}R (frequencies at the straight pose, rad/s: "
            + ", ".join(f"{w:.1f}" for w in omega) + ")",
            "",
            "| exported joint damping | modal ratios, projection (%) | modal ratios, "
            "eigenvalue (%) |",
            "|---|---|---|",
            f"| stiffness form beta K (today) | {pct(new_proj)} | {pct(new_eig)} |",
            f"| diagonal of the modal matrix (before) | {pct(old_proj)} | {pct(old_eig)} |",
            "",
            "| MuJoCo run | simulate run | over T1 = " + f"{1e3 * T1:.1f} ms | over 0.5 s | "
            "over 2 s |",
            "|---|---|---|---|---|",
        ]
        sims = {form: simulate(model, 2.0, tip_force=force, damping_ratio=xi, damping=form,
                               output_dt_s=OUTPUT_DT_S) for form in ("stiffness", "modal")}
        t = sims["stiffness"].t_s
        h_exp = OUTPUT_DT_S / np.ceil(OUTPUT_DT_S / m_new.opt.timestep)
        for label, m_mj, form, integrator, h in (
            ("stiffness form (today)", m_new, "stiffness", "RK4", 1e-4),
            ("stiffness form (today), as exported", m_new, "stiffness", "RK4", h_exp),
            ("stiffness form (today)", m_new, "stiffness", "EULER", h_exp),
            ("diagonal of modal (before), as exported", m_old, "modal", "EULER", h_exp),
            ("diagonal of modal (before)", m_old, "modal", "RK4", 1e-4),
        ):
            mm = mujoco.MjModel.from_xml_string(text)
            mm.dof_damping[:] = m_mj.dof_damping
            mm.opt.timestep = h
            mm.opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{integrator}")
            tips = mj_step(mm, force, 2.0)
            d = diffs(t, sims[form].tip_position_m, tips, rest_z, windows)
            label = f"{label}, {integrator} {1e6 * h:.0f} us"
            lines.append(f"| {label} | damping={form!r} | "
                         + " | ".join(f"{v:.3g} %" for v in d) + " |")
            print(f"{n}R {label} vs simulate {form}: " + ", ".join(f"{v:.3g} %" for v in d),
                  flush=True)
        fine = simulate(model, 2.0, tip_force=force, damping_ratio=xi, damping="stiffness",
                        output_dt_s=OUTPUT_DT_S, method="DOP853", rtol=1e-10)
        floor = diffs(t, fine.tip_position_m, sims["stiffness"].tip_position_m, rest_z, windows)
        lines += ["", "simulate's default settings against DOP853 at rtol 1e-10 (the floor of the "
                  "rows above): " + ", ".join(f"{v:.3g} %" for v in floor), ""]
        lines += ["| URDF consumer | largest relative M difference, 3 poses |", "|---|---|"]
        poses = [np.zeros(n), np.linspace(0.1, 0.4, n), np.linspace(-0.6, 0.5, n)]
        for name, v in consumers(model, poses).items():
            lines.append(f"| {name} | {v:.2g} |")
        lines.append("")
    lines += hub_section(beam)
    lines.append(f"Wall time {time.perf_counter() - t0:.0f} s.")
    out = Path(args.out)
    atomic_write_text(out, "\n".join(lines) + "\n")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
