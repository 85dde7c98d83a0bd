"""A PRBDM plant against the finite-element truth of the same plant (``compare_plant``).

The comparison goes input/output pair by pair and mode by mode.

What is compared, for every (input, output) pair both plants have:

- the FRF over the band [omega_lo, omega_hi], omega_hi = BAND_FACTOR omega_n (omega_n: the
  truth's n-th flexible frequency, n the PRBDM's flexible modes): its relative L2 error
  (complex and magnitude), integrated over frequency. A hub plant's rigid-body mode makes the
  FRF singular at 0, so its band starts at omega_lo = LOW_FRACTION omega_1; its flexible part
  (the rigid-body mode's 1/s^2 term subtracted, finite at 0) is compared over [0, omega_hi] too;
- the peak magnitude at each resonance (a mode the pair does not see has none);
- the response to a unit step of the input from rest over HORIZON_PERIODS periods of the
  truth's first flexible mode: relative L2, peak and largest-deviation errors. A hub under a
  torque step turns without bound; there the flexible part is compared (the response with the
  rigid-body rotation's subtracted, i.e. seen from the mean rotation of the whole plant), and
  the rigid-body gain (the 1/s^2 or 1/s coefficient: torque arm over the total inertia) is
  reported as its own error;
- per flexible mode: the signed frequency error 100 (omega_prbdm / omega_truth - 1) and each
  side's modal damping ratio.

Damping: both sides should give every flexible mode of the coupled plant the same ratio (the
PRBDM's ``damping="modal"``, the truth's ``hybrid_model(..., damping="modal")``): the truth's
default damps its clamped modes instead, which gives the hub-stiffened modes other ratios and
so other peak heights. The comparison reports both sides' ratios and notes where they differ.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import BeamInputError
from .comparison_metrics import frequency_grid, peak, relative_l2_band, step_errors
from .second_order import SecondOrderPlant, second_order

__all__ = ["BAND_FACTOR", "HORIZON_PERIODS", "LOW_FRACTION", "ModeComparison",
           "PairComparison", "PlantComparison", "compare_plant"]

BAND_FACTOR = 1.2
LOW_FRACTION = 0.1
HORIZON_PERIODS = 10.0
# step samples per period of the band's top frequency, and their cap
SAMPLES_PER_PERIOD, MAX_STEP_SAMPLES = 20, 20001
# damping ratios of the two sides count as equal within this relative difference
DAMPING_MATCH = 1e-6


@dataclass(frozen=True)
class ModeComparison:
    """Flexible mode k (1-based) of both plants: frequencies rad/s, signed error %, ratios."""

    mode: int
    omega_truth_rad_s: float
    omega_prbdm_rad_s: float
    frequency_error_pct: float
    damping_ratio_truth: float
    damping_ratio_prbdm: float


@dataclass(frozen=True, eq=False)
class PairComparison:
    """The comparison of one (input, output) pair.

    Errors in % (None where the truth's response is zero); peaks per flexible mode as
    (omega rad/s, ``|H|``) or None (no resonance peak in this pair).

    ``frf_flexible_error_pct`` and ``rigid_gain_error_pct`` are for hub plants (None
    otherwise). The curves: ``omega_rad_s`` with the complex FRFs (output unit per input unit),
    ``t_s`` with the step responses (flexible part on a hub plant).
    """

    input_name: str
    output_name: str
    frf_error_pct: float | None
    frf_magnitude_error_pct: float | None
    frf_flexible_error_pct: float | None
    peaks_truth: tuple[tuple[float, float] | None, ...]
    peaks_prbdm: tuple[tuple[float, float] | None, ...]
    step_error_pct: float | None
    step_peak_error_pct: float | None
    step_max_deviation_pct: float | None
    rigid_gain_error_pct: float | None
    omega_rad_s: np.ndarray = field(repr=False)
    frf_truth: np.ndarray = field(repr=False)
    frf_prbdm: np.ndarray = field(repr=False)
    t_s: np.ndarray = field(repr=False)
    step_truth: np.ndarray = field(repr=False)
    step_prbdm: np.ndarray = field(repr=False)

    @property
    def peak_errors_pct(self) -> tuple[float | None, ...]:
        """``100 (|H_prbdm| / |H_truth| - 1)`` at each mode's peak, None where either has none."""
        return tuple(None if a is None or b is None else 100.0 * (b[1] / a[1] - 1.0)
                     for a, b in zip(self.peaks_truth, self.peaks_prbdm, strict=True))


@dataclass(frozen=True, eq=False)
class PlantComparison:
    """A PRBDM plant against the truth plant (see the module notes for the measures).

    Attributes
    ----------
    hub : bool
    modes : tuple of ModeComparison
        The PRBDM's n flexible modes against the truth's first n.
    truth_omega_rad_s : ndarray
        Every flexible frequency of the truth plant, rad/s.
    band_rad_s : (float, float)
        The FRF band (starting at LOW_FRACTION omega_1 on a hub plant).
    horizon_s : float
        The step responses' horizon, s.
    pairs : tuple of PairComparison
    not_compared : tuple of (name, kind, reason)
        The PRBDM's inputs and outputs the truth plant does not have.
    notes : tuple of str

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -100.0])
    >>> truth = pp.compute_truth(beam, model="beam", modes=2)
    >>> target = pp.target_from_truth(truth, beam.tip_force_N)
    >>> result = pp.fit(beam, target, 2, objective="eigen", stiffness="joint", starts=1,
    ...                 progress=False)
    >>> model = pp.build_model(beam, result.lengths_m, result.stiffness_Nm_per_rad)
    >>> from prbdm_pin.truth.plant import clamped_model
    >>> truth_plant = clamped_model(truth, beam, damping_ratio=0.02)
    >>> comparison = pp.compare_plant(pp.linearize(model), truth_plant)
    >>> isinstance(comparison, pp.PlantComparison)
    True
    >>> [(pair.input_name, pair.output_name) for pair in comparison.pairs]
    [('tip_force_z', 'tip_z')]
    """

    hub: bool
    modes: tuple[ModeComparison, ...]
    truth_omega_rad_s: np.ndarray
    band_rad_s: tuple[float, float]
    horizon_s: float
    pairs: tuple[PairComparison, ...]
    not_compared: tuple[tuple[str, str, str], ...]
    notes: tuple[str, ...]

    def pair(self, input_name: str, output_name: str) -> PairComparison:
        """Return the comparison of one pair; BeamInputError when it was not compared."""
        for p in self.pairs:
            if (p.input_name, p.output_name) == (input_name, output_name):
                return p
        raise BeamInputError(f"pair ({input_name}, {output_name}): not compared")


def _prbdm_unloaded(prbdm) -> None:
    q = np.asarray(getattr(prbdm, "q_eq", np.zeros(1)))
    u = np.asarray(getattr(prbdm, "u_eq", np.zeros(1)))
    if np.any(q) or np.any(u):
        raise BeamInputError("prbdm: linearised about a loaded pose (q_eq or u_eq is not zero); "
                             "the truth plant is the unloaded straight beam")


def _names(p: SecondOrderPlant, t: SecondOrderPlant):
    ins = [n for n in p.input_names if n in t.input_names]
    outs = [n for n in p.output_names if n in t.output_names]
    skipped = tuple((n, "input", "the truth plant has no such input")
                    for n in p.input_names if n not in t.input_names) + tuple(
        (n, "output", "the truth plant has no such output")
        for n in p.output_names if n not in t.output_names)
    if not ins or not outs:
        raise BeamInputError(f"prbdm: no input/output pair the truth plant has too (inputs "
                             f"{list(t.input_names)}, outputs {list(t.output_names)})")
    return ins, outs, skipped


def compare_plant(prbdm, truth, omega_max_rad_s: float | None = None, n_points: int = 2001,
                  horizon_s: float | None = None) -> PlantComparison:
    """Compare a PRBDM plant with the truth of the same plant, pair by pair and mode by mode.

    Parameters
    ----------
    prbdm : LinearModel
        ``prbdm_pin.linearize`` of the PRBDM, unloaded at the straight pose, with or without hub.
    truth : HybridModel or ClampedModel
        The truth plant with the same hub and actuators (``strain[i]`` must be the same patch on
        both sides: the names are matched, the stations cannot be checked here).
    omega_max_rad_s : float, optional
        Top of the FRF band, rad/s (default BAND_FACTOR times the truth's n-th flexible
        frequency).
    n_points : int
        Uniform points over the band, besides those clustered at the poles.
    horizon_s : float, optional
        Step-response horizon, s (default HORIZON_PERIODS periods of the truth's first flexible
        mode).

    Returns
    -------
    PlantComparison

    Raises
    ------
    BeamInputError
        A loaded PRBDM, a hub on one side only, no common pair, an undamped flexible mode, fewer
        truth modes than PRBDM modes, or a bad band or horizon.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -100.0])
    >>> truth = pp.compute_truth(beam, model="beam", modes=2)
    >>> target = pp.target_from_truth(truth, beam.tip_force_N)
    >>> result = pp.fit(beam, target, 2, objective="eigen", stiffness="joint", starts=1,
    ...                 progress=False)
    >>> model = pp.build_model(beam, result.lengths_m, result.stiffness_Nm_per_rad)
    >>> from prbdm_pin.truth.plant import clamped_model
    >>> lin = pp.linearize(model, damping_ratio=0.02)
    >>> comparison = pp.compare_plant(lin, clamped_model(truth, beam, damping_ratio=0.02))
    >>> [round(m.frequency_error_pct, 3) for m in comparison.modes]
    [0.0, 0.0]
    """
    _prbdm_unloaded(prbdm)
    p, t = second_order(prbdm, "prbdm"), second_order(truth, "truth")
    if bool(p.rigid) != bool(t.rigid):
        raise BeamInputError(f"truth: {'has' if t.rigid else 'has no'} rigid-body mode while the "
                             f"prbdm {'has' if p.rigid else 'has no'} one: compare plants with "
                             "the same hub (or both clamped)")
    ins, outs, skipped = _names(p, t)
    wp, zp = p.modes()
    wt, zt = t.modes()
    n = wp.size
    if wt.size < n:
        raise BeamInputError(f"truth: has {wt.size} flexible modes, fewer than the prbdm's {n}")
    if np.any(zp <= 0.0) or np.any(zt[:n] <= 0.0):
        raise BeamInputError("prbdm, truth: every flexible mode needs damping (ratio > 0) for "
                             "finite resonance peaks")
    hi = BAND_FACTOR * float(wt[n - 1]) if omega_max_rad_s is None else float(omega_max_rad_s)
    lo = LOW_FRACTION * float(wt[0]) if p.rigid else 0.0
    if not (np.isfinite(hi) and hi > lo):
        raise BeamInputError(f"omega_max_rad_s = {omega_max_rad_s!r}: must be > {lo:g} rad/s")
    if isinstance(n_points, bool) or not isinstance(n_points, (int, np.integer)) or n_points < 2:
        raise BeamInputError(f"n_points = {n_points!r}: must be an integer >= 2")
    T = HORIZON_PERIODS * 2.0 * np.pi / float(wt[0]) if horizon_s is None else horizon_s
    if isinstance(T, bool) or not isinstance(T, (int, float)) or not (np.isfinite(T) and T > 0):
        raise BeamInputError(f"horizon_s = {horizon_s!r}: must be a time > 0 (s)")

    poles = [(float(w), float(z)) for w, z in zip(np.concatenate([wt, wp]),
                                                  np.concatenate([zt, zp]), strict=True)
             if w <= hi]
    grid = frequency_grid(0.0, hi, n_points, poles)
    if p.rigid and lo not in grid:
        grid = np.union1d(grid, [lo])
    band = grid >= lo
    samples = int(min(MAX_STEP_SAMPLES, np.ceil(T * hi / (2.0 * np.pi) * SAMPLES_PER_PERIOD) + 1))
    ts = np.linspace(0.0, T, samples)
    sides = (_Side(p, outs, ins, grid, ts), _Side(t, outs, ins, grid, ts))

    pairs = []
    for a, o in enumerate(outs):
        for b, i in enumerate(ins):
            sp, st = (side.pair(a, b) for side in sides)
            peaks_t = tuple(peak(st.response, float(wt[k]), float(zt[k]), wt) for k in range(n))
            peaks_p = tuple(peak(sp.response, float(wp[k]), float(zp[k]), wp) for k in range(n))
            frf = relative_l2_band(sp.frf[band], st.frf[band], grid[band])
            mag = relative_l2_band(np.abs(sp.frf[band]), np.abs(st.frf[band]), grid[band])
            flex = relative_l2_band(sp.frf_flexible, st.frf_flexible, grid) if p.rigid else None
            rigid = None
            if p.rigid and st.rigid_gain != 0.0:
                rigid = 100.0 * (sp.rigid_gain / st.rigid_gain - 1.0)
            pairs.append(PairComparison(
                i, o, _pct(frf), _pct(mag), _pct(flex), peaks_t, peaks_p,
                **step_errors(sp.step, st.step), rigid_gain_error_pct=rigid,
                omega_rad_s=grid[band], frf_truth=st.frf[band], frf_prbdm=sp.frf[band],
                t_s=ts, step_truth=st.step, step_prbdm=sp.step))
    modes = tuple(ModeComparison(k + 1, float(wt[k]), float(wp[k]),
                                 100.0 * (float(wp[k]) / float(wt[k]) - 1.0), float(zt[k]),
                                 float(zp[k])) for k in range(n))
    return PlantComparison(bool(p.rigid), modes, wt, (lo, hi), float(T), tuple(pairs), skipped,
                           _notes(wp, zp, wt, zt, hi))


def _pct(x: float | None) -> float | None:
    return None if x is None else 100.0 * x


def _notes(wp, zp, wt, zt, hi) -> tuple[str, ...]:
    n = wp.size
    notes = []
    dz = np.abs(zp / zt[:n] - 1.0)
    k = int(np.argmax(dz))
    if dz[k] > DAMPING_MATCH:
        notes.append(f"damping ratios differ (mode {k + 1}: truth {zt[k]:.4g}, prbdm "
                     f"{zp[k]:.4g}): the peak heights differ for that reason too")
    extra = wt[n:][wt[n:] <= hi]
    if extra.size:
        notes.append(f"truth modes above the prbdm's {n} inside the band at "
                     f"{', '.join(f'{w:.4g}' for w in extra)} rad/s")
    return tuple(notes)


@dataclass(frozen=True, eq=False)
class _PairCurves:
    frf: np.ndarray
    frf_flexible: np.ndarray
    step: np.ndarray
    rigid_gain: float
    response: object  # w (rad/s) -> complex H(w), for the peak search


class _Side:
    """Return one plant's responses on the common grid and horizon.

    Its rows and columns are picked by the compared names.
    """

    def __init__(self, plant: SecondOrderPlant, outs, ins, grid, ts):
        self.rows = [plant.output_names.index(o) for o in outs]
        self.cols = [plant.input_names.index(i) for i in ins]
        self.flex = plant.flexible()
        self.gains = [g[np.ix_(self.rows, self.cols)] for g in plant.rigid_gains()]
        self.frf_flexible = self._pick(self.flex.frequency_response(grid))
        self.frf = self.frf_flexible + self._rigid(grid, slice(None), slice(None))
        self.step = self._pick(self.flex.step_response(ts))

    def _pick(self, a: np.ndarray) -> np.ndarray:
        return a[:, self.rows][:, :, self.cols]

    def _rigid(self, w: np.ndarray, a, b) -> np.ndarray:
        s = 1j * np.asarray(w, dtype=float)[:, None, None]
        g0, g1 = self.gains[0][a, b], self.gains[1][a, b]
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(s != 0.0, (g0 + s * g1) / s**2, 0.0)

    def pair(self, a: int, b: int) -> _PairCurves:
        row, col = self.rows[a], self.cols[b]

        def response(w):
            h = self.flex.frequency_response(w)[:, row, col]
            return h + self._rigid(w, slice(a, a + 1), slice(b, b + 1))[:, 0, 0]

        return _PairCurves(self.frf[:, a, b], self.frf_flexible[:, a, b], self.step[:, a, b],
                           float(self.gains[0][a, b] + self.gains[1][a, b]), response)
