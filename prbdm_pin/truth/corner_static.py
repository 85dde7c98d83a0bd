"""Static truth under a tip load off the centre line: a force at a tip corner, a tip moment.

A load that twists the member as well as bending it, for the spatial chain's statics. The load
is a force F (N, world axes) at one of the tip points (``tip``, ``tip_corner_left`` at
y = +w(L), ``tip_corner_right`` at y = -w(L), mid-surface; the names of
:mod:`prbdm_pin.chain.points`) and a moment M (N m, world axes). It is applied as the traction
over the tip face x = L (solid) or the line load along the tip edge (plate) that is uniform
plus linear across the section and statically equivalent to F at the point plus M: a point
load differs from it only near the tip (Saint-Venant), and while the tip face turns as a rigid
body the dead traction has the moment of a dead force at the turned corner, as the chain's load
(``PrbdmModel.static_deflection(..., point=...)``). A tip moment alone is a couple of dead
forces: its moment follows the tip face as it turns (by cos phi at a twist phi), not a moment
fixed in the world.

Models: the Kirchhoff plate (linear; it carries F_z and the moment about x, the in-plane parts
F_x, F_y and M_z give no deflection, a moment about y is refused) and the 3D solid, linear or
geometrically nonlinear (:mod:`.solid_nonlinear`). Reported: the tip centre's (L, 0, 0)
displacement, the tip corners' and the tip twist, the angle of the corner-to-corner line to the
world y axis in the y-z plane: (u_z,left - u_z,right) / (2 w(L)) in the linear solves,
atan2(dz, dy) of the deformed line in the nonlinear one.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, SolveError, TruthError
from ..member.geometry import Beam
from ..options.validate import check_type
from .result import Timings

# scikit-fem loads inside the solves: the fit checks a load point against POINT_SIDES without it

__all__ = ["POINT_SIDES", "CornerSolution", "corner_static", "face_load"]

# each tip point's side across the width (+1 left, -1 right, 0 centre), as
# ``prbdm_pin.chain.points.POINTS`` (not imported: the truth never loads Pinocchio)
POINT_SIDES = {"tip": 0.0, "tip_corner_left": 1.0, "tip_corner_right": -1.0}


@dataclass(frozen=True, eq=False)
class CornerSolution:
    """The tip response to a force at a tip point and a tip moment.

    Attributes
    ----------
    model : str
        ``"plate-argyris"`` or ``"solid"``.
    nonlinear : bool
        True for the geometrically nonlinear solve.
    point : str
        Where the force acts (``tip``, ``tip_corner_left``, ``tip_corner_right``).
    tip_force_N, tip_moment_Nm : ndarray, shape (3,)
        The force (N) at the point and the moment (N m), world axes.
    tip_position_m, tip_displacement_m : ndarray, shape (3,)
        The tip centre (L, 0, 0) deformed, and its displacement, m.
    corner_displacement_m : ndarray, shape (2, 3)
        The left (y = +w(L)) and right tip corners' mid-surface displacements, m.
    tip_twist_rad : float
        The tip twist (module notes), rad; positive turns +y towards +z.
    dofs, mesh_level, load_steps : int
    timings : Timings
    """

    model: str
    nonlinear: bool
    point: str
    tip_force_N: np.ndarray
    tip_moment_Nm: np.ndarray
    tip_position_m: np.ndarray
    tip_displacement_m: np.ndarray
    corner_displacement_m: np.ndarray
    tip_twist_rad: float
    dofs: int
    mesh_level: int
    load_steps: int = 1
    timings: Timings = Timings()


def _vector(name: str, v, unit: str) -> np.ndarray:
    a = np.zeros(3) if v is None else np.asarray(v, dtype=float)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise BeamInputError(f"{name} = {np.asarray(v).tolist()}: must be 3 finite numbers in "
                             f"{unit}")
    return a


def centre_moment(beam: Beam, point: str, F: np.ndarray, M: np.ndarray) -> np.ndarray:
    """Return the load's moment about the tip centre, M + o x F (N m), o the point's offset."""
    if point not in POINT_SIDES:
        raise BeamInputError(f"point = {point!r}: must be one of {', '.join(POINT_SIDES)}")
    o = np.array([0.0, POINT_SIDES[point] * float(beam.half_width_at(beam.length_m)), 0.0])
    return M + np.cross(o, F)


def face_load(beam: Beam, d, F: np.ndarray, Mc: np.ndarray) -> np.ndarray:
    """Consistent nodal forces (N) of the solid's tip-face traction of resultant F and Mc.

    t = F / A + (Mc_x / I_y) y e_z + (Mc_y / I_z z - Mc_z / I_y y) e_x over the face x = L,
    with A, I_y = int y^2 dA and I_z = int z^2 dA of the face (m^2, m^4): its resultant about
    the tip centre is F (N) and Mc (N m), the face being symmetric in y and z.
    """
    from skfem import ElementHex2, FacetBasis, LinearForm, asm

    L = beam.length_m
    facets = d.mesh.facets_satisfying(lambda x: np.isclose(x[0], L, atol=1e-12 * L))
    fb = FacetBasis(d.mesh, ElementHex2(), facets=facets, intorder=4)
    f0 = asm(LinearForm(lambda v, w: v), fb)
    fy = asm(LinearForm(lambda v, w: v * w.x[1]), fb)
    fz = asm(LinearForm(lambda v, w: v * w.x[2]), fb)
    # the Lagrange basis sums to one, so summing a form's entries integrates its weight
    A = f0.sum()
    Iy = asm(LinearForm(lambda v, w: v * w.x[1] ** 2), fb).sum()
    Iz = asm(LinearForm(lambda v, w: v * w.x[2] ** 2), fb).sum()
    f = np.zeros(d.n_vec)
    f[0::3] = F[0] * f0 / A + Mc[1] * fz / Iz - Mc[2] * fy / Iy
    f[1::3] = F[1] * f0 / A
    f[2::3] = F[2] * f0 / A + Mc[0] * fy / Iy
    return f


def _solid(beam: Beam, F, Mc, level, nonlinear: bool, load_steps, tol: float, max_iter: int):
    from .solid_fe import SpdFactor, assemble, discretise
    from .solid_nonlinear import solve_nonlinear

    if load_steps is None:
        # as solid_static: about 3 increments per unit of the load index, the moment's as the
        # force at the half-width that gives it
        size = float(np.linalg.norm(F)) + float(np.linalg.norm(Mc)) / float(
            beam.half_width_at(beam.length_m))
        load_steps = int(np.clip(np.ceil(3 * beam.load_index(size)), 1, 100))
    t0 = time.perf_counter()
    d = discretise(beam, level)
    f = face_load(beam, d, F, Mc)
    t1 = time.perf_counter()
    if nonlinear:
        u, steps = solve_nonlinear(beam, d, f, int(load_steps), tol, max_iter)
    else:
        K = assemble(beam, d)[0]
        u = np.zeros(d.n_vec)
        u[d.free] = SpdFactor(K[d.free][:, d.free], d.order).solve(f[d.free])
        steps = 1
    t2 = time.perf_counter()
    locs = d.basis.doflocs
    L, w = beam.length_m, float(beam.half_width_at(beam.length_m))
    out = []
    for y in (0.0, w, -w):
        # the DOFs on the face's line at y through the thickness (z = -t/2, 0, t/2)
        at = np.flatnonzero((np.abs(locs[0] - L) < 1e-9 * L) & (np.abs(locs[1] - y) < 1e-9 * L))
        if at.size != 3:
            raise SolveError(f"found {at.size} DOF locations at the tip (L, {y:.6g}), expected 3")
        out.append(np.array([u[3 * at + i].mean() for i in range(3)]))
    return out, int(d.free.size), d.level, steps, Timings(mesh_s=t1 - t0, solve_s=t2 - t1)


def _plate(beam: Beam, F, Mc, level):
    from skfem import Basis, FacetBasis, LinearForm, asm

    from .mesh import planform_tri_mesh
    from .mesh_budget import check_plate_budget
    from .plate import ROOT_CLAMP_DOFS, assemble_plate, plate_rigidity_Nm
    from .plate_elements import ElementTriArgyrisLocal
    from .plate_static import spd_solve
    from .settings import DEFAULT_PLATE_LEVEL, check_level

    if Mc[1] != 0.0:
        raise BeamInputError(f"tip_moment_Nm = {Mc.tolist()}: the plate truth takes no moment "
                             "about y (an edge moment); use model='solid'")
    lev = DEFAULT_PLATE_LEVEL if level is None else check_level(level)
    L, w = beam.length_m, float(beam.half_width_at(beam.length_m))
    t0 = time.perf_counter()
    check_plate_budget(beam, lev, "argyris")
    mesh = planform_tri_mesh(beam, lev)
    basis = Basis(mesh, ElementTriArgyrisLocal())
    tol = 1e-9 * L
    fb = FacetBasis(mesh, ElementTriArgyrisLocal(),
                    facets=mesh.facets_satisfying(lambda x: np.abs(x[0] - L) < tol))
    mat = beam.material
    t_u = beam.uniform_thickness_m("the plate truth")
    K, _ = assemble_plate(basis, plate_rigidity_Nm(beam), mat.nu, mat.rho_kg_m3 * t_u)
    # q(y) = F_z / (2 w) + Mc_x y / I, I = int y^2 dy = 2 w^3 / 3 over the edge (N/m)
    a, b = F[2] / (2.0 * w), Mc[0] / (2.0 * w**3 / 3.0)
    f = asm(LinearForm(lambda v, p: (a + b * p.x[1]) * v), fb)
    clamped = basis.get_dofs(lambda x: np.abs(x[0]) < tol).all(ROOT_CLAMP_DOFS["argyris"])
    free = np.setdiff1d(np.arange(basis.N), clamped)
    t1 = time.perf_counter()
    u = np.zeros(basis.N)
    u[free] = spd_solve(K[free][:, free].tocsc(), f[free])
    t2 = time.perf_counter()
    out = []
    for y in (0.0, w, -w):
        node = np.flatnonzero((np.abs(mesh.p[0] - L) < tol) & (np.abs(mesh.p[1] - y) < tol))
        if node.size != 1:
            raise TruthError(f"{beam.name!r}: plate mesh has {node.size} nodes at (L, {y:.6g})")
        out.append(np.array([0.0, 0.0, u[basis.nodal_dofs[0, node[0]]]]))
    return out, int(free.size), lev, 1, Timings(mesh_s=t1 - t0, solve_s=t2 - t1)


def corner_static(beam: Beam, model: str = "plate", tip_force_N=None,
                  point: str = "tip_corner_left", tip_moment_Nm=None, level: int | None = None,
                  nonlinear: bool = False, load_steps: int | None = None, tol: float = 1e-7,
                  max_iter: int = 25) -> CornerSolution:
    """Tip response of the plate or the solid to a force at a tip point and a tip moment.

    Parameters
    ----------
    beam : Beam
    model : str
        ``"plate"`` (the Kirchhoff plate, linear) or ``"solid"``.
    tip_force_N : array_like, shape (3,), optional
        The force at ``point``, N, world axes (default: ``beam.tip_force_N``).
    point : str
        ``tip``, ``tip_corner_left`` (y = +w(L)) or ``tip_corner_right``.
    tip_moment_Nm : array_like, shape (3,), optional
        A tip moment besides, N m (default none; module notes on its large-rotation meaning).
    level : int, optional
        Mesh level (the model's default when None).
    nonlinear : bool
        Geometrically nonlinear (solid only): total-Lagrangian Saint Venant-Kirchhoff.
    load_steps, tol, max_iter
        The nonlinear solve's initial increments (default about 3 per unit of the load index),
        Newton tolerance on the residual relative to the load and iterations per increment.

    Returns
    -------
    CornerSolution
        The tip centre's displacement (m), the corners' (m) and the tip twist (rad).

    Raises
    ------
    BeamInputError
        An unknown model or point, a load that is not 3 finite numbers, a nonlinear plate or a
        moment about y on the plate, each naming the field.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> sol = pp.corner_static(beam, "plate", tip_force_N=[0.0, 0.0, -1.0], level=0)
    >>> EI = 205e9 * 0.05 * 0.01**3 / 12  # N m^2
    >>> # the tip centre against the 1D beam's F L^3 / (3 EI): the plate is a little stiffer
    >>> round(float(sol.tip_displacement_m[2]) * 1e3, 4), round(-1.0 / (3 * EI) * 1e3, 4)  # mm
    (-0.3884, -0.3902)
    >>> left, right = sol.corner_displacement_m[:, 2] * 1e3  # mm: the loaded corner sinks more
    >>> bool(left < right)
    True
    >>> J = 0.05 * 0.01**3 / 3 * (1 - 0.630 * 0.01 / 0.05)  # m^4: the strip's Saint-Venant J
    >>> # the twist against T L / (G J); the clamp's warping restraint makes the plate stiffer
    >>> round(sol.tip_twist_rad * 1e6, 1), round(-1.0 * 0.025 / (205e9 / 2.56 * J) * 1e6, 1)  # urad
    (-18.5, -21.4)
    """
    check_type("beam", beam, Beam)
    F = _vector("tip_force_N", beam.tip_force_N if tip_force_N is None else tip_force_N, "N")
    M = _vector("tip_moment_Nm", tip_moment_Nm, "N m")
    Mc = centre_moment(beam, point, F, M)
    if model == "solid":
        disp, dofs, lev, steps, times = _solid(beam, F, Mc, level, bool(nonlinear), load_steps,
                                               tol, max_iter)
        name = "solid"
    elif model == "plate":
        if nonlinear:
            raise BeamInputError("nonlinear = True: the plate truth is linear; use "
                                 "model='solid'")
        disp, dofs, lev, steps, times = _plate(beam, F, Mc, level)
        name = "plate-argyris"
    else:
        raise BeamInputError(f"model = {model!r}: must be 'plate' or 'solid'")
    centre, left, right = disp
    w = float(beam.half_width_at(beam.length_m))
    dz = left[2] - right[2]
    twist = math.atan2(dz, 2.0 * w + left[1] - right[1]) if nonlinear else dz / (2.0 * w)
    return CornerSolution(
        model=name, nonlinear=bool(nonlinear), point=point, tip_force_N=F, tip_moment_Nm=M,
        tip_position_m=np.array([beam.length_m, 0.0, 0.0]) + centre,
        tip_displacement_m=centre, corner_displacement_m=np.vstack([left, right]),
        tip_twist_rad=float(twist), dofs=dofs, mesh_level=lev, load_steps=steps,
        timings=times)
