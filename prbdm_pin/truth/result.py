"""Data carried out of the finite-element truth: modal and static solutions, and the TruthResult.

Every array is read-only; every field has its unit in its name or docstring.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Timings", "ModalSolution", "StaticSolution", "TruthResult"]


@dataclass(frozen=True)
class Timings:
    """Wall times of one finite-element solve, in s.

    Attributes
    ----------
    mesh_s : float
        Mesh generation, s.
    basis_s : float
        Basis (element DOF maps and quadrature), s.
    assembly_s : float
        Matrix assembly, s.
    solve_s : float
        Eigen or linear solve, s.
    """

    mesh_s: float = 0.0
    basis_s: float = 0.0
    assembly_s: float = 0.0
    solve_s: float = 0.0

    @property
    def total_s(self) -> float:
        """Total wall time of the solve, s."""
        return self.mesh_s + self.basis_s + self.assembly_s + self.solve_s


@dataclass(frozen=True, eq=False)
class ModalSolution:
    """All computed modes of one model on one mesh, ascending in frequency.

    Attributes
    ----------
    model : str
        ``"plate-argyris"``, ``"plate-morley"``, ``"solid"`` or ``"beam"``.
    omega_rad_s : ndarray, shape (k,)
        Natural frequencies in rad/s.
    mpf_z : ndarray, shape (k,)
        z mass-participation factor (phi^T M r_z)^2 / (phi^T M phi), in kg.
    mpf_z_fraction : ndarray, shape (k,)
        ``mpf_z`` divided by the total mass (sums to <= 1 over all modes).
    symmetric : ndarray of bool, shape (k,)
        Whether the mode's z displacement is symmetric about the x axis.
    mac_beam : ndarray, shape (k,)
        Best modal assurance criterion of the mode's centreline z displacement with a 1D beam
        bending mode (NaN where not computed).
    beam_mode_index : ndarray of int, shape (k,)
        Index (0-based) of that best-matching beam mode (-1 where not computed).
    centerline_x_m : ndarray, shape (s,)
        Stations along the axis y = 0 where ``centerline_uz`` is sampled, m.
    centerline_uz : ndarray, shape (k, s)
        Mode shapes' z displacement along the axis (arbitrary scale).
    dofs : int
    mesh_level : int
    timings : Timings
    nodes_m : ndarray, shape (N, 3)
        Mesh nodes for export, m.
    cells : ndarray, shape (c, v)
        Mesh connectivity for export.
    cell_type : str
        meshio cell type name (``"triangle"``, ``"hexahedron27"``, ``"line"`` ...).
    node_uz : ndarray, shape (k, N)
        Nodal z displacement of each mode (not the element's raw DOF vector).
    modal_mass_kg : ndarray, shape (k,), optional
        phi^T M phi of each mode at the scale of ``centerline_uz`` and ``node_uz`` (ones for
        mass-normalised shapes); None where the model does not provide it.
    z_energy_fraction : ndarray, shape (k,), optional
        Share of each mode's kinetic energy phi^T M phi in the z displacement (the 3D solid:
        near 1 for bending and torsion, near 0 for in-plane modes); None for models that only
        move in z (plate, bending-only beam).
    x_energy_fraction : ndarray, shape (k,), optional
        Share of each mode's kinetic energy in the x displacement (the 3D solid: near 1 for its
        extension modes, small for all others); None for the other models.
    eig_residual : ndarray, shape (k,), optional
        The plate's eigenpairs' relative residuals (``truth.plate.PlateModes.rel_residual``):
        the solve's own accuracy, which a convergence check between mesh levels allows for;
        None for the other models.
    kinds : tuple of str, optional
        The family of every mode where the model solves the families apart (the 1D beam with
        ``spatial=True``: ``"bending"``, ``"torsion"``, ``"in-plane"``); None where the labels
        are judged from the mode shapes (``truth.modes.label_modes``).
    node_u : ndarray, shape (k, N, 3), optional
        The whole nodal displacement (x, y, z) of each mode at the scale of ``node_uz`` (the
        3D solid, whose modes also move in the plane); None where z is the whole displacement
        (plate mid-surface, Euler-Bernoulli axis).
    """

    model: str
    omega_rad_s: np.ndarray
    mpf_z: np.ndarray
    mpf_z_fraction: np.ndarray
    symmetric: np.ndarray
    mac_beam: np.ndarray
    beam_mode_index: np.ndarray
    centerline_x_m: np.ndarray
    centerline_uz: np.ndarray
    dofs: int
    mesh_level: int
    timings: Timings = field(default_factory=Timings)
    nodes_m: np.ndarray | None = None
    cells: np.ndarray | None = None
    cell_type: str = ""
    node_uz: np.ndarray | None = None
    modal_mass_kg: np.ndarray | None = None
    z_energy_fraction: np.ndarray | None = None
    x_energy_fraction: np.ndarray | None = None
    kinds: tuple[str, ...] | None = None
    eig_residual: np.ndarray | None = None
    node_u: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class StaticSolution:
    """Tip response under a tip force spread uniformly over the free edge.

    Attributes
    ----------
    model : str
    nonlinear : bool
        True for a geometrically nonlinear (large-deflection) solve.
    tip_force_N : ndarray, shape (3,)
    tip_position_m : ndarray, shape (3,)
        Deformed position of the tip centre (x = L, y = 0, mid-surface), m.
    tip_displacement_m : ndarray, shape (3,)
        ``tip_position_m`` minus the undeformed tip (L, 0, 0), m.
    dofs : int
    mesh_level : int
    load_steps : int
    timings : Timings
    """

    model: str
    nonlinear: bool
    tip_force_N: np.ndarray
    tip_position_m: np.ndarray
    tip_displacement_m: np.ndarray
    dofs: int
    mesh_level: int
    load_steps: int = 1
    timings: Timings = field(default_factory=Timings)


@dataclass(frozen=True, eq=False)
class TruthResult:
    """The finite-element truth a fit is measured against.

    Attributes
    ----------
    beam_fingerprint : str
    model : str
    mesh_level : int
    selection : str
        Mode-selection policy: ``"paper"`` (largest z mass participation) or ``"shape"``.
    omega_rad_s : ndarray, shape (N,)
        The selected bending modes' natural frequencies, ascending, rad/s.
    mode_index : ndarray of int, shape (N,)
        Their indices into ``modal.omega_rad_s``.
    mpf_z_fraction, mac_beam : ndarray, shape (N,)
        Their mass participation (fraction of total mass) and MAC with a beam bending mode.
    labels : tuple of str
        A label for every computed mode (``"bending"``, ``"torsion"``, ``"chordwise"``, ...).
    modal : ModalSolution
    static_linear, static_nonlinear : StaticSolution or None
        Under the beam file's tip force.
    version : str
        Package version that computed it.
    warnings : tuple of str
        E.g. a selected mode that is not beam-like.
    static_theory_gap_pct : float or None
        100 (u_1D / u_model - 1): how far the 1D beam's linear tip deflection is from the truth
        model's under the same load, in % (None without a static solve). Positive: the 1D beam
        is softer. The ``calibrated-elastica`` large-deflection tip removes this gap.
    error_estimate_pct : ndarray, shape (N,), or None
        Estimated discretisation error of each selected frequency, in % (the change to mesh level
        ``error_estimate_level``; see ``truth.estimate``); None where not estimated.
    error_estimate_level : int or None
        The mesh level the estimate compares with.
    beam_gap_pct : ndarray, shape (N,), or None
        100 (omega_1D / omega - 1) of each selected mode against its best-MAC 1D Euler-Bernoulli
        beam mode, in %.
    beam_gap_cause : tuple of str
        The cause of each gap (clamped Poisson effect, plate action, a mode without a 1D
        counterpart).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -1.0])
    >>> truth = pp.compute_truth(beam, model="beam", modes=2)
    >>> isinstance(truth, pp.TruthResult), truth.model, truth.labels[:2]
    (True, 'beam', ('bending', 'bending'))
    >>> EI = 205e9 * 0.05 * 0.01**3 / 12  # N m^2
    >>> w_tip = truth.static_linear.tip_displacement_m[2]  # m
    >>> round(float(w_tip) * 1e3, 4), round(-1.0 * 1.0**3 / (3 * EI) * 1e3, 4)  # mm: F L^3 / (3 EI)
    (-0.3902, -0.3902)
    """

    beam_fingerprint: str
    model: str
    mesh_level: int
    selection: str
    omega_rad_s: np.ndarray
    mode_index: np.ndarray
    mpf_z_fraction: np.ndarray
    mac_beam: np.ndarray
    labels: tuple[str, ...]
    modal: ModalSolution
    static_linear: StaticSolution | None
    static_nonlinear: StaticSolution | None
    version: str
    warnings: tuple[str, ...] = ()
    static_theory_gap_pct: float | None = None
    error_estimate_pct: np.ndarray | None = None
    error_estimate_level: int | None = None
    beam_gap_pct: np.ndarray | None = None
    beam_gap_cause: tuple[str, ...] = ()

    @property
    def request(self):
        """The :class:`~prbdm_pin.truth.TruthRequest` of the ``compute_truth`` call that made it.

        None for a truth read from a file or computed with a non-default ``n_computed``. A fit
        to a target made from this truth records it (``fit.json``'s ``truth_request``), so
        ``prbdm simulate/linearize --compare-truth`` ask for the same truth.
        """
        return self.__dict__.get("_request")

    @property
    def tip_position_m(self) -> np.ndarray | None:
        """Large-deflection tip position if computed, else the linear one (m)."""
        s = self.static_nonlinear or self.static_linear
        return None if s is None else s.tip_position_m

    @property
    def tip_displacement_m(self) -> np.ndarray | None:
        """Large-deflection tip displacement if computed, else the linear one (m)."""
        s = self.static_nonlinear or self.static_linear
        return None if s is None else s.tip_displacement_m
