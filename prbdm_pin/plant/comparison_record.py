"""A plant comparison as JSON (per mode, per pair) and as short summary lines."""

from __future__ import annotations

from typing import Any

from .comparison import (
    BAND_FACTOR,
    HORIZON_PERIODS,
    LOW_FRACTION,
    PlantComparison,
)

__all__ = ["comparison_dict", "comparison_summary"]


def _peak(p: tuple[float, float] | None) -> dict[str, float] | None:
    return None if p is None else {"omega_rad_s": p[0], "magnitude": p[1]}


def comparison_dict(cmp: PlantComparison) -> dict[str, Any]:
    """Return the JSON form of ``cmp``.

    Errors in % (null where the truth's response is zero or a mode has no resonance peak in a
    pair), frequencies in rad/s, magnitudes in output unit per input unit.
    """
    lo, hi = cmp.band_rad_s
    return {
        "hub": cmp.hub,
        "truth_flexible_modes": int(cmp.truth_omega_rad_s.size),
        "truth_omega_rad_s": [float(w) for w in cmp.truth_omega_rad_s],
        "frf_band_rad_s": [lo, hi],
        "frf_band": (f"[{LOW_FRACTION:g} omega_1, {BAND_FACTOR:g} omega_n] of the truth (the "
                     "rigid-body mode makes the FRF singular at 0); the flexible part "
                     "(rigid-body term subtracted) over [0, the same top]" if cmp.hub else
                     f"[0, {BAND_FACTOR:g} omega_n] of the truth"),
        "frf_error": "relative L2 over frequency, of the complex FRF and of its magnitude",
        "step_horizon_s": cmp.horizon_s,
        "step": (f"unit step of each input from rest over {HORIZON_PERIODS:g} periods of the "
                 "truth's first flexible mode" + ("; the flexible part (the rigid-body "
                                                  "rotation's response subtracted)"
                                                  if cmp.hub else "")),
        "modes": [
            {"mode": m.mode, "omega_truth_rad_s": m.omega_truth_rad_s,
             "omega_prbdm_rad_s": m.omega_prbdm_rad_s,
             "frequency_error_pct": m.frequency_error_pct,
             "damping_ratio_truth": m.damping_ratio_truth,
             "damping_ratio_prbdm": m.damping_ratio_prbdm}
            for m in cmp.modes
        ],
        "pairs": [
            {"input": p.input_name, "output": p.output_name,
             "frf_error_pct": p.frf_error_pct,
             "frf_magnitude_error_pct": p.frf_magnitude_error_pct,
             "frf_flexible_error_pct": p.frf_flexible_error_pct,
             "peaks": [{"mode": k + 1, "truth": _peak(a), "prbdm": _peak(b),
                        "error_pct": e}
                       for k, (a, b, e) in enumerate(zip(p.peaks_truth, p.peaks_prbdm,
                                                         p.peak_errors_pct, strict=True))],
             "step_error_pct": p.step_error_pct,
             "step_peak_error_pct": p.step_peak_error_pct,
             "step_max_deviation_pct": p.step_max_deviation_pct,
             "rigid_gain_error_pct": p.rigid_gain_error_pct}
            for p in cmp.pairs
        ],
        "not_compared": [{"name": n, "kind": k, "reason": r} for n, k, r in cmp.not_compared],
        "notes": list(cmp.notes),
    }


def _fmt(x: float | None, signed: bool = False) -> str:
    if x is None:
        return "-"
    return f"{x:+.3g}%" if signed else f"{x:.3g}%"


def comparison_summary(cmp: PlantComparison) -> list[str]:
    """One line for the modes, one per pair, one for what was not compared, the notes."""
    lines = ["modes (prbdm vs truth): " + ", ".join(
        f"{m.mode}: {m.omega_prbdm_rad_s:.4g} vs {m.omega_truth_rad_s:.4g} rad/s "
        f"({m.frequency_error_pct:+.3g}%)" for m in cmp.modes)]
    for p in cmp.pairs:
        peaks = " ".join(_fmt(e, signed=True) for e in p.peak_errors_pct)
        flex = f" (flexible {_fmt(p.frf_flexible_error_pct)})" if cmp.hub else ""
        lines.append(f"{p.input_name} -> {p.output_name}: FRF {_fmt(p.frf_error_pct)}{flex}, "
                     f"peaks [{peaks}], step {_fmt(p.step_error_pct)} (peak "
                     f"{_fmt(p.step_peak_error_pct, signed=True)})")
    if cmp.not_compared:
        lines.append("not compared (the truth plant has no such signal): "
                     + ", ".join(f"{k} {n}" for n, k, _ in cmp.not_compared))
    lines += [f"note: {n}" for n in cmp.notes]
    return lines
