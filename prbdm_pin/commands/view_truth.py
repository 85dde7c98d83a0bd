"""The truth ``prbdm view`` draws beside the model: its frequencies and mode shapes, paired.

A fit.json records the truth it was fitted to (``truth_request``) and, per matched truth mode,
the model frequency it was paired with (``modes``: by kind, and by shape for a spatial fit). The
truth comes from the truth cache (computed there when absent, as ``--compare-truth`` does); its
shapes along the span are those the fit pairs by (:func:`prbdm_pin.fitting.mode_shapes.
truth_mode_shapes`), or the centreline deflection of a truth without width (the 1D beam). A
model JSON or a URDF knows only the truth frequencies its export recorded: paired in order.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["ViewTruth", "view_truth"]

# a fit record's model frequency is the chain's own, read back from JSON: equal to rounding
PAIR_RTOL = 1e-9


@dataclass(frozen=True, eq=False)
class ViewTruth:
    """What the view knows of the truth.

    Attributes
    ----------
    shapes : TruthShapes or None
        The truth frequencies (rad/s) paired with the chain's modes, with shapes when known.
    truth : TruthResult or None
        The truth itself (its VTU is written beside the model's).
    note : str
        One line saying what is drawn.
    """

    shapes: object
    truth: object
    note: str


def _pairs(omega_chain: np.ndarray, source) -> np.ndarray:
    """Return the truth frequency paired with each chain mode (rad/s; NaN: none)."""
    out = np.full(omega_chain.size, np.nan)
    records = getattr(source.fit, "modes", ()) if source.fit is not None else ()
    if records:
        for r in records:
            wm, wt = r.get("omega_model_rad_s"), r.get("omega_truth_rad_s")
            if wm is None or wt is None:
                continue
            k = int(np.argmin(np.abs(omega_chain - wm)))
            if abs(omega_chain[k] - wm) <= PAIR_RTOL * wm:
                out[k] = wt
        return out
    w = source.omega_truth_rad_s
    if w is not None:
        w = np.asarray(w, dtype=float)
        m = min(w.size, out.size)
        out[:m] = w[:m]
    return out


def view_truth(source, n_modes: int, cache_dir: str | None, use_truth: bool, quiet: bool
               ) -> ViewTruth:
    """Return the truth paired with the first ``n_modes`` chain modes of ``source.model``.

    ``use_truth`` False (``--no-truth``): nothing. A fit.json with a truth record: the truth from
    the cache with its shapes; otherwise the frequencies the file recorded, or nothing.
    """
    from ..views.chain_geometry import chain_modes
    from ..views.modes import TruthShapes

    if not use_truth:
        return ViewTruth(None, None, "truth not drawn (--no-truth)")
    omega = chain_modes(source.model, n_modes).omega_rad_s
    paired = _pairs(omega, source)
    if not np.any(np.isfinite(paired)):
        return ViewTruth(None, None, f"truth not available: {source.path} records no truth "
                                     "frequencies; the model is drawn alone")
    request = getattr(source.fit, "truth_request", None)
    if request is None or source.model.beam is None:
        return ViewTruth(TruthShapes(paired), None,
                         "truth shapes not available (the file records the truth's frequencies "
                         "only: give the fit.json for its shapes)")
    from .compare_truth import print_truth_warnings

    truth = request.compute(source.model.beam, cache_dir=cache_dir)
    print_truth_warnings(truth, quiet)
    return ViewTruth(_shapes(truth, paired), truth, f"truth: {truth.model} (mesh level "
                                                    f"{truth.mesh_level}) from the cache")


def _shapes(truth, paired: np.ndarray):
    """Return the truth shapes of the modes at the ``paired`` frequencies (rad/s), per mode."""
    from ..fitting.mode_shapes import truth_mode_shapes
    from ..views.modes import TruthShapes

    modal = truth.modal
    shapes = truth_mode_shapes(modal)
    if shapes is not None:
        x, defl, twist = shapes.stations_m, shapes.deflection, shapes.twist
    else:  # no width to twist over (the 1D beam): its centreline deflection
        x, defl, twist = modal.centerline_x_m, modal.centerline_uz, None
    rows = np.zeros((paired.size, np.size(x)))
    trows = None if twist is None else np.zeros_like(rows)
    for k, w in enumerate(paired):
        if not np.isfinite(w):
            continue
        i = int(np.argmin(np.abs(modal.omega_rad_s - w)))
        rows[k] = defl[i]
        if trows is not None:
            trows[k] = twist[i]
    return TruthShapes(paired, x, rows, trows)
