"""Geometry in the exports, measured: what each consumer shows, mesh mass, tip body and tip load.

For a 5R planar chain (reference-random, finite-segment springs) and a 4-node xyz spatial chain
(tapered, spatial springs), each exported to URDF and MJCF with geometry: the link meshes MuJoCo,
Pinocchio (``buildGeomFromUrdf``, visual) and yourdfpy (its scene) show; the worst relative
difference between a mesh file's volume times density and the link's mass, and between its
centroid and the link's centre of mass (over L); the tip body's change of MuJoCo's mass matrix
(against the file without geometry, over max |M|, straight and two random poses); and the MJCF
under a constant tip load applied on ``tip_body`` with ``xfrc_applied`` against the package's
simulate (DOP853, rtol 1e-11, the same stiffness-form damping 2 %), as % of the peak tip
deflection, at 1e-4 s or the file's step where RK4 needs a shorter one.

Writes a Markdown table to results/bench_export_geometry.md and
docs/benchmarks/bench_export_geometry.md (or the path given with --out).

    python scripts/bench_export_geometry.py [--out results/bench_export_geometry.md]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "scripts"))

from docs_tables import write_table  # noqa: E402

from prbdm_pin.chain.spatial_stiffness import spatial_stiffness  # noqa: E402
from prbdm_pin.chain.stiffness import finite_segment_stiffness  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.files.export import export_model, mjcf_text  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402
from prbdm_pin.simulation import simulate  # noqa: E402


def chains():
    beam = load_beam(ROOT / "examples" / "beams" / "reference-random.json")
    L = np.array([0.1, 0.2, 0.2, 0.2, 0.15, 0.15])
    yield "5R planar", build_model(beam, L, finite_segment_stiffness(beam, L)), \
        np.asarray(beam.tip_force_N, dtype=float)
    beam = load_beam(ROOT / "examples" / "beams" / "tapered.json")
    L = np.full(5, 0.12)
    yield "4-node xyz", build_model(beam, L, spatial_stiffness(beam, L, "xyz"), axes="xyz"), \
        np.array([0.0, 0.3, -1.0]) * abs(beam.tip_force_N[2])


def full_M(mujoco, m, q):
    d = mujoco.MjData(m)
    d.qpos[:] = q
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    return M


def row(label, model, force, folder: Path) -> str:
    import mujoco
    import pinocchio as pin
    import trimesh
    import yourdfpy

    urdf = export_model(model, folder / "beam.urdf", "urdf", 0.02)
    mjcf = export_model(model, folder / "beam.xml", "mjcf", 0.02)
    links = model.n_joints + 1
    m = mujoco.MjModel.from_xml_path(str(mjcf))
    n_mesh = int(np.sum(m.geom_type == mujoco.mjtGeom.mjGEOM_MESH))
    pm = pin.buildModelFromUrdf(str(urdf))
    n_pin = pin.buildGeomFromUrdf(pm, str(urdf), pin.GeometryType.VISUAL,
                                  package_dirs=[str(folder)]).ngeoms
    n_yd = len(yourdfpy.URDF.load(str(urdf)).scene.geometry)
    s, rho, L = model.sections, model.beam.material.rho_kg_m3, model.beam.length_m
    mass_err = com_err = 0.0
    for i in range(links):
        tm = trimesh.load(folder / "beam_meshes" / f"link_{i}.obj", force="mesh", process=False)
        mass_err = max(mass_err, abs(tm.volume * rho / s.mass_kg[i] - 1.0))
        com = np.asarray(tm.center_mass) + [s.start_m[i], 0.0, 0.0]
        com_err = max(com_err, np.abs(com - s.com_m[i]).max() / L)
    bare = mujoco.MjModel.from_xml_string(mjcf_text(model, 0.02))
    rng = np.random.default_rng(3)
    dM = 0.0
    for q in [np.zeros(m.nq), *rng.normal(0.0, 0.3, (2, m.nq))]:
        M = full_M(mujoco, m, q)
        dM = max(dM, np.abs(M - full_M(mujoco, bare, q)).max() / np.abs(M).max())
    out_dt = 1e-3
    every = int(np.ceil(out_dt / min(1e-4, m.opt.timestep)))
    m.opt.timestep = out_dt / every
    duration = round(1.5 * np.pi / model.natural_frequencies()[0], 3)
    d = mujoco.MjData(m)
    d.xfrc_applied[m.body("tip_body").id, :3] = force
    mujoco.mj_forward(m, d)
    tips = [d.site("tip").xpos.copy()]
    for i in range(1, int(round(duration / out_dt)) * every + 1):
        mujoco.mj_step(m, d)
        if i % every == 0:
            mujoco.mj_kinematics(m, d)
            tips.append(d.site("tip").xpos.copy())
    ref = simulate(model, duration, tip_force=force, damping_ratio=0.02, damping="stiffness",
                   method="DOP853", rtol=1e-11, atol=1e-13, output_dt_s=out_dt).tip_position_m
    peak = np.abs(ref - model.tip_position()).max()
    err = 100.0 * np.abs(ref - np.array(tips)).max() / peak
    return (f"| {label} | {links} | {n_mesh} | {n_pin} | {n_yd} | {mass_err:.1e} | "
            f"{com_err:.1e} | {dM:.1e} | {m.opt.timestep:.2e} | {duration:.3f} | {err:.1e} |")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_export_geometry.md"))
    args = ap.parse_args()
    rows = []
    for label, model, force in chains():
        with tempfile.TemporaryDirectory() as tmp:
            rows.append(row(label, model, force, Path(tmp)))
        print(rows[-1], flush=True)
    text = "\n".join([
        "| chain | links | MuJoCo mesh geoms | Pinocchio visual objects | yourdfpy geometries "
        "| max abs(V rho / m - 1) | max COM error / L | tip body: max abs(dM) / max abs(M) "
        "| RK4 step (s) | run (s) | MuJoCo tip load vs DOP853 (% of peak) |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
        *rows, "",
        "Written by `python scripts/bench_export_geometry.py`: the meshes read back from the "
        "exported OBJ files; the MJCF with the tip body (1e-12 of the member's mass) against "
        "the same model's MJCF without geometry; the load a constant `xfrc_applied` force on "
        "`tip_body`.", ""])
    for path in write_table(args.out, text, ap.get_default("out"), "bench_export_geometry"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
