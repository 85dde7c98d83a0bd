"""The Bode figure of a linear plant: one magnitude and phase pair per input/output pair.

Each pair has its own axes, titled with the input and the output and labelled with the pair's
units (output unit per input unit), so pairs of different units never share an axis. Pairs
whose response is zero at every frequency are left out. Drawn without pyplot (see
:mod:`prbdm_pin.views.plots`).
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError

__all__ = ["plot_bode", "bode_band", "bode_pairs", "unit_ratio"]

# the band: a decade below the first flexible mode to 3 times the last; 800 points a band
BAND_LOW, BAND_HIGH, POINTS = 0.1, 3.0, 800


def unit_ratio(out_unit: str, in_unit: str) -> str:
    """Return the unit of an output per input: ``m/N``, ``rad/(N m)``."""
    return f"{out_unit}/({in_unit})" if " " in in_unit else f"{out_unit}/{in_unit}"


def bode_band(lin) -> np.ndarray:
    """Return the frequencies the figure draws, rad/s (log-spaced over the flexible modes)."""
    md = lin.modal()
    flex = md.omega_rad_s[md.omega_rad_s > 0.0]
    lo = BAND_LOW * float(flex.min()) if flex.size else 0.1
    hi = BAND_HIGH * float(flex.max()) if flex.size else 100.0
    return np.logspace(np.log10(lo), np.log10(hi), POINTS)


def bode_pairs(lin, H: np.ndarray) -> list[tuple[int, int]]:
    """Return the (output, input) index pairs whose response ``H`` (f, p, m) is not all zero."""
    return [(i, j) for i in range(len(lin.output_names)) for j in range(len(lin.input_names))
            if np.any(H[:, i, j])]


def plot_bode(lin, *, axes=None, path=None, title: str = ""):
    """Draw the Bode magnitude (log-log) and phase of every input/output pair; return the Figure.

    Parameters
    ----------
    lin : LinearModel
        The plant (:func:`prbdm_pin.linearize`): ``A, B, C, D``, names and units.
    axes : array of matplotlib Axes, shape (2, pairs), optional
        Row 0 the magnitudes, row 1 the phases, a column per pair with a nonzero response, in
        output-major order (default: a new figure, a column per input, a magnitude and a phase
        row per output).
    path : path-like, optional
        Also write the figure there (PNG, PDF or SVG by the suffix).
    title : str
        The figure's title (default: the plant's states and coordinates).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from .plots import figure_format, new_figure, save_figure

    if not all(hasattr(lin, a) for a in ("A", "frequency_response", "modal")):
        from ..errors import InputTypeError

        raise InputTypeError(f"lin = {lin!r:.60}: must be a prbdm_pin.LinearModel")
    if path is not None:
        figure_format(path)
    w = bode_band(lin)
    H = lin.frequency_response(w)
    pairs = bode_pairs(lin, H)
    if not pairs and axes is None:
        fig = new_figure((5.0, 2.0))
        fig.text(0.5, 0.5, "every input/output pair has a zero response", ha="center")
        if path is not None:
            save_figure(fig, path)
        return fig
    if axes is None:
        outs = sorted({i for i, _ in pairs})
        ins = sorted({j for _, j in pairs})
        fig = new_figure((3.6 * len(ins) + 0.8, 3.4 * len(outs) + 0.8))
        grid = fig.add_gridspec(2 * len(outs), len(ins), height_ratios=[2, 1] * len(outs))
        cells = []
        for i, j in pairs:
            r, c = outs.index(i), ins.index(j)
            mag = fig.add_subplot(grid[2 * r, c])
            cells.append((mag, fig.add_subplot(grid[2 * r + 1, c], sharex=mag)))
        own = True
    else:
        a = np.asarray(axes, dtype=object).reshape(2, -1)
        if a.shape[1] < len(pairs):
            raise BeamInputError(f"axes: {a.shape[1]} pairs given for {len(pairs)} input/output "
                                 "pairs; give one magnitude and one phase axes per pair")
        cells = list(zip(a[0], a[1], strict=False))[: len(pairs)]
        fig = cells[0][0].figure
        own = False
    for (mag, ph), (i, j) in zip(cells, pairs, strict=False):
        h = H[:, i, j]
        yu, uu = lin.output_units[i], lin.input_units[j]
        mag.loglog(w, np.abs(h), color="C0", label="|H|")
        ph.semilogx(w, np.degrees(np.unwrap(np.angle(h))), color="C0", label="phase")
        mag.set_title(f"{lin.input_names[j]} ({uu}) -> {lin.output_names[i]} ({yu})",
                      fontsize=8)
        mag.set_ylabel(f"|H| ({unit_ratio(yu, uu)})", fontsize=8)
        ph.set_ylabel("phase (deg)", fontsize=8)
        ph.set_xlabel("omega (rad/s)", fontsize=8)
        mag.tick_params(labelsize=7, labelbottom=False)
        ph.tick_params(labelsize=7)
        mag.legend(fontsize=7, loc="lower left")
        ph.legend(fontsize=7, loc="lower left")
    if own:
        n_states, nv = lin.A.shape[0], len(lin.q_eq)
        fig.suptitle(title or f"linearised PRBDM: {n_states} states ({nv} coordinates and "
                              f"their rates), {len(pairs)} input/output pairs", fontsize=9)
        fig.tight_layout()
    if path is not None:
        save_figure(fig, path)
    return fig
