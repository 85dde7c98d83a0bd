"""fit.json's ``modes``: one record per matched truth mode, labelled by kind.

Each record has the fixed keys ``kind``, ``omega_truth_rad_s``, ``omega_model_rad_s`` and
``error_pct`` (signed, 100 (omega_model / omega_truth - 1)); a spatial fit adds ``mac``,
the shape agreement of the pair (1 identical) where the truth has shapes. A truth mode that no
chain mode can represent (a chordwise mode in the band of a spatial fit) has a null model
frequency and error: it is named, never matched to a model mode of another kind.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["mode_record", "mode_records", "worst_record"]


def mode_record(kind: str, omega_truth_rad_s: float, omega_model_rad_s: float | None,
                mac: float | None = None) -> dict:
    """Return one record; ``omega_model_rad_s`` None for a mode no chain mode represents.

    ``mac`` (a spatial fit's pairing by shape, :mod:`prbdm_pin.fitting.mode_shapes`) adds the
    key ``mac`` when known.
    """
    w_t = float(omega_truth_rad_s)
    if omega_model_rad_s is None:
        return {"kind": str(kind), "omega_truth_rad_s": w_t, "omega_model_rad_s": None,
                "error_pct": None}
    w_m = float(omega_model_rad_s)
    out = {"kind": str(kind), "omega_truth_rad_s": w_t, "omega_model_rad_s": w_m,
           "error_pct": 100.0 * (w_m / w_t - 1.0)}
    if mac is not None and math.isfinite(mac):
        out["mac"] = float(mac)
    return out


def mode_records(kinds, omega_truth_rad_s: np.ndarray, omega_model_rad_s: np.ndarray
                 ) -> tuple[dict, ...]:
    """Return the records of matched modes: truth and model frequencies (rad/s) in pairs.

    ``kinds`` is one label per mode (None: every mode ``bending``, a planar target without
    labels).
    """
    w_t = np.asarray(omega_truth_rad_s, dtype=float)
    w_m = np.asarray(omega_model_rad_s, dtype=float).reshape(-1)[: w_t.size]
    kinds = ("bending",) * w_t.size if kinds is None else tuple(kinds)
    return tuple(mode_record(k, a, b) for k, a, b in zip(kinds, w_t, w_m, strict=True))


def worst_record(records) -> dict | None:
    """Return the matched record of the largest |error| (None when none is matched)."""
    matched = [r for r in records if r.get("error_pct") is not None
               and math.isfinite(r["error_pct"])]
    return max(matched, key=lambda r: abs(r["error_pct"]), default=None)
