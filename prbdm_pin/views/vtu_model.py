"""A chain as VTU files for ParaView (meshio): its mode shapes, and a trajectory as a series.

The chain is its points (root, nodes, tip) at the straight pose joined by one line cell per
link. A modes file holds per mode the point fields ``displacement_mode_<k>`` (the full
displacement vector, m per unit modal coordinate of the mass-normalised mode: ParaView's "Warp
By Vector" draws it) and ``twist_mode_<k>`` (rotation about x of the link starting at the
point, rad). A trajectory is one VTU per frame, each
with the point field ``displacement`` (m, from the straight pose) and ``twist`` (rad), and a
ParaView collection (``.pvd``) naming each file with its time (s).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pinocchio as pin

from ..chain.points import twist_angle
from ..errors import BeamInputError
from ..io.atomic import atomic_path, atomic_write_text
from .chain_geometry import chain_frames, chain_modes, chain_points, check_model

__all__ = ["write_model_modes_vtu", "write_trajectory_vtu"]


def _mesh(points: np.ndarray, point_data: dict):
    import meshio

    n = points.shape[0]
    lines = np.column_stack([np.arange(n - 1), np.arange(1, n)])
    return meshio.Mesh(np.asarray(points, dtype=float), [("line", lines)],
                       point_data=point_data)


def _write(mesh, path: Path) -> Path:
    import meshio

    with atomic_path(path) as tmp:
        meshio.write(tmp, mesh, file_format="vtu")
    return path


def write_model_modes_vtu(model, path: str | os.PathLike, n_modes: int | None = None) -> Path:
    """Write the chain's mode shapes as a VTU file (module docstring); return the path.

    Parameters
    ----------
    model : PrbdmModel
        Clamped or on a hub (the hub's rigid mode is left out).
    path : path-like
        The ``.vtu`` file, written atomically.
    n_modes : int, optional
        How many modes (default all flexible modes).

    Returns
    -------
    Path

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import meshio
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> path = pp.write_model_modes_vtu(model, Path(tempfile.mkdtemp()) / "modes.vtu")
    >>> mesh = meshio.read(path)  # read back as ParaView would
    >>> mesh.points.shape, sorted(mesh.point_data)[:2]
    ((4, 3), ['displacement_mode_1', 'displacement_mode_2'])
    >>> u = mesh.point_data["displacement_mode_1"]  # m per modal unit
    >>> bool(np.allclose(u, pp.chain_modes(model).displacement_m[0]))
    True
    """
    check_model(model)
    _vtu_path(path)
    m = chain_modes(model, n_modes)
    data = {}
    for k in range(m.omega_rad_s.size):
        data[f"displacement_mode_{k + 1}"] = m.displacement_m[k]
        data[f"twist_mode_{k + 1}"] = m.twist_rad[k]
    return _write(_mesh(m.points_m, data), Path(path))


def _vtu_path(path) -> None:
    if Path(path).suffix.lower() != ".vtu":
        raise BeamInputError(f"path = {str(path)!r}: a VTU file's name ends in .vtu")


def _link_twist(model, q: np.ndarray, data) -> np.ndarray:
    """Rotation about x of the link starting at each point, rad (the tip: link n's)."""
    frames = chain_frames(model)
    pin.framesForwardKinematics(model.pin_model, data, q)
    return np.array([twist_angle(data.oMf[f].rotation) for f in frames])


def write_trajectory_vtu(model, trajectory, folder: str | os.PathLike, *, frames: int = 60,
                         name: str = "trajectory") -> Path:
    """Write ``trajectory`` as a VTU series with a ParaView collection; return the ``.pvd``.

    Parameters
    ----------
    model : PrbdmModel
        The chain simulated.
    trajectory : Trajectory
        The response (:func:`prbdm_pin.simulate`).
    folder : path-like
        Where ``<name>.pvd`` and ``<name>_<i>.vtu`` go (created when missing).
    frames : int
        Samples written, spread evenly over the trajectory (the first is its first).
    name : str
        The files' stem.

    Returns
    -------
    Path
        The collection ``<name>.pvd``.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import meshio
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> run = pp.simulate(model, 0.2, q0=[0.01, 0.0])  # s, rad
    >>> pvd = pp.write_trajectory_vtu(model, run, tempfile.mkdtemp(), frames=3)
    >>> pvd.name, sorted(p.name for p in pvd.parent.glob("*.vtu"))
    ('trajectory.pvd', ['trajectory_0000.vtu', 'trajectory_0001.vtu', 'trajectory_0002.vtu'])
    >>> first = meshio.read(pvd.parent / "trajectory_0000.vtu")  # the first sample, t = 0
    >>> tip = first.points[-1] + first.point_data["displacement"][-1]  # m
    >>> bool(np.allclose(tip, run.tip_position_m[0]))  # the trajectory's own tip
    True
    """
    from .animate import frame_samples

    check_model(model)
    idx = frame_samples(int(trajectory.t_s.size), frames)
    d = model.new_data()
    rest = chain_points(model, None, d)
    out = Path(folder)
    entries = []
    for i, s in enumerate(idx):
        q = np.asarray(trajectory.q_rad[s], dtype=float)
        pts = chain_points(model, q, d)
        data = {"displacement": pts - rest, "twist": _link_twist(model, q, d)}
        f = out / f"{name}_{i:04d}.vtu"
        _write(_mesh(rest, data), f)
        entries.append(f'    <DataSet timestep="{float(trajectory.t_s[s])!r}" part="0" '
                       f'file="{f.name}"/>')
    text = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
            "  <Collection>\n" + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
    return atomic_write_text(out / f"{name}.pvd", text)
