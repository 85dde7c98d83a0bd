"""The spatial fit's modal-gain term: how much each mode moves the points a controller sees.

A frequency-only fit can match every frequency and still move a tip corner more or less than
the truth in a mode, so its corner-force to corner-displacement FRF is off by its residues.
This term adds, for the lowest ``gain_modes`` matched modes k of each kind (default all of
them) and every point p of ``gain_points`` (``tip``, ``tip_corner_left``,
``tip_corner_right``), the error of the mass-normalised z amplitude:

    r_kp = w (s_k a_model,kp - a_truth,kp) / (a_ref (omega_k / omega_1)^(3/2))

with a_model the chain's mode of the same kind and rank (its own axis block at the straight
pose, mass-normalised: phi^T M phi = 1 in kg m^2, so J_p phi is in 1/sqrt(kg), as the truth's
phi^T M phi = 1 in kg), s_k = +-1 the sign that aligns the two shapes over the points (a mode's
sign is arbitrary), a_ref the largest truth amplitude of the term's modes and points, omega_1
the lowest of their frequencies and w the ``gain_weight`` option.

The weight is each mode's share of the FRF: a corner's residue is a^2, and near its peak
|H|^2 ~ a^4 / ((omega_k^2 - Omega^2)^2 + (2 zeta omega_k Omega)^2), whose integral over Omega
is pi a^4 / (4 zeta omega_k^3); an amplitude error da changes the FRF's L2 norm by about
a^3 da / omega_k^(3/2) relative to the same scale. Every amplitude is held (a mode the term left
free can grow far above the truth's on a short tip link, which ruins the FRF), and the higher
modes, whose peaks weigh less, are held less. ``scripts/bench_spatial_frf.py`` compares this
with the first mode of each kind alone and with the frequency-only fit on the reference panel.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..errors import BeamInputError
from ..options.objects import FitOptions
from .spatial_target import SpatialSelection
from .target import FitTarget

__all__ = ["GainsTerm", "with_point_gains", "gain_terms", "gain_records"]


def with_point_gains(target: FitTarget, truth, beam, points=None) -> FitTarget:
    """Return ``target`` with the truth's modal amplitudes at the tip points, every mode.

    Parameters
    ----------
    target : FitTarget
        From :func:`~prbdm_pin.fitting.target.target_from_truth` of ``truth``.
    truth : TruthResult
        A plate truth (``"plate"`` or ``"plate-morley"``): its modes are recomputed once and
        read at (L, 0) and (L, +-w(L)) (:func:`prbdm_pin.truth.plant.truth_modal_gains`); or
        the 1D beam truth (``"beam"``), read at the tip alone (a planar fit's ``tip``).
    beam : Beam
    points : sequence of str, optional
        Default all three (the 1D beam: ``tip``).

    Raises
    ------
    BeamInputError
        Tip corners of a truth without a width (the 1D beam), or a truth of another beam.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 0.3], half_width_m=[0.05, 0.05], thickness_m=0.002,
    ...                tip_force_N=[0.0, 0.0, -1.0])
    >>> truth = pp.compute_truth(beam, model="plate", modes=2, mesh_level=0, error_tol_pct=None)
    >>> truth.labels[:2]
    ('bending', 'torsion')
    >>> target = pp.with_point_gains(pp.target_from_truth(truth, beam.tip_force_N), truth, beam)
    >>> gains = dict(target.point_gains)  # per mode, the tip centre's and corners' z amplitudes
    >>> left, right = gains["tip_corner_left"][1], gains["tip_corner_right"][1]  # mode 2, torsion
    >>> bool(np.isclose(left, -right)), bool(abs(gains["tip"][1]) < 1e-6 * abs(left))
    (True, True)
    """
    from ..member.geometry import Beam
    from ..options.validate import check_type
    from ..truth.plant.gains import truth_modal_gains
    from ..truth.result import TruthResult

    check_type("target", target, FitTarget)
    check_type("truth", truth, TruthResult)
    check_type("beam", beam, Beam)
    if target.all_omega_rad_s is None:
        raise BeamInputError("target: needs every truth mode (target_from_truth) for its gains")
    k = int(np.asarray(target.all_omega_rad_s).size)
    g = truth_modal_gains(truth, beam, mode_index=np.arange(k))
    values = {"tip": g.tip_z_per_sqrt_kg}
    if g.corner_per_sqrt_kg is not None:
        values.update(tip_corner_left=g.corner_per_sqrt_kg[0],
                      tip_corner_right=g.corner_per_sqrt_kg[1])
    names = tuple(values) if points is None else tuple(points)
    missing = [p for p in names if p not in values]
    if missing:
        raise BeamInputError(f"points = {list(names)}: the {truth.model!r} truth has no tip "
                             f"corners ({', '.join(missing)}); the modal gains there need "
                             "the plate truth")
    return replace(target, point_gains=tuple((p, values[p]) for p in names))


def _truth_gains(target: FitTarget, sel: SpatialSelection, points: tuple[str, ...]):
    have = dict(target.point_gains or ())
    missing = [p for p in points if p not in have]
    if missing:
        raise BeamInputError(f"gain_points = {list(points)}: the target has no truth amplitude "
                             f"at {', '.join(missing)} (with_point_gains of a computed "
                             "truth)")
    return np.stack([np.asarray(have[p])[sel.index] for p in points], axis=1)  # (N, P)


class GainsTerm:
    """Each selected mode's amplitude error at each gain point (module notes)."""

    label = "gains"

    def __init__(self, target: FitTarget, sel: SpatialSelection, options: FitOptions):
        self.points = options.gain_points
        self.sel, self.weight = sel, float(options.gain_weight)
        # the lowest gain_modes of each axis's matched modes (the selection is ascending)
        rank = np.array([np.sum(sel.axis[:k] == a) for k, a in enumerate(sel.axis)])
        keep = sel.axis.size if options.gain_modes is None else options.gain_modes
        self.rows = np.flatnonzero(rank < keep)
        self.truth = _truth_gains(target, sel, self.points)[self.rows]
        a_ref = float(np.max(np.abs(self.truth)))
        if a_ref <= 0.0:
            raise BeamInputError(f"gain_points = {list(self.points)}: no matched truth mode "
                                 "moves any of them")
        w = sel.omega_truth_rad_s[self.rows]
        self.norm = a_ref * (w / w.min()) ** 1.5  # each mode's share of the FRF (module notes)
        # the records' scale: each mode's own largest amplitude (a_ref where it is zero)
        own = np.max(np.abs(self.truth), axis=1)
        self.scale = np.where(own > 0.0, own, a_ref)
        self.size = int(self.truth.size)

    def model_gains(self, design, model) -> np.ndarray:
        """Return the chain's amplitudes (1/sqrt(kg)) of the matched modes, (N, P)."""
        J = np.stack([model.point_kinematics(p)[1][2] for p in self.points])  # (P, nv)
        out = np.empty((self.sel.axis.size, len(self.points)))
        for a in design.order:
            rows = np.flatnonzero(self.sel.axis == a)
            _, shapes = design.axis_modes(model, a)
            out[rows] = (J @ shapes[:, : rows.size]).T
        return out[self.rows]

    def signs(self, gains: np.ndarray) -> np.ndarray:
        """Return s_k = +-1, aligning each mode's model amplitudes (N, P) with the truth's."""
        return np.where(np.sum(gains * self.truth, axis=1) < 0.0, -1.0, 1.0)

    def aligned(self, design, model) -> np.ndarray:
        """Return the model's amplitudes with each mode's sign aligned to the truth's."""
        g = self.model_gains(design, model)
        return g * self.signs(g)[:, None]

    def residual(self, design, model) -> np.ndarray:
        """Return the weighted relative amplitude errors (dimensionless), (N P,)."""
        err = (self.aligned(design, model) - self.truth) / self.norm[:, None]
        return self.weight * err.ravel()


def gain_terms(sel: SpatialSelection, target: FitTarget, options: FitOptions) -> tuple:
    """Return the gains term the options ask for (none without ``gain_points``)."""
    return (GainsTerm(target, sel, options),) if options.gain_points else ()


def gain_records(term: GainsTerm, design, model) -> tuple[dict, ...]:
    """Return one record per (matched mode, point): amplitudes (1/sqrt(kg)) and error (%).

    The error is relative to the mode's largest truth amplitude over the points (the largest
    of every mode's where the mode moves none of them).
    """
    g = term.aligned(design, model)
    out = []
    for i, k in enumerate(term.rows):
        for j, p in enumerate(term.points):
            out.append({"point": p, "kind": term.sel.kind[k],
                        "omega_truth_rad_s": float(term.sel.omega_truth_rad_s[k]),
                        "truth_per_sqrt_kg": float(term.truth[i, j]),
                        "model_per_sqrt_kg": float(g[i, j]),
                        "error_pct": float(100.0 * (g[i, j] - term.truth[i, j])
                                           / term.scale[i])})
    return tuple(out)
