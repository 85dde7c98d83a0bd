"""``truth_gradient``: the truth's frequencies and linear tip with their design gradients.

Eigenvalue derivatives d lam = phi^T (dK - lam dM) phi / (phi^T M phi) of the selected bending
modes and the adjoint derivative of the linear static tip deflection, for the Kirchhoff plate
(default) or the 1D beam, on the truth's own mesh moving with the planform (fixed topology).
See ``sensitivity_rules`` for the rules, ``sensitivity_plate`` and ``sensitivity_beam`` for the
models, ``morph`` for how the mesh follows the planform.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..io.records import readonly_array as _ro
from ..member.design import Design
from ..member.geometry import Beam
from .request import TruthRequest, request_of
from .settings import DEFAULT_PLATE_LEVEL

__all__ = ["TruthGradient", "truth_gradient", "GRADIENT_MODELS"]

GRADIENT_MODELS = ("plate", "beam")


@dataclass(frozen=True, eq=False)
class TruthGradient:
    """Truth values and their derivatives with respect to design variables.

    Attributes
    ----------
    model : str
        ``"plate"`` or ``"beam"``.
    mesh_level : int or None
        Plate mesh level (None for the 1D beam).
    names, units : tuple of str
        The design variables and their SI units.
    values : ndarray, shape (n,)
        The design variables' values (SI units).
    mode_index : ndarray of int, shape (N,)
        Indices of the N selected bending modes among the computed modes.
    omega_rad_s : ndarray, shape (N,)
        Selected bending frequencies, rad/s.
    d_omega_rad_s : ndarray, shape (N, n)
        d omega_k / d p_j, rad/s per unit of variable j.
    tip_z_m : float or None
        Linear static tip deflection (z) under the beam's tip force, m (None without the static
        case).
    d_tip_z_m : ndarray, shape (n,), or None
        d tip_z / d p_j, m per unit of variable j (adjoint).
    solve_s, gradient_s : float
        Wall time (s) of the truth's solve (modes, selection, static) and of all gradients after
        it.
    solve_cpu_s, gradient_cpu_s : float
        The same in CPU time (s) of this process (less disturbed by other processes).
    dofs : int
        Number of degrees of freedom of the truth's finite-element model.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> g = pp.truth_gradient(beam, ("thickness", "rho"), model="beam", modes=2, static=False)
    >>> isinstance(g, pp.TruthGradient), g.model, g.tip_z_m  # no static case asked
    (True, 'beam', None)
    >>> # omega is proportional to rho^(-1/2): d omega / d rho = -omega / (2 rho)
    >>> g.d_omega_rad_s[:, 1].round(5), (-g.omega_rad_s / (2 * 7850.0)).round(5)  # rad/s per kg/m^3
    (array([-0.0033, -0.0207]), array([-0.0033, -0.0207]))
    """

    model: str
    mesh_level: int | None
    names: tuple[str, ...]
    units: tuple[str, ...]
    values: np.ndarray
    mode_index: np.ndarray
    omega_rad_s: np.ndarray
    d_omega_rad_s: np.ndarray
    tip_z_m: float | None
    d_tip_z_m: np.ndarray | None
    solve_s: float
    gradient_s: float
    solve_cpu_s: float
    gradient_cpu_s: float
    dofs: int

    @property
    def relative_d_omega(self) -> np.ndarray:
        """p_j / omega_k d omega_k / d p_j (dimensionless), shape (N, n)."""
        return self.d_omega_rad_s * self.values[None, :] / self.omega_rad_s[:, None]

    @property
    def relative_d_tip_z(self) -> np.ndarray | None:
        """p_j / tip_z d tip_z / d p_j (dimensionless), or None."""
        if self.d_tip_z_m is None or not self.tip_z_m:
            return None
        return self.d_tip_z_m * self.values / self.tip_z_m


def truth_gradient(beam: Beam, design: Design | tuple[str, ...] | list[str],
                   request: TruthRequest | None = None, **fields) -> TruthGradient:
    """Compute the truth's bending frequencies, linear tip deflection and their design gradients.

    Parameters
    ----------
    beam : Beam
        The design point.
    design : Design or sequence of str
        The design variables (a ``Design`` of any beam of the same vertex structure, or its
        variable names); the gradient is taken at ``beam``.
    request : TruthRequest, optional
        The truth, as ``compute_truth`` takes it: its ``model`` (``"plate"``, the Kirchhoff
        plate with Argyris elements, or ``"beam"``, 1D Euler-Bernoulli), ``modes`` selected by
        its ``selection`` among ``n_computed`` (at least 2 * modes), the plate's ``mesh_level``
        (ignored for the 1D beam), and with ``static`` the linear tip deflection under
        ``beam.tip_force_N`` (z) and its gradient. ``large_deflection``, ``error_tol_pct`` and
        ``check_convergence`` do not enter: the gradient is that of the linear tip, on the
        request's own mesh, without an error estimate.
    **fields
        Without ``request``, its fields as keywords (``model="beam", modes=3``), the others at
        the defaults of :class:`TruthRequest`.

    Returns
    -------
    TruthGradient
        Frequencies (rad/s) and tip deflection (m) with their derivatives per SI unit of each
        design variable.

    Raises
    ------
    BeamInputError
        Bad arguments or design variables, or a model other than plate and beam.
    TruthError
        A truth that cannot be trusted, or a selected eigenvalue (nearly) repeated (relative gap
        below ``sensitivity_rules.GAP_TOL``): its derivative is not defined by one mode.
    TypeError
        A keyword that is no field of TruthRequest, or a request given with fields.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -1.0])
    >>> g = pp.truth_gradient(beam, ("thickness",), model="beam", modes=2)
    >>> g.names, g.units, g.d_omega_rad_s.shape
    (('thickness',), ('m',), (2, 1))
    >>> # omega is proportional to t and the tip to 1 / t^3: d omega/dt = omega/t, d w/dt = -3 w/t
    >>> g.d_omega_rad_s[:, 0].round(2), (g.omega_rad_s / 0.01).round(2)  # rad/s per m
    (array([ 5186.83, 32505.33]), array([ 5186.83, 32505.33]))
    >>> round(float(g.d_tip_z_m[0]), 5), round(-3 * g.tip_z_m / 0.01, 5)  # m per m
    (0.11707, 0.11707)
    """
    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r}: must be a prbdm_pin.Beam")
    names = design.names if isinstance(design, Design) else design
    if isinstance(names, str):
        names = tuple(n.strip() for n in names.split(","))
    d = Design(beam, tuple(names))
    req = request_of(request, fields, "truth_gradient")
    if req.model not in GRADIENT_MODELS:
        raise BeamInputError(f"model = {req.model!r}: must be one of {GRADIENT_MODELS}")
    model, modes, selection, static = req.model, req.modes, req.selection, req.static
    if req.spatial and model == "beam":
        # its mode_index would count the bending modes only, not the spatial truth's modes
        raise BeamInputError("spatial = True: the 1D truth's design sensitivities cover its "
                             "bending modes only (give spatial=False)")
    n_computed = req.computed_modes
    if model == "plate":
        from .plate_derivatives import plate_sensitivity

        level = DEFAULT_PLATE_LEVEL if req.mesh_level is None else req.mesh_level
        r = plate_sensitivity(d, level, modes, selection, n_computed, static)
    else:
        from .beam_derivatives import beam_sensitivity

        r = beam_sensitivity(d, modes, selection, n_computed, static)
    index = np.array(r["mode_index"])
    index.setflags(write=False)
    return TruthGradient(
        model=model, mesh_level=r["mesh_level"], names=d.names, units=d.units,
        values=_ro(d.values), mode_index=index, omega_rad_s=_ro(r["omega_rad_s"]),
        d_omega_rad_s=_ro(r["d_omega_rad_s"]),
        tip_z_m=None if r["tip_z_m"] is None else float(r["tip_z_m"]),
        d_tip_z_m=None if r["d_tip_z_m"] is None else _ro(r["d_tip_z_m"]),
        solve_s=float(r["solve_s"]), gradient_s=float(r["gradient_s"]),
        solve_cpu_s=float(r["solve_cpu_s"]), gradient_cpu_s=float(r["gradient_cpu_s"]),
        dofs=int(r["dofs"]),
    )
