"""The MuJoCo side of ``bench_mujoco_accuracy.py``: the scene's model exported as MJCF, run
with RK4 or implicitfast at a sweep of steps, the tip read from the file's ``tip`` site every
step, timed in CPU time (``mujoco_accuracy_runs`` states the scene, the error and the timing).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from mujoco_accuracy_runs import (
    MUJOCO_DTS_S,
    OUTPUT_DT_S,
    TARGETS,
    OverCap,
    Run,
    Scene,
    best_cpu,
    tip_error,
)


def export_mjcf(scene: Scene, folder: Path):
    """The scene's model exported as MJCF (with the tip body: the export's default geometry)
    and loaded: (MjModel, tip body id, tip site id)."""
    import mujoco

    from prbdm_pin.files.export import export_model

    path = export_model(scene.model, folder / f"{scene.n_joints}r.xml", "mjcf",
                        scene.damping_ratio)
    m = mujoco.MjModel.from_xml_path(str(path))
    return m, m.body("tip_body").id, m.site("tip").id


def check_step_s(m, dt_s: float) -> float:
    """The largest step <= ``dt_s`` and <= the MJCF's own (RK4-stable) step that divides the
    1 ms output."""
    return OUTPUT_DT_S / math.ceil(OUTPUT_DT_S / min(dt_s, float(m.opt.timestep)) - 1e-9)


def _start(mujoco, m, body: int, scene: Scene):
    d = mujoco.MjData(m)
    d.qpos[:] = scene.q0_rad
    # held constant by MuJoCo across RK4's stages (mj_applyFT's force would be frozen at the
    # step's start pose); the tip body's origin is the tip point
    d.xfrc_applied[body, :3] = scene.force_N
    return d


def mujoco_run(m, body: int, site: int, scene: Scene, integrator: str, dt_s: float,
               repeats: int, cap_s: float | None = None) -> Run:
    """1 s of ``mj_step`` at ``dt_s``, the tip read from the ``tip`` site every step.

    After an RK4 step the site positions are those of its last stage, so the step is followed by
    ``mj_kinematics``; after an implicitfast step they are the step's start state (``mj_step``
    begins with ``mj_forward``), so the read lags one step and the last state gets one
    ``mj_kinematics`` at the end.
    """
    import mujoco

    m.opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{integrator.upper()}")
    m.opt.timestep = dt_s
    steps = int(round(1.0 / dt_s))
    rk4 = integrator == "rk4"

    def run():
        d = _start(mujoco, m, body, scene)
        mujoco.mj_forward(m, d)
        tips = np.empty((steps + 1, 3))
        tips[0] = d.site_xpos[site]
        xpos, step, kin = d.site_xpos, mujoco.mj_step, mujoco.mj_kinematics
        if rk4:
            for i in range(1, steps + 1):
                step(m, d)
                kin(m, d)
                tips[i] = xpos[site]
        else:
            for i in range(steps):
                step(m, d)
                tips[i] = xpos[site]
            kin(m, d)
            tips[steps] = xpos[site]
        return tips, int(d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number)

    def bare():
        d = _start(mujoco, m, body, scene)
        mujoco.mj_step(m, d, nstep=steps)

    try:
        cpu, (tips, bad) = best_cpu(run, repeats, cap_s=cap_s)
    except OverCap:
        return Run(scene.label, "mujoco", integrator, "dt_s", dt_s, math.inf, cap_s, steps,
                   failure=f"stopped at the CPU cap ({cap_s:g} s)")
    # the bare stepping only beside RK4, the table's yardstick
    bare_cpu = best_cpu(bare, repeats)[0] if rk4 else math.nan
    if dt_s <= OUTPUT_DT_S:
        every = int(round(OUTPUT_DT_S / dt_s))
        err, stride = tip_error(tips[::every], scene), 1
    else:
        stride = int(round(dt_s / OUTPUT_DT_S))
        err = tip_error(tips, scene, stride)
    return Run(scene.label, "mujoco", integrator, "dt_s", dt_s, math.inf if bad else err, cpu,
               steps, bare_cpu, "unstable (MuJoCo reset the state)" if bad else "")


def mujoco_sweep(scene: Scene, mjcf, repeats: int, max_run_cpu_s: float,
                 dts_s=MUJOCO_DTS_S, log=print) -> list[Run]:
    """RK4 and implicitfast from the largest step down to the first that reaches the tightest
    target, or the first run dearer than ``max_run_cpu_s``; ``mjcf`` is what
    :func:`export_mjcf` returns."""
    m, body, site = mjcf
    runs = []
    for integrator in ("rk4", "implicitfast"):
        for dt in dts_s:
            runs.append(mujoco_run(m, body, site, scene, integrator, dt, repeats,
                                   max_run_cpu_s))
            log(runs[-1])
            if runs[-1].error <= TARGETS[-1] or runs[-1].cpu_s_per_s >= max_run_cpu_s:
                break
    return runs
