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

from ..design import Design
from ..errors import BeamInputError, InputTypeError
from ..geometry import Beam
from ..json_record import readonly_array as _ro
from .modes import SELECTIONS
from .settings import DEFAULT_COMPUTED_MODES, DEFAULT_PLATE_LEVEL, check_mesh_level

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
    mode_index : ndarray of int, shape (modes,)
        Indices of the selected bending modes among the computed modes.
    omega_rad_s : ndarray, shape (modes,)
        Selected bending frequencies, rad/s.
    d_omega_rad_s : ndarray, shape (modes, n)
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
        """p_j / omega_k d omega_k / d p_j (dimensionless), shape (modes, n)."""
        return self.d_omega_rad_s * self.values[None, :] / self.omega_rad_s[:, None]

    @property
    def relative_d_tip_z(self) -> np.ndarray | None:
        """p_j / tip_z d tip_z / d p_j (dimensionless), or None."""
        if self.d_tip_z_m is None or not self.tip_z_m:
            return None
        return self.d_tip_z_m * self.values / self.tip_z_m


def _count(name: str, value: object, minimum: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise BeamInputError(f"{name} = {value!r}: must be an integer >= {minimum}")
    return int(value)


def truth_gradient(
    beam: Beam,
    design: Design | tuple[str, ...] | list[str],
    model: str = "plate",
    modes: int = 3,
    mesh_level: int | None = None,
    selection: str = "paper",
    static: bool = True,
    n_computed: int = DEFAULT_COMPUTED_MODES,
) -> TruthGradient:
    """Compute the truth's bending frequencies, linear tip deflection and their design gradients.

    Parameters
    ----------
    beam : Beam
        The design point.
    design : Design or sequence of str
        The design variables (a ``Design`` of any beam of the same vertex structure, or its
        variable names); the gradient is taken at ``beam``.
    model : {"plate", "beam"}
        Kirchhoff plate (Argyris, the default truth) or 1D Euler-Bernoulli beam.
    modes : int
        Number of bending modes, selected as ``compute_truth`` selects them.
    mesh_level : int, optional
        Plate mesh level (default: the truth's default); ignored for the 1D beam.
    selection : {"paper", "shape"}
        Mode selection, as in ``compute_truth``: ``paper``, the modes of largest z mass
        participation; ``shape``, the lowest symmetric modes matching a 1D beam bending mode.
    static : bool
        Also the linear tip deflection under ``beam.tip_force_N`` (z) and its gradient.
    n_computed : int
        Modes computed before the selection (at least 2 * modes).

    Returns
    -------
    TruthGradient
        Frequencies (rad/s) and tip deflection (m) with their derivatives per SI unit of each
        design variable.

    Raises
    ------
    BeamInputError
        Bad arguments or design variables.
    TruthError
        A truth that cannot be trusted, or a selected eigenvalue (nearly) repeated (relative gap
        below ``sensitivity_rules.GAP_TOL``): its derivative is not defined by one mode.
    """
    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r}: must be a prbdm_pin.Beam")
    names = design.names if isinstance(design, Design) else design
    if isinstance(names, str):
        names = tuple(n.strip() for n in names.split(","))
    d = Design(beam, tuple(names))
    if model not in GRADIENT_MODELS:
        raise BeamInputError(f"model = {model!r}: must be one of {GRADIENT_MODELS}")
    if selection not in SELECTIONS:
        raise BeamInputError(f"selection = {selection!r}: must be one of {SELECTIONS}")
    modes = _count("modes", modes)
    n_computed = max(_count("n_computed", n_computed), 2 * modes)
    if model == "plate":
        from .sensitivity_plate import plate_sensitivity

        level = DEFAULT_PLATE_LEVEL if mesh_level is None else check_mesh_level(mesh_level)
        r = plate_sensitivity(d, level, modes, selection, n_computed, bool(static))
    else:
        from .sensitivity_beam import beam_sensitivity

        r = beam_sensitivity(d, modes, selection, n_computed, bool(static))
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
