"""The planar joint fit's modal-gain term: each mode's tip amplitude beside its frequency.

A frequency-only planar fit matches every frequency but not how far each mode moves the tip
(the 5R eigen fit of the uniform strip: mode 1's tip amplitude +5.4 %, so its residue a^2
+11 %; mode 2's +7.8 % and +16 %), which biases everything
that reads absolute gains: an E and rho calibrated from a tip-force FRF or a driven run, tip
FRFs for control. ``gain_points=("tip",)`` adds, for the lowest ``gain_modes`` fitted modes, the
error of the mass-normalised tip z amplitude with the residual and weights of the spatial term
(:mod:`.spatial_gains`: one formula for both chains):

    r_k = w (s_k a_model,k - a_truth,k) / (a_ref (omega_k / omega_1)^(3/2))

with a_model,k = J_tip phi_k: phi_k the chain's k-th mode at the straight pose (phi^T M phi = 1,
M in kg m^2) and J_tip the z row of the tip's Jacobian (m/rad; the chain's closed-form tip,
:mod:`prbdm_pin.chain.amplitude_derivatives`), in 1/sqrt(kg) as the truth's. A planar chain
moves its tip corners as its tip, so only ``tip`` is a planar gain point (the corners are
refused by name: their difference is the plate's torsion, which a planar chain does not have).

The amplitude rows of the Jacobian are analytic as the frequency rows (:mod:`.joint_jacobian`):
the modal expansion of each mode's derivative in the stations and springs
(:func:`prbdm_pin.chain.amplitude_derivatives.tip_amplitude_gradients`).
"""

from __future__ import annotations

import numpy as np

from ..chain.amplitude_derivatives import tip_amplitudes
from ..chain.eigen import modes_from_mass
from ..chain.planar_mass import chain_points, planar_mass_matrices
from ..chain.sections import planar_sections
from ..errors import BeamInputError
from .spatial_gains import GainsTerm, gain_records
from .spatial_target import SpatialSelection

__all__ = ["PlanarGainsTerm", "planar_gain_term", "planar_gain_records", "straight_modes"]

def _selection(target, n_freq: int) -> SpatialSelection:
    """Return the fitted truth modes as a selection of the truth's computed modes (axis y)."""
    w = np.asarray(target.omega_truth_rad_s, dtype=float)[:n_freq]
    if target.all_omega_rad_s is None:
        raise BeamInputError("gain_points: the target has no truth amplitudes (make it with "
                             "target_from_truth and with_point_gains)")
    every = np.asarray(target.all_omega_rad_s, dtype=float)
    index = np.array([int(np.argmin(np.abs(every - v))) for v in w])
    # the fitted frequencies are copies of the computed ones: equal to rounding
    if not np.allclose(every[index], w, rtol=1e-12, atol=0.0):
        raise BeamInputError("gain_points: the target's frequencies are not among its computed "
                             "modes (all_omega_rad_s)")
    labels = tuple(target.labels[:n_freq]) if target.labels else ("bending",) * w.size
    return SpatialSelection(index, w, labels, np.full(w.size, "y"))


class PlanarGainsTerm(GainsTerm):
    """The tip amplitude errors of the planar chain's fitted modes (module notes)."""

    def model_gains(self, lengths_m, modes) -> np.ndarray:
        """Return the chain's tip amplitudes (1/sqrt(kg)) of the term's modes, (N, 1).

        Parameters
        ----------
        lengths_m : ndarray, shape (n+1,)
            Link lengths, m.
        modes : ndarray, shape (n, n)
            Mass-normalised modes at the straight pose (columns, ascending), rad/sqrt(kg m^2).
        """
        return tip_amplitudes(lengths_m, modes[:, : self.sel.axis.size])[:, None][self.rows]


def planar_gain_term(target, options, n_freq: int) -> PlanarGainsTerm | None:
    """Return the planar gains term the options ask for (None without ``gain_points``)."""
    points = getattr(options, "gain_points", ())
    if not points:
        return None
    return PlanarGainsTerm(target, _selection(target, n_freq), options)


def straight_modes(M0: np.ndarray, springs_Nm_per_rad: np.ndarray) -> np.ndarray:
    """Return the mass-normalised modes (n, n) of mass matrix ``M0`` (kg m^2) and the springs."""
    return modes_from_mass(M0[None], springs_Nm_per_rad)[1][0]


def planar_gain_records(problem, lengths_m, springs_Nm_per_rad) -> tuple[dict, ...]:
    """Return one record per fitted mode of a design: tip amplitudes (1/sqrt(kg)), error (%).

    Parameters
    ----------
    problem : FitProblem
        The planar fit problem (no records without ``gain_points`` in its options).
    lengths_m : ndarray, shape (n+1,)
        Link lengths, m.
    springs_Nm_per_rad : ndarray, shape (n,)
        The exported joint springs, N m/rad.
    """
    term = planar_gain_term(problem.target, problem.options, problem.n_freq)
    if term is None:
        return ()
    L = np.asarray(lengths_m, dtype=float)
    sec = planar_sections(problem.beam, L)
    straight = np.zeros((1, L.size - 1))
    M = planar_mass_matrices(L, *sec[:3], straight, chain_points(L[None], sec[1][None], straight))
    return gain_records(term, L, straight_modes(M[0], np.asarray(springs_Nm_per_rad, float)))
