"""The links' solids in an export: OBJ meshes beside the file, and the XML that uses them.

An export to ``DIR/NAME.urdf`` (or ``.xml``, ``.mjcf``) writes each link's solid
(:mod:`prbdm_pin.files.link_mesh`) as ``DIR/NAME_meshes/link_j.obj`` (Wavefront OBJ through
trimesh, 17 decimals: the file is the exact mesh, where a binary STL's float32 would move its
volume by 1e-7), one per link ``link_0`` ... ``link_n`` in the link's frame; the massless node links
of a spatial URDF (``link_j_y``, ``link_j_z``) and the hub carry no geometry. The folder name
follows the export's, so two exports in one folder never share (or overwrite) meshes.

URDF: each link gets ``<visual>`` and ``<collision>`` with ``<mesh filename="NAME_meshes/
link_j.obj"/>``, a path relative to the URDF, which yourdfpy, MuJoCo's URDF import and
RViz resolve beside the file; Pinocchio's ``buildGeomFromUrdf(model, path,
pin.GeometryType.VISUAL, package_dirs=[DIR])`` finds it through ``package_dirs``. For a ROS
package put the folder in the package and replace the prefix by ``package://PKG/`` (e.g.
``sed 's#filename="#filename="package://my_beam/#'``). The spatial URDF read into MuJoCo through
``mujoco.MjSpec.from_string`` (:mod:`prbdm_pin.files.export`) needs ``spec.meshdir`` set to the
URDF's folder (a string has no folder to resolve the paths against).

MJCF: an ``<asset>`` ``<mesh name="link_j" file="NAME_meshes/link_j.obj"/>`` per link (paths
relative to the MJCF file: load it with ``mujoco.MjModel.from_xml_path``) and a mesh geom in each
link body. The geoms have ``contype="1" conaffinity="0"``: two beam geoms never collide (MuJoCo
collides a pair when one's contype meets the other's conaffinity), so neighbouring links, which
overlap at a bent joint, and the links of one member never touch; a user's object with the
default ``conaffinity="1"`` still collides with every link. The bodies' ``<inertial>`` is
written, so MuJoCo takes no mass from the geoms.

The tip body (MJCF): ``tip_body`` at the free end of ``link_n``, welded to it (no joint), a
sphere geom (no contacts) of mass :data:`TIP_MASS_FRACTION` times the member's, holding the
sites ``tip``, ``tip_corner_left`` and ``tip_corner_right`` (at +-w(L) along y, as the package's
points of those names). ``data.xfrc_applied[tip_body_id, :3] = F`` is then a dead force at the
tip: MuJoCo applies it at the body's centre of mass, which is the tip, at every stage of RK4 with
the stage's pose (a force written as joint torques J^T F from a callback keeps the step's first
pose through the stages). The tiny mass keeps MuJoCo's ``xfrc_applied`` and ``xipos`` defined on a
body of its own and changes the mass matrix by m_tip J^T J, about 1e-12 of it (measured in the
tests and the guide).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from ..chain.points import point_offset_m
from ..errors import BeamInputError
from ..io.atomic import atomic_write_text
from ..io.paths import writable_dir
from ..model.checks import check_model
from ..options.checks import check_float
from .export_comment import number_text as _f
from .export_comment import vector_text as _vec
from .link_mesh import LinkMesh, planform_link_mesh, round_profile_mesh

__all__ = ["TIP_MASS_FRACTION", "TIP_SITES", "link_meshes", "station_sites", "mesh_folder",
           "write_meshes", "obj_text", "urdf_geometry", "mjcf_assets", "mjcf_link_geom",
           "mjcf_tip_body"]

# the tip body's mass over the member's: far below anything the model resolves (the mass
# matrix moves by about this fraction) yet a body MuJoCo gives a centre of mass
TIP_MASS_FRACTION = 1.0e-12
TIP_SITES = ("tip", "tip_corner_left", "tip_corner_right")
_RGBA = "0.55 0.6 0.7 1"


def link_meshes(model) -> tuple[LinkMesh, ...]:
    """Return the solid of every link (``link_0`` to ``link_n``), each in its own frame (m).

    Raises
    ------
    BeamInputError
        A model without a beam (read from a URDF): it carries no planform to mesh.
    InputTypeError
        ``model`` not a PrbdmModel.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.05, 0.025], thickness_m=0.01)  # a taper
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> meshes = pp.link_meshes(model)
    >>> len(meshes), all(isinstance(m, pp.LinkMesh) for m in meshes)
    (3, True)
    >>> def volume(mesh):  # m^3: the divergence theorem over the triangles
    ...     v = mesh.vertices_m[mesh.faces]
    ...     return float(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6)
    >>> [round(7850.0 * volume(m), 4) for m in meshes]  # kg: rho V
    [1.4915, 3.0419, 1.3541]
    >>> model.sections.mass_kg.round(4)  # kg: the links' masses
    array([1.4915, 3.0419, 1.3541])
    """
    check_model(model)
    beam = model.beam
    if beam is None:
        raise BeamInputError("model: read from a URDF, it carries no beam, so no geometry; "
                             "export without geometry or from the fit.json")
    if not has_geometry(model):
        raise BeamInputError("model: a section-table member has no geometry to mesh; export "
                             "without geometry")
    s = model.sections
    mesh = planform_link_mesh if beam.section is None else _round_member_mesh
    return tuple(mesh(beam, float(a), float(b)) for a, b in zip(s.start_m, s.end_m, strict=True))


def has_geometry(model) -> bool:
    """Whether ``model``'s member has a solid to mesh: a planform or a round section.

    A model read from a URDF (no beam) and a section-table member (properties, no shape) have
    none; their exports are the bare files.
    """
    from ..member.round_section import RoundSection

    beam = model.beam
    return beam is not None and (beam.section is None or isinstance(beam.section, RoundSection))


def _round_member_mesh(beam, start_m: float, end_m: float) -> LinkMesh:
    # D and d are linear between stations: rings at the link's ends and the stations inside
    sec = beam.section
    D = sec.outer_diameter_m
    d = np.zeros_like(D) if sec.inner_diameter_m is None else sec.inner_diameter_m
    inner = beam.x_m[(beam.x_m > start_m) & (beam.x_m < end_m)]
    cuts = np.concatenate([[start_m], inner, [end_m]])
    return round_profile_mesh(cuts - start_m, np.interp(cuts, beam.x_m, D),
                              np.interp(cuts, beam.x_m, d))


def mesh_folder(path: str | os.PathLike) -> Path:
    """Return the mesh folder of the export ``path``: ``NAME_meshes`` beside it."""
    p = Path(path)
    return p.with_name(f"{p.stem}_meshes")


def obj_text(mesh: LinkMesh) -> str:
    """Return the Wavefront OBJ text of ``mesh`` (trimesh's writer, no normals).

    Coordinates carry 17 decimals (m): the file's volume and centroid are the double-precision
    mesh's to rounding, where a binary STL's float32 would lose them at 1e-7.
    """
    import trimesh

    tm = trimesh.Trimesh(vertices=np.asarray(mesh.vertices_m), faces=np.asarray(mesh.faces),
                         process=False)
    return trimesh.exchange.obj.export_obj(tm, include_normals=False, include_color=False,
                                           include_texture=False, digits=17)


def write_meshes(model, path: str | os.PathLike) -> tuple[Path, ...]:
    """Write the links' OBJ files into :func:`mesh_folder` of ``path``, each atomically.

    The folder is checked first (``BeamInputError`` naming it, nothing written); all meshes are
    built before the first file is written.
    """
    folder = writable_dir(mesh_folder(path), "mesh folder")
    data = [obj_text(m) for m in link_meshes(model)]
    return tuple(atomic_write_text(folder / f"link_{i}.obj", t) for i, t in enumerate(data))


def urdf_geometry(folder_name: str, i: int) -> str:
    """Return ``link_i``'s URDF ``<visual>`` and ``<collision>`` (a relative mesh path)."""
    mesh = f'<mesh filename="{folder_name}/link_{i}.obj"/>'
    return (f"    <visual>\n      <origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\n"
            f"      <geometry>\n        {mesh}\n      </geometry>\n    </visual>\n"
            f"    <collision>\n      <origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\n"
            f"      <geometry>\n        {mesh}\n      </geometry>\n    </collision>\n")


def mjcf_assets(folder_name: str, n_links: int) -> list[str]:
    """Return the MJCF ``<asset>`` lines: one mesh per link."""
    return ["  <asset>",
            *[f'    <mesh name="link_{i}" file="{folder_name}/link_{i}.obj"/>'
              for i in range(n_links)],
            "  </asset>"]


def mjcf_link_geom(i: int) -> str:
    """Return the mesh geom of ``link_i``: no contact among beam geoms, contact with others."""
    return (f'<geom name="link_{i}" type="mesh" mesh="link_{i}" contype="1" conaffinity="0" '
            f'group="1" rgba="{_RGBA}"/>')


def mjcf_tip_body(model, indent: str) -> list[str]:
    """Return the MJCF lines of ``tip_body`` (inside ``link_n``), its sphere and sites."""
    s = model.sections
    n = model.n_joints
    w = float(model.beam.half_width_m[-1])
    m = TIP_MASS_FRACTION * float(np.sum(s.mass_kg))
    r = 0.5 * w  # visible at the tip, inside the planform
    inertia = 0.4 * m * r * r  # a solid sphere's
    if not (math.isfinite(m) and m > 0.0):
        raise BeamInputError(f"model: member mass = {m!r} kg gives no tip body")
    sites = [f'{indent}  <site name="{p}" pos="{_vec(point_offset_m(p, w))}" size="{_f(0.2 * r)}"/>'
             for p in TIP_SITES]
    return [f'{indent}<body name="tip_body" pos="{_f(model.lengths_m[n])} 0 0">',
            f'{indent}  <inertial pos="0 0 0" mass="{_f(m)}" '
            f'diaginertia="{_f(inertia)} {_f(inertia)} {_f(inertia)}"/>',
            f'{indent}  <geom name="tip" type="sphere" size="{_f(r)}" contype="0" '
            'conaffinity="0" group="1" rgba="0.9 0.3 0.2 1"/>',
            *sites,
            f"{indent}</body>"]


def station_sites(model, stations_m) -> dict[int, list[str]]:
    """Return the MJCF sites ``station_k`` at the member's stations, by the link that holds each.

    Station k (m from the root, on the beam axis) sits on the link whose span holds it, at
    ``x - start`` in that body; one on a joint goes on the outboard link, at its origin (a
    section there moves with both links: the package's ``slope@X`` reads their mean).

    Raises
    ------
    BeamInputError
        A station off the member, naming ``sensor_stations_m[k]``.
    """
    from ..model.stations import check_station, section_links

    s = model.sections
    out: dict[int, list[str]] = {}
    for k, x in enumerate(stations_m):
        xs = check_station(model, check_float(f"sensor_stations_m[{k}]", x, unit="m"),
                           f"sensor_stations_m[{k}]")
        i = section_links(model, xs)[-1][0]
        pos = max(xs - float(s.start_m[i]), 0.0)
        out.setdefault(i, []).append(f'<site name="station_{k}" pos="{_f(pos)} 0 0" '
                                     'size="0.002"/>')
    return out
