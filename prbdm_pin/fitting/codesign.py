"""A design evaluated through truth -> fit -> PRBDM, with gradients chained through all three.

``codesign_point(design, p)`` solves the truth's frequencies (``truth_gradient``: 1D beam by
default, or the plate), fits the ``unique="nearest"`` nR model to them (one smooth model per
design) and reads from the PRBDM what a design problem constrains: its natural frequencies and
its large-deflection tip deflection under the beam's tip force; the panel's mass beside them.
With ``gradient=True`` each comes with its derivative in the design variables::

    d(model output)/dp = d out/d theta . d theta/dp + d out/dp |_theta

- d out/d theta: ``model_gradient`` (analytic, joint stations and springs);
- d theta/dp: ``fit_design_gradient`` (implicit-function theorem on the fit's KKT conditions,
  with the truth's analytic frequency gradient);
- d out/dp at fixed theta: the sections of the moved planform change the chain's masses and
  inertias (frequencies only: the statics do not see the masses), analytic at fixed lengths
  and springs (``model_design_gradient.frequency_design_gradient``);
- the mass: closed form (rho t times the trapezoidal planform area).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..chain.chain_derivatives import model_gradient
from ..errors import BeamInputError, SolveError
from ..member.design import Design
from ..member.geometry import Beam
from ..model.prbdm_model_derivatives import frequency_design_gradient
from ..options.validate import check_joints, check_type
from .target import FitTarget, read_only

__all__ = ["CodesignPoint", "codesign_point", "panel_mass", "TRUTH_MODELS"]

TRUTH_MODELS = ("beam", "plate")


@dataclass(frozen=True, eq=False)
class CodesignPoint:
    """One design through truth -> fit -> PRBDM.

    Attributes
    ----------
    names, units : tuple of str
        The design variables' names and SI units, in vector order (as in ``Design``).
    values : ndarray, shape (nv,)
        The design (SI units).
    mass_kg : float
        Panel mass (kg).
    omega_rad_s : ndarray, shape (n,)
        The PRBDM's natural frequencies (rad/s, straight pose).
    tip_deflection_m : float
        The absolute z of the PRBDM's large-deflection tip under the beam's tip force (m; 0
        without a load).
    truth_omega_rad_s : ndarray, shape (n,)
        The truth frequencies the model was fitted to (rad/s).
    lengths_m, stiffness_Nm_per_rad : ndarray
        The fitted model: link lengths (m), shape (n + 1,), and joint springs (N m/rad),
        shape (n,).
    d_mass_kg, d_omega_rad_s, d_tip_deflection_m : ndarray or None
        Derivatives per unit (SI) of each variable, shapes (nv,), (n, nv), (nv,), in kg,
        rad/s and m per unit; None without ``gradient``.
    truth_s, fit_s, gradient_s : float
        Wall time (s) of the truth (with its gradient when asked), the fit, and the chain rule.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> point = pp.codesign_point(pp.Design(beam, ("thickness",)), [0.01], joints=2)
    >>> point.names, point.units
    (('thickness',), ('m',))
    >>> round(float(point.d_mass_kg[0]), 1)  # kg/m: rho L 2 w = 7850 x 1 x 0.05
    392.5
    """

    names: tuple[str, ...]
    units: tuple[str, ...]
    values: np.ndarray
    mass_kg: float
    omega_rad_s: np.ndarray
    tip_deflection_m: float
    truth_omega_rad_s: np.ndarray
    lengths_m: np.ndarray
    stiffness_Nm_per_rad: np.ndarray
    d_mass_kg: np.ndarray | None
    d_omega_rad_s: np.ndarray | None
    d_tip_deflection_m: np.ndarray | None
    truth_s: float
    fit_s: float
    gradient_s: float


def panel_mass(design: Design, p: np.ndarray) -> tuple[float, np.ndarray]:
    """Return the panel's mass (kg) at ``p`` and its exact gradient (kg per unit of each variable).

    m = rho t A with A = sum_k (x_(k+1) - x_k)(w_k + w_(k+1)) (full width 2w, trapezoids):
    dA/dw_i is the length of the intervals next to vertex i; moving a station (with its step
    partner, vertices i..j) changes A by (w_(i-1) + w_i) - (w_j + w_(j+1)) per metre.

    Parameters
    ----------
    design : Design
        The design variables.
    p : numpy.ndarray
        Design values (SI units), shape (nv,), strictly inside ``design.bounds``.

    Returns
    -------
    mass_kg : float
        Panel mass (kg).
    d_mass_kg : numpy.ndarray
        Its derivative (kg per SI unit of each variable), shape (nv,).
    """
    beam = design.beam_at(p)
    x, w = beam.x_m, beam.half_width_m
    t, rho = beam.uniform_thickness_m("co-design"), beam.material.rho_kg_m3
    area = beam.planform_area_m2
    mass = beam.mass_kg
    gaps = np.diff(x)
    d = np.zeros(design.size)
    for row, (kind, i) in enumerate(design.kinds):
        if kind == "thickness":
            d[row] = rho * area
        elif kind == "rho":
            d[row] = t * area
        elif kind == "half_width":
            near = (gaps[i - 1] if i > 0 else 0.0) + (gaps[i] if i < gaps.size else 0.0)
            d[row] = rho * t * near
        elif kind == "x":
            a, b = i, i
            while a > 0 and x[a - 1] == x[i]:
                a -= 1
            while b + 1 < x.size and x[b + 1] == x[i]:
                b += 1
            d[row] = rho * t * ((w[a - 1] + w[a]) - (w[b] + w[b + 1]))
    return float(mass), read_only(d)


def _truth(design: Design, beam: Beam, model: str, joints: int, mesh_level: int | None,
           gradient: bool):
    """Truth frequencies (n,) and, with ``gradient``, their TruthGradient."""
    from ..truth.compute_derivatives import truth_gradient

    # the values-only path runs the same solve with the one closed-form derivative (E), so
    # both paths read bitwise the same truth and differ only in the shape derivatives' cost
    names = design.names if gradient else ("E",)
    g = truth_gradient(beam, names, model=model, modes=joints, mesh_level=mesh_level,
                       static=False)
    return g.omega_rad_s[:joints], (g if gradient else None)


def codesign_point(design: Design, p: np.ndarray, joints: int = 3, *, truth_model: str = "beam",
                   mesh_level: int | None = None, gradient: bool = True) -> CodesignPoint:
    """Evaluate the design ``p`` through truth -> ``unique="nearest"`` fit -> PRBDM.

    Parameters
    ----------
    design : Design
        The design variables and the beam they act on.
    p : array_like, shape (nv,)
        Design values (SI units), strictly inside ``design.bounds``.
    joints : int
        n of the nR model (n truth frequencies matched exactly).
    truth_model : {"beam", "plate"}
        The truth of ``truth_gradient``: 1D Euler-Bernoulli beam (fast) or Kirchhoff plate.
    mesh_level : int, optional
        Plate mesh level (the truth's default when None).
    gradient : bool
        Chain the derivatives too.

    Returns
    -------
    CodesignPoint
        The model's frequencies (rad/s), tip deflection (m) and the panel mass (kg), with
        their derivatives when ``gradient``.

    Raises
    ------
    BeamInputError
        A design outside its bounds, bad arguments.
    SolveError, TruthError
        The fit's rule or the truth fails at this design.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> design = pp.Design(beam, ("thickness",))
    >>> point = pp.codesign_point(design, [0.01], joints=2)
    >>> point.omega_rad_s.round(1), round(point.mass_kg, 3)
    (array([ 51.9, 325.1]), 3.925)
    >>> (point.d_omega_rad_s[:, 0] * 0.01 / point.omega_rad_s).round(3)  # omega ~ t
    array([1., 1.])
    """
    from . import fit
    from .design_derivatives import fit_design_gradient

    check_type("design", design, Design)
    joints = check_joints(joints)
    if truth_model not in TRUTH_MODELS:
        raise BeamInputError(f"truth_model = {truth_model!r}: must be one of {TRUTH_MODELS}")
    p = design.check(p)
    beam = design.beam_at(p)
    t0 = time.perf_counter()
    omega_t, tg = _truth(design, beam, truth_model, joints, mesh_level, gradient)
    t1 = time.perf_counter()
    target = FitTarget(omega_t, beam.tip_force_N, source=f"{truth_model} truth")
    fr = fit(beam, target, joints, stiffness="joint", unique="nearest", progress=False)
    L, K = np.array(fr.lengths_m), np.array(fr.stiffness_Nm_per_rad)
    mg = model_gradient(beam, L, K)
    if mg.tip_position_m is None:
        tip = 0.0
        sign = 0.0
    else:
        tip = abs(float(mg.tip_position_m[2]))
        sign = float(np.sign(mg.tip_position_m[2]))
    t2 = time.perf_counter()
    mass, d_mass = panel_mass(design, p)
    d_omega = d_tip = None
    if gradient:
        fd = fit_design_gradient(fr, design, p, tg)
        d_stations = np.cumsum(fd.d_lengths_m, axis=0)[:-1]  # x_j = L_0 + ... + L_(j-1)
        d_theta = np.vstack([d_stations, fd.d_stiffness_Nm_per_rad])  # (2n, nv)
        d_omega = mg.d_omega_rad_s @ d_theta + frequency_design_gradient(beam, design, L, K)[1]
        d_tip = (sign * mg.d_tip_position_m[2] @ d_theta if mg.tip_position_m is not None
                 else np.zeros(design.size))
        if not (np.all(np.isfinite(d_omega)) and np.all(np.isfinite(d_tip))):
            raise SolveError("codesign_point: a derivative is not finite")
        d_omega, d_tip = read_only(d_omega), read_only(d_tip)
    t3 = time.perf_counter()
    return CodesignPoint(
        names=design.names, units=design.units, values=read_only(p), mass_kg=mass,
        omega_rad_s=read_only(mg.omega_rad_s), tip_deflection_m=tip,
        truth_omega_rad_s=read_only(omega_t), lengths_m=read_only(L),
        stiffness_Nm_per_rad=read_only(K), d_mass_kg=d_mass if gradient else None,
        d_omega_rad_s=d_omega, d_tip_deflection_m=d_tip, truth_s=t1 - t0, fit_s=t2 - t1,
        gradient_s=t3 - t2)
