"""The figure of a truth comparison: step response, FRF magnitude and phase of both sides.

Each on its own axes with its units and a legend. Drawn without pyplot (see
:mod:`prbdm_pin.views.plots`).
"""

from __future__ import annotations

import os

import numpy as np

from .truth_comparison import TruthComparison

__all__ = ["plot_truth_comparison"]


def plot_truth_comparison(cmp: TruthComparison, path: str | os.PathLike | None = None, *,
                          axes=None):
    """Draw the step response and the FRF of the truth and the PRBDM; return the Figure.

    The unit-step tip response (um/N against s), the tip FRF magnitude (m/N) and phase (deg)
    against rad/s.

    Parameters
    ----------
    cmp : TruthComparison
    path : path-like, optional
        Also write the figure there (PNG, PDF or SVG by the suffix, atomically).
    axes : sequence of 3 matplotlib Axes, optional
        The step, magnitude and phase axes to draw into (default: a new figure).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib

    from ..errors import BeamInputError
    from ..views.plots import figure_format, new_figure, save_png

    if path is not None:
        figure_format(path)
    acc, name = cmp.accuracy, cmp.truth_model
    mine = f"{cmp.prbdm.omega_rad_s.size}R PRBDM"
    if axes is None:
        # laid out at matplotlib's own figure dpi, as this figure always was (a pyplot figure
        # before), and written at DPI: the layout, hence the PNG, stays what it was
        fig = new_figure((7, 8), dpi=matplotlib.rcParams["figure.dpi"])
        ax = fig.subplots(3, 1)
    else:
        ax = list(np.ravel(axes))
        if len(ax) < 3:
            raise BeamInputError(f"axes: {len(ax)} given; give 3 (step, magnitude, phase)")
        fig = ax[0].figure
    ax[0].plot(acc.t_s, acc.step_truth_m_per_N * 1e6, label=f"{name} truth")
    ax[0].plot(acc.t_s, acc.step_model_m_per_N * 1e6, "--", label=mine)
    ax[0].set_xlabel("t (s)")
    ax[0].set_ylabel("tip z / F, unit step (um/N)")
    ax[0].legend()
    w = acc.omega_band_rad_s
    ax[1].semilogy(w, np.abs(acc.frf_truth_m_per_N), label=f"{name} truth")
    ax[1].semilogy(w, np.abs(acc.frf_model_m_per_N), "--", label=mine)
    ax[1].set_xlabel("omega (rad/s)")
    ax[1].set_ylabel("|H| (m/N)")
    ax[1].legend()
    ax[2].plot(w, np.degrees(np.angle(acc.frf_truth_m_per_N)), label=f"{name} truth")
    ax[2].plot(w, np.degrees(np.angle(acc.frf_model_m_per_N)), "--", label=mine)
    ax[2].set_xlabel("omega (rad/s)")
    ax[2].set_ylabel("phase (deg)")
    ax[2].legend()
    if axes is None:
        fig.suptitle(f"{name} truth, zeta = {cmp.damping_ratio}: step error "
                     f"{acc.step_error:.1%}, FRF error {acc.frf_error:.1%}")
        fig.tight_layout()
    if path is not None:
        save_png(fig, path, bbox_inches=None if axes is None else "tight")
    return fig
