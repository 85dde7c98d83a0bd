"""A spatial fit's design and its residual terms.

The design x = [u (n), log s]: the stick-breaking link lengths of
:func:`~prbdm_pin.fitting.problem.lengths_from_unit` and the spring factors, within the planar
joint fit's bounds: ``joint`` one per spring (n len(axes)) on its finite-segment value,
``paper`` one per axis (len(axes)) on the paper's Eq. 14 closed form of that axis
(:mod:`prbdm_pin.chain.spatial_stiffness`). The residual is the
concatenation of its terms' (each an object with ``size``, ``residual(design, model)`` and
``label``): the frequencies by kind (:class:`EigenTerm`) and whatever else the options ask for.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from ..chain.eigen import eig_scaled
from ..chain.sections import link_sections_unchecked
from ..chain.spatial_stiffness import axis_stiffness, paper_axis_unit_stiffness
from ..member.geometry import Beam
from ..options.choices import StiffnessKind
from ..options.objects import FitOptions
from .problem import lengths_from_unit
from .spatial_target import SpatialSelection
from .spec import LN_S_BOUNDS

__all__ = ["LOG_FACTOR_BOUND", "EigenTerm", "SpatialDesign", "spatial_terms"]

# a spring factor stays within a factor 1e3 of the finite-segment spring of its axis, as the
# planar joint fit's (jagged panels need their bending springs far off the 1D beam's)
LOG_FACTOR_BOUND = LN_S_BOUNDS[1]


class EigenTerm:
    """Each selected truth mode's relative frequency error, omega_model / omega_truth - 1."""

    label = "eigen"

    def __init__(self, sel: SpatialSelection):
        self.sel = sel
        self.size = int(sel.omega_truth_rad_s.size)

    def residual(self, design: SpatialDesign, model) -> np.ndarray:
        """Return the relative errors (dimensionless), in the selection's order."""
        return design.frequencies(model) / self.sel.omega_truth_rad_s - 1.0


def spatial_terms(sel: SpatialSelection, target, options: FitOptions) -> tuple:
    """Return the residual terms the options ask for: the frequencies, then the others."""
    from .spatial_deflection import deflection_terms  # they build on this module's terms
    from .spatial_gains import gain_terms

    eigen = (EigenTerm(sel),) if options.objective.has_eigen_term else ()
    return eigen + deflection_terms(sel, target, options) + gain_terms(sel, target, options)


class SpatialDesign:
    """Evaluates designs of one spatial fit (beam, selection, terms and bounds fixed)."""

    def __init__(self, beam: Beam, sel: SpatialSelection, joints: int, options: FitOptions,
                 terms: tuple = ()):
        from ..model.prbdm_model import build_model  # Pinocchio loads with the first model

        self.build_model = build_model
        self.beam, self.sel, self.n, self.o = beam, sel, joints, options
        self.terms = terms or (EigenTerm(sel),)
        self.order = options.axes.joint_order
        self.m = len(self.order)
        # joint: one factor per spring; paper: one per axis on Eq. 14's closed form
        self.paper = options.stiffness is StiffnessKind.PAPER
        self.n_factors = self.m if self.paper else joints * self.m
        self.nfev = 0
        self._mass = (None, None)

    def lengths(self, u: np.ndarray) -> np.ndarray:
        """Return the link lengths (m) of the unit-box coordinates ``u`` (n,)."""
        return lengths_from_unit(u, self.beam.length_m, self.o.min_fraction)

    def unit_springs(self, lengths: np.ndarray) -> np.ndarray:
        """Return the unit-factor springs (N m/rad), node-major, shape (n m,).

        ``joint``: the finite-segment springs; ``paper``: Eq. 14's closed form on each axis.
        """
        if self.paper:
            mass = link_sections_unchecked(self.beam, lengths).mass_kg
            per_axis = [paper_axis_unit_stiffness(self.beam, lengths, mass, a)
                        for a in self.order]
        else:
            per_axis = [axis_stiffness(self.beam, lengths, a) for a in self.order]
        return np.stack(per_axis, axis=1).reshape(-1)

    def spring_factors(self, log_factors: np.ndarray) -> np.ndarray:
        """Return every spring's factor (node-major, (n m,)) from the design's log factors."""
        f = np.exp(np.asarray(log_factors, dtype=float))
        return np.tile(f, self.n) if self.paper else f

    def model(self, x: np.ndarray):
        """Return the PrbdmModel of design ``x``."""
        lengths = self.lengths(x[: self.n])
        k = self.unit_springs(lengths) * self.spring_factors(x[self.n:])
        return self.build_model(self.beam, lengths, k, min_fraction=self.o.min_fraction,
                                axes=self.o.axes)

    def mass_matrix(self, model) -> np.ndarray:
        """Return ``model``'s mass matrix at the straight pose (kg m^2), once per model.

        The terms of one residual evaluation share one model: its CRBA runs once for the
        frequencies and the shapes of every axis.
        """
        if self._mass[0] is not model:
            self._mass = (model, model.mass_matrix())
        return self._mass[1]

    def axis_modes(self, model, axis: str) -> tuple[np.ndarray, np.ndarray]:
        """Return the frequencies (rad/s) and mass-normalised shapes (nv, n) of one axis block.

        At the straight pose the axis blocks of M do not couple (``spatial_fit``'s docstring);
        a shape is zero outside its block's coordinates.
        """
        M = self.mass_matrix(model)
        k = model.stiffness_Nm_per_rad
        idx = model.axis_index(axis)
        w2, phi = scipy.linalg.eigh(np.diag(k[idx]), M[np.ix_(idx, idx)])
        shapes = np.zeros((k.size, idx.size))
        shapes[idx] = phi
        return np.sqrt(w2), shapes

    def frequencies(self, model) -> np.ndarray:
        """Return the model's frequencies (rad/s) of the selected modes, in their order."""
        M = self.mass_matrix(model)
        k = model.stiffness_Nm_per_rad
        out = np.empty(self.sel.omega_truth_rad_s.size)
        for c, a in enumerate(self.order):
            idx = np.arange(c, self.n * self.m, self.m)
            w = eig_scaled(M[np.ix_(idx, idx)], 1.0 / np.sqrt(k[idx]))
            rows = self.sel.axis == a
            out[rows] = w[: int(rows.sum())]
        return out

    def residual(self, x: np.ndarray) -> np.ndarray:
        """Return every term's residual of design ``x``, concatenated (dimensionless)."""
        self.nfev += 1
        model = self.model(x)
        return np.concatenate([t.residual(self, model) for t in self.terms])
