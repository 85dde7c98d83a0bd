"""The measures of a plant comparison.

The frequency grid, relative L2 errors over it, resonance peaks, and the step-response errors.

The grid is uniform over the band plus, around every flexible pole of either plant, points
spaced a tenth of the half-power half-width zeta omega over +-10 zeta omega, so every
resonance peak is resolved; the L2 errors integrate over frequency (trapezoids), so that this
clustering does not weight the peaks more than the band's measure does.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize_scalar

__all__ = ["PEAK_WINDOW", "frequency_grid", "peak", "relative_l2_band", "step_errors"]

# poles are resolved over +-POLE_SPAN zeta omega in steps of zeta omega / POLE_STEPS
POLE_SPAN, POLE_STEPS = 10.0, 10
# a resonance peak is looked for within omega (1 +- PEAK_WINDOW zeta), at most +-MAX_WINDOW
PEAK_WINDOW, MAX_WINDOW = 5.0, 0.3


def frequency_grid(lo_rad_s: float, hi_rad_s: float, n_points: int,
                   poles: list[tuple[float, float]]) -> np.ndarray:
    """Return sorted unique frequencies (rad/s) in [lo, hi].

    ``n_points`` uniform ones plus the clusters around ``poles`` ((omega rad/s, zeta) pairs).
    """
    parts = [np.linspace(lo_rad_s, hi_rad_s, n_points)]
    s = np.linspace(-POLE_SPAN, POLE_SPAN, 2 * int(POLE_SPAN) * POLE_STEPS + 1)
    for w, z in poles:
        parts.append(w * (1.0 + max(z, 1e-4) * s))
    g = np.unique(np.concatenate(parts))
    return g[(g >= lo_rad_s) & (g <= hi_rad_s)]


def relative_l2_band(a: np.ndarray, ref: np.ndarray, w: np.ndarray) -> float | None:
    """Return the relative L2 error of ``a`` against ``ref`` over the grid ``w``, a fraction.

    ``sqrt(int |a - ref|^2 dw / int |ref|^2 dw)`` by trapezoids; None where ``ref`` is zero.
    """
    den = np.trapezoid(np.abs(ref) ** 2, w)
    if not den > 0.0:
        return None
    return float(np.sqrt(np.trapezoid(np.abs(a - ref) ** 2, w) / den))


def peak(response, omega_rad_s: float, zeta: float, neighbours: np.ndarray
         ) -> tuple[float, float] | None:
    """Return the resonance peak (frequency rad/s, ``|H|``) of ``response`` near a mode.

    ``response(w)`` returns a complex array; the mode is at ``omega_rad_s`` with ratio
    ``zeta``. None when ``|H|`` has no local maximum there (a mode the pair does not see). The
    window is omega (1 +- PEAK_WINDOW zeta), at most +-MAX_WINDOW and at most half-way to the
    ``neighbours`` (the plant's other modes).
    """
    half = min(PEAK_WINDOW * max(zeta, 1e-4), MAX_WINDOW)
    others = neighbours[neighbours != omega_rad_s]
    if others.size:
        half = min(half, 0.5 * float(np.min(np.abs(others / omega_rad_s - 1.0))))
    w = omega_rad_s * (1.0 + np.linspace(-half, half, 401))
    mag = np.abs(response(w))
    i = int(np.argmax(mag))
    if i in (0, w.size - 1) or not np.isfinite(mag[i]):
        return None
    res = minimize_scalar(lambda x: -float(np.abs(response(np.array([x]))[0])),
                          bounds=(w[i - 1], w[i + 1]), method="bounded",
                          options={"xatol": 1e-12 * omega_rad_s})
    x = float(res.x) if -res.fun >= mag[i] else float(w[i])
    return x, float(np.abs(response(np.array([x]))[0]))


def step_errors(y: np.ndarray, ref: np.ndarray) -> dict[str, float | None]:
    """Return the errors of a sampled response ``y`` against ``ref`` (uniform samples), in %.

    ``step_error_pct`` = ``100 ||y - ref|| / ||ref||``, ``step_peak_error_pct`` =
    ``100 (max|y| / max|ref| - 1)`` (signed: the peak's over- or under-estimate),
    ``step_max_deviation_pct`` = ``100 max|y - ref| / max|ref|``; None where ``ref`` is zero.
    """
    top = float(np.max(np.abs(ref)))
    if not top > 0.0:
        return {"step_error_pct": None, "step_peak_error_pct": None,
                "step_max_deviation_pct": None}
    return {
        "step_error_pct": 100.0 * float(np.linalg.norm(y - ref) / np.linalg.norm(ref)),
        "step_peak_error_pct": 100.0 * (float(np.max(np.abs(y))) / top - 1.0),
        "step_max_deviation_pct": 100.0 * float(np.max(np.abs(y - ref))) / top,
    }
