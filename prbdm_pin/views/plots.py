"""Figures of a fit and of a simulation.

The planform with its links and joints (paper Figs. 5, 7, 9, 12), SCF against joint angle
(Figs. 8, 10), the Pareto front with its knee (Fig. 11); a simulated response is drawn by
:mod:`prbdm_pin.views.response_plot`. Every function draws into the axes it is given (``ax=``)
or a new figure, writes it when given a path (PNG, PDF or SVG by the suffix, atomically) and
returns the Figure.

matplotlib is imported lazily and without pyplot: each figure is a ``Figure`` on its own Agg
canvas, so no backend is chosen and no figure manager holds it.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

from ..errors import BeamInputError
from ..io.atomic import atomic_path
from ..options.choices import MIN_FRACTION

__all__ = ["plot_planform", "plot_scf", "plot_pareto", "new_figure", "pyplot",
           "save_figure", "save_png", "figure_format", "FIGURE_FORMATS", "own_axes"]

DPI = 120


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def new_figure(figsize_in: tuple[float, float], dpi: float = DPI):
    """Make a matplotlib Figure of ``figsize_in`` (width, height; inches) on its own Agg canvas.

    Neither pyplot nor a backend is loaded: the figure is not managed by any window manager,
    so nothing needs closing and no display is looked for. ``dpi`` is the figure's own
    resolution (dots per inch), at which ``tight_layout`` measures its text; ``save_png``
    writes at ``DPI`` whatever it is.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize_in, dpi=dpi)
    FigureCanvasAgg(fig)
    return fig


# the formats a figure is written in, by the path's suffix
FIGURE_FORMATS = ("png", "pdf", "svg")


def figure_format(path: str | os.PathLike) -> str:
    """Return the format of a figure file by its suffix: ``png``, ``pdf`` or ``svg``.

    Raises
    ------
    BeamInputError
        Another suffix (naming the path and the formats).
    """
    fmt = Path(path).suffix.lower().lstrip(".")
    if fmt not in FIGURE_FORMATS:
        raise BeamInputError(f"path = {str(path)!r}: a figure is written as "
                             f"{', '.join('.' + f for f in FIGURE_FORMATS)} (by the suffix)")
    return fmt


def save_png(fig, path: str | os.PathLike, bbox_inches: str | None = None) -> Path:
    """Write ``fig`` (``DPI``) to ``path`` atomically; the figure stays open.

    PNG, PDF or SVG by the suffix (:func:`figure_format`). ``bbox_inches="tight"`` trims the
    margins; the default keeps the figure's own size.
    """
    p = Path(path)
    fmt = figure_format(p)
    with atomic_path(p) as tmp:
        fig.savefig(tmp, format=fmt, dpi=DPI, bbox_inches=bbox_inches)
    return p


def save_figure(fig, path: str | os.PathLike) -> Path:
    """Write ``fig`` (``DPI``) cropped to its artists to ``path`` atomically.

    PNG, PDF or SVG by the suffix (:func:`figure_format`). The crop is that of
    ``bbox_inches="tight"``; a pyplot figure is closed.
    """
    import matplotlib

    p = Path(path)
    fmt = figure_format(p)
    try:
        # "tight" lays the figure out in a dry-run draw before the real one; the tight box
        # measured with the canvas's renderer, without that draw, is the same box
        fig.set_dpi(DPI)
        bbox = fig.get_tightbbox(fig.canvas.get_renderer())
        bbox = bbox.padded(matplotlib.rcParams["savefig.pad_inches"])
        with atomic_path(p) as tmp:
            fig.savefig(tmp, format=fmt, dpi=DPI, bbox_inches=bbox)
    finally:
        plt = sys.modules.get("matplotlib.pyplot")
        if plt is not None:
            plt.close(fig)
    return p


def own_axes(ax, figsize_in: tuple[float, float]):
    """Return ``(figure, axes, own)``: ``ax`` and its figure, or a new figure's one axes.

    ``own`` says the figure is new (its layout and title are the caller's to set).
    """
    if ax is not None:
        return ax.figure, ax, False
    fig = new_figure(figsize_in)
    return fig, fig.subplots(), True


def _finish(fig, path, own: bool):
    """Write the figure to ``path`` when given (a new one cropped and closed); return it."""
    if path is not None and own:
        save_figure(fig, path)
    elif path is not None:  # a caller's figure: written whole, cropped, left open
        save_png(fig, path, bbox_inches="tight")
    return fig


