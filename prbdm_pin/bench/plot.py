"""The error-against-cost figure of a benchmark run, drawn with :mod:`prbdm_pin.views.plots`."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .config import BenchResult
from .report import frontier_mask, plot_modes, summary_points

__all__ = ["plot_error_vs_cost"]


def plot_error_vs_cost(result: BenchResult, path: str | Path | None = None, *, axes=None):
    """Plot error against simulation cost (log-log); return the Figure.

    One panel per k (first k modes), frontier marked; a last panel shows the FE truth levels
    (modal-solve CPU against error vs the finest level).

    Parameters
    ----------
    result : BenchResult
    path : path-like, optional
        Also write the figure there (PNG, PDF or SVG by the suffix, atomically).
    axes : sequence of matplotlib Axes, optional
        One per panel (default: a new figure with a grid of them).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..errors import BeamInputError
    from ..views.plots import figure_format, new_figure, save_figure, save_png

    if path is not None:
        figure_format(path)
    ks = plot_modes(result)
    fe = [t for t in result.truths if t.errors_pct is not None]
    panels = len(ks) + (1 if fe else 0)
    if axes is None:
        ncol = min(panels, 3)  # a grid, so that the figure stays readable at any k
        nrow = -(-panels // ncol)
        fig = new_figure((4.6 * ncol, 3.9 * nrow))
        axes = fig.subplots(nrow, ncol, squeeze=False).ravel()
        own = True
    else:
        axes = np.ravel(axes)
        if axes.size < panels:
            raise BeamInputError(f"axes: {axes.size} given for {panels} panels; give one per "
                                 "panel")
        fig, own = axes[0].figure, False
    for ax in axes[panels:]:
        ax.set_visible(False)
    style = {"fitted": ("o", "C0"), "chain": ("s", "C1"), "MuJoCo": ("^", "C2")}
    for ax, k in zip(axes, ks, strict=False):
        pts = summary_points(result, k)
        cost = np.array([p[1] for p in pts])
        err = np.maximum(np.array([p[2] for p in pts]), 1e-10)
        mask = frontier_mask(cost, err)
        for (label, c, e) in zip([p[0] for p in pts], cost, err, strict=True):
            mk, col = style[label.split()[0]]
            ax.loglog(c, e, mk, color=col, ms=6)
            ax.annotate(label.split()[-1], (c, e), fontsize=7, xytext=(3, 3),
                        textcoords="offset points")
        order = np.argsort(cost[mask])
        ax.loglog(cost[mask][order], err[mask][order], "k--", lw=1, label="frontier")
        for kind, (mk, col) in style.items():
            ax.plot([], [], mk, color=col, label=kind)
        ax.set_xlabel("CPU s per simulated s")
        ax.set_ylabel(f"max freq. error, first {k} modes (%)")
        ax.set_title(f"first {k} modes (worst over beams)")
        ax.legend(fontsize=7)
        ax.grid(True, which="both", alpha=0.3)
    if fe:
        ax = axes[panels - 1]
        for t in fe:
            ax.loglog(t.cpu_s, max(float(np.max(np.abs(t.errors_pct))), 1e-10), "d", color="C0")
            ax.annotate(f"{t.beam} L{t.level}", (t.cpu_s, float(np.max(np.abs(t.errors_pct)))),
                        fontsize=7)
        ax.set_xlabel("modal solve CPU s")
        ax.set_ylabel("max error vs finest level (%)")
        ax.set_title("FE truth (plate)")
        ax.grid(True, which="both", alpha=0.3)
        ax.plot([], [], "d", color="C0", label="FE truth level")
        ax.legend(fontsize=7)
    if own:
        fig.tight_layout()
    if path is not None and own:
        save_figure(fig, path)
    elif path is not None:  # a caller's figure is written whole, cropped
        save_png(fig, path, bbox_inches="tight")
    return fig
