"""The Bode figure of a plant comparison.

Magnitude and phase of the PRBDM and the truth for every compared (input, output) pair, each
pair on its own axes with its units (drawn without pyplot, see :mod:`prbdm_pin.views.plots`).
"""

from __future__ import annotations

import os

import numpy as np

from .comparison import PlantComparison

__all__ = ["plot_plant_comparison"]

# the figure starts at this fraction of the truth's first flexible frequency (log axis)
PLOT_LOW_FRACTION = 0.1


def _unit(name: str, lookup) -> str:
    try:
        return lookup(name)
    except KeyError:  # a name outside the tables (a bus's): the figure says so
        return "?"


def plot_plant_comparison(cmp: PlantComparison, path: str | os.PathLike | None = None,
                          title: str = "", *, axes=None):
    """Draw the Bode magnitude (log-log) and phase of both plants; return the Figure.

    One column per input and a magnitude and a phase row per output, each pair's units in its
    title and labels; dotted lines mark the truth's flexible frequencies.

    Parameters
    ----------
    cmp : PlantComparison
    path : path-like, optional
        Also write the figure there (PNG, PDF or SVG by the suffix, atomically).
    title : str
        The figure's title (default: the mode frequency errors).
    axes : array of matplotlib Axes, shape (2, pairs), optional
        Row 0 the magnitudes, row 1 the phases, a column per compared pair in ``cmp.pairs``'
        order (default: a new figure).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..errors import BeamInputError
    from ..model.bus_outputs import bus_output_unit
    from ..model.inputs import input_unit
    from ..views.bode import unit_ratio
    from ..views.plots import figure_format, new_figure, save_figure

    if path is not None:
        figure_format(path)
    ins = list(dict.fromkeys(p.input_name for p in cmp.pairs))
    outs = list(dict.fromkeys(p.output_name for p in cmp.pairs))
    if axes is None:
        fig = new_figure((3.4 * len(ins) + 0.8, 3.6 * len(outs) + 0.8))
        grid = fig.add_gridspec(2 * len(outs), len(ins), height_ratios=[2, 1] * len(outs))
        cells = []
        for p in cmp.pairs:
            r, c = outs.index(p.output_name), ins.index(p.input_name)
            mag = fig.add_subplot(grid[2 * r, c])
            cells.append((mag, fig.add_subplot(grid[2 * r + 1, c], sharex=mag)))
    else:
        a = np.asarray(axes, dtype=object).reshape(2, -1)
        if a.shape[1] < len(cmp.pairs):
            raise BeamInputError(f"axes: {a.shape[1]} pairs given for {len(cmp.pairs)} "
                                 "compared pairs; give a magnitude and a phase axes per pair")
        cells = list(zip(a[0], a[1], strict=False))
        fig = cells[0][0].figure
    lo = PLOT_LOW_FRACTION * float(cmp.truth_omega_rad_s[0])
    marks = cmp.truth_omega_rad_s[cmp.truth_omega_rad_s <= cmp.band_rad_s[1]]
    for (mag, ph), p in zip(cells, cmp.pairs, strict=False):
        keep = p.omega_rad_s >= lo
        w = p.omega_rad_s[keep]
        uu = _unit(p.input_name, input_unit)
        yu = _unit(p.output_name, bus_output_unit)
        for h, style, label in ((p.frf_truth[keep], "-", "truth"),
                                (p.frf_prbdm[keep], "--", "PRBDM")):
            mag.loglog(w, np.abs(h), style, label=label)
            ph.semilogx(w, np.degrees(np.unwrap(np.angle(h))), style, label=label)
        for wk in marks:
            mag.axvline(wk, color="0.7", lw=0.6, ls=":")
        err = "-" if p.frf_error_pct is None else f"{p.frf_error_pct:.3g}%"
        mag.set_title(f"{p.input_name} ({uu}) -> {p.output_name} ({yu}): FRF error {err}",
                      fontsize=8)
        mag.tick_params(labelsize=7, labelbottom=False)
        ph.tick_params(labelsize=7)
        mag.set_ylabel(f"|H| ({unit_ratio(yu, uu)})", fontsize=8)
        ph.set_ylabel("phase (deg)", fontsize=8)
        ph.set_xlabel("omega (rad/s)", fontsize=8)
        mag.legend(fontsize=7)
        ph.legend(fontsize=7)
    if axes is None:
        modes = ", ".join(f"{m.frequency_error_pct:+.2g}%" for m in cmp.modes)
        fig.suptitle(title or f"PRBDM against the truth plant: mode frequency errors {modes}",
                     fontsize=9)
        fig.tight_layout()
    if path is not None:
        save_figure(fig, path)
    return fig
