"""The Bode figure of a plant comparison.

Magnitude and phase of the PRBDM and the truth for every compared (input, output) pair (drawn
without pyplot, see :mod:`prbdm_pin.views.plots`).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .comparison import PlantComparison

__all__ = ["plot_plant_comparison"]

# the figure starts at this fraction of the truth's first flexible frequency (log axis)
PLOT_LOW_FRACTION = 0.1


def plot_plant_comparison(cmp: PlantComparison, path: str | os.PathLike,
                          title: str = "") -> Path:
    """Write the Bode magnitude (log-log) and phase of both plants to ``path``; return the path.

    One column per input and a magnitude and a phase row per output (PNG, written atomically).
    Dotted lines mark the truth's flexible frequencies.
    """
    from ..views.plots import new_figure, save_png

    ins = list(dict.fromkeys(p.input_name for p in cmp.pairs))
    outs = list(dict.fromkeys(p.output_name for p in cmp.pairs))
    fig = new_figure((3.4 * len(ins) + 0.8, 3.6 * len(outs) + 0.8))
    grid = fig.add_gridspec(2 * len(outs), len(ins), height_ratios=[2, 1] * len(outs))
    lo = PLOT_LOW_FRACTION * float(cmp.truth_omega_rad_s[0])
    marks = cmp.truth_omega_rad_s[cmp.truth_omega_rad_s <= cmp.band_rad_s[1]]
    for p in cmp.pairs:
        r, c = outs.index(p.output_name), ins.index(p.input_name)
        keep = p.omega_rad_s >= lo
        w = p.omega_rad_s[keep]
        mag = fig.add_subplot(grid[2 * r, c])
        ph = fig.add_subplot(grid[2 * r + 1, c], sharex=mag)
        for h, style, label in ((p.frf_truth[keep], "-", "truth"),
                                (p.frf_prbdm[keep], "--", "PRBDM")):
            mag.loglog(w, np.abs(h), style, label=label)
            ph.semilogx(w, np.degrees(np.unwrap(np.angle(h))), style)
        for wk in marks:
            mag.axvline(wk, color="0.7", lw=0.6, ls=":")
        err = "-" if p.frf_error_pct is None else f"{p.frf_error_pct:.3g}%"
        mag.set_title(f"{p.input_name} -> {p.output_name}: FRF error {err}", fontsize=8)
        mag.tick_params(labelsize=7, labelbottom=False)
        ph.tick_params(labelsize=7)
        if c == 0:
            mag.set_ylabel("|H|", fontsize=8)
            ph.set_ylabel("phase (deg)", fontsize=8)
        if r == len(outs) - 1:
            ph.set_xlabel("omega (rad/s)", fontsize=8)
        if r == 0 and c == 0:
            mag.legend(fontsize=7)
    modes = ", ".join(f"{m.frequency_error_pct:+.2g}%" for m in cmp.modes)
    fig.suptitle(title or f"PRBDM against the truth plant: mode frequency errors {modes}",
                 fontsize=9)
    fig.tight_layout()
    return save_png(fig, path)