def plot_planform(beam, lengths_m: np.ndarray, path=None, title: str = "", *, ax=None):
    """Plot the planform (m) with joint lines, link spans and centres of mass.

    Parameters
    ----------
    beam : Beam
    lengths_m : ndarray, shape (n+1,)
        Link lengths, m.
    path : path-like, optional
        Write the figure there (PNG, PDF or SVG by the suffix).
    title : str
        The axes' title (default: the beam and the joints).
    ax : matplotlib Axes, optional
        Draw into it (default: a new figure).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..chain.sections import link_sections

    if path is not None:
        figure_format(path)
    lengths = np.asarray(lengths_m, dtype=float)
    # any fitted layout, also one with links below Eq. 15's default 0.02 L (--min-link)
    sec = link_sections(beam, lengths,
                        min_fraction=min(MIN_FRACTION, 0.5 * float(lengths.min()) / beam.length_m))
    fig, ax, own = own_axes(ax, (7, 4))
    x, w = beam.x_m, beam.half_width_m
    # a width step is two vertices at one x: fill_between and the outline draw it as a jump
    ax.fill_between(x, -w, w, color="0.85", label="planform")
    ax.plot(np.r_[x, x[::-1], x[:1]], np.r_[w, -w[::-1], w[:1]], color="0.3", lw=1)
    joints = np.cumsum(lengths)[:-1]
    wmax = float(np.max(w))
    for j, xj in enumerate(joints):
        ax.axvline(xj, color="tab:red", lw=1.2, ls="--")
        ax.annotate(f"J{j + 1}", (xj, 1.05 * wmax), ha="center", color="tab:red")
    ax.plot([], [], color="tab:red", lw=1.2, ls="--", label="joint")
    ax.plot(sec.com_m[:, 0], sec.com_m[:, 1], "o", color="tab:blue", label="link centre of mass")
    for i in range(lengths.size):
        ax.annotate(f"{lengths[i]:.3f} m\n{sec.mass_kg[i]:.2f} kg",
                    (0.5 * (sec.start_m[i] + sec.end_m[i]), -1.25 * wmax), ha="center",
                    fontsize=7)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_ylim(-1.5 * wmax, 1.2 * wmax)
    ax.set_title(title or f"{beam.name}: {lengths.size - 1}R PRBDM")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)
    return _finish(fig, path, own)


def plot_scf(result, path=None, *, ax=None):
    """Plot SCF k_i against the pose's joint angle (deg), with P_i (equation 26) on the right axis.

    The exported pose's SCF is circled, SCF_mean (a diagnostic, not exported) dotted. Drawn
    into ``ax`` (a twin axes takes P_i) or a new figure, written to ``path`` when given (PNG,
    PDF or SVG by the suffix); returns the Figure.
    """
    if path is not None:
        figure_format(path)
    ang = np.degrees(np.asarray(result.poses_rad)[:, 0])
    k = np.asarray(result.factors)
    fig, ax, own = own_axes(ax, (6, 4))
    ax.plot(ang, k, "o-", color="tab:blue", label="k_i (left axis)")
    ax.axhline(result.scf_mean, color="0.5", ls=":", lw=1, label="SCF_mean (not exported)")
    pose = result.export_pose_rad
    if pose is not None:
        i = int(np.argmin(np.abs(np.asarray(result.poses_rad)[:, 0] - pose[0])))
        ax.plot(ang[i], k[i], "o", ms=12, mfc="none", color="tab:red",
                label=f"exported: pose {i}, k = {k[i]:.4g}")
    ax.set_xlabel("joint angle (deg)")
    ax.set_ylabel("stiffness correction factor k_i (-)")
    ax2 = ax.twinx()
    ax2.plot(ang, np.asarray(result.scf_deviation_pct), "s--", color="tab:orange", ms=3)
    ax.plot([], [], "s--", color="tab:orange", ms=3, label="P_i (right axis)")
    ax.legend(loc="best", fontsize=7)
    ax2.set_ylabel("P_i: change from mean (%)")
    ax.set_title(f"{result.joints}R, SCF_mean = {result.scf_mean:.4g}")
    return _finish(fig, path, own)


def plot_pareto(pareto, path=None, *, ax=None):
    """Plot the front (eigen %, deflection %) with the knee of equation 27 starred.

    ``pareto`` may be a list of ParetoResults, drawn together (as the paper's Fig. 11). Drawn
    into ``ax`` or a new figure, written to ``path`` when given (PNG, PDF or SVG by the
    suffix); returns the Figure.
    """
    if path is not None:
        figure_format(path)
    fronts = list(pareto) if isinstance(pareto, (list, tuple)) else [pareto]
    fig, ax, own = own_axes(ax, (6, 4.5))
    for i, p in enumerate(fronts):
        F = np.asarray(p.F_pct)
        color = f"C{i}"
        ax.plot(F[:, 0], F[:, 1], ".", color=color, label=f"{p.joints}R front")
        k = p.knee_index
        ax.plot(F[k, 0], F[k, 1], "*", ms=14, color=color, markeredgecolor="k",
                label=f"{p.joints}R knee: {np.hypot(*F[k]):.3g} %")
    ax.set_xlabel("eigen loss (%)")
    ax.set_ylabel(f"deflection loss (%, {fronts[0].deflection_norm})")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.legend()
    return _finish(fig, path, own)
