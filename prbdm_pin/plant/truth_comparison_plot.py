"""The figure of a truth comparison: step response, FRF magnitude and phase of both sides.

Drawn without pyplot (see :mod:`prbdm_pin.views.plots`).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .truth_comparison import TruthComparison

__all__ = ["plot_truth_comparison"]


def plot_truth_comparison(cmp: TruthComparison, path: str | os.PathLike) -> Path:
    """Write the step response and the FRF of the truth and the PRBDM to ``path``; return it.

    The unit-step tip response (um/N against s), the tip FRF magnitude (m/N) and phase (deg)
    against rad/s, as a PNG written atomically.
    """
    import matplotlib

    from ..views.plots import new_figure, save_png

    acc, name = cmp.accuracy, cmp.truth_model
    mine = f"{cmp.prbdm.omega_rad_s.size}R PRBDM"
    # laid out at matplotlib's own figure dpi, as this figure always was (a pyplot figure
    # before), and written at DPI: the layout, hence the PNG, stays what it was
    fig = new_figure((7, 8), dpi=matplotlib.rcParams["figure.dpi"])
    ax = fig.subplots(3, 1)
    ax[0].plot(acc.t_s, acc.step_truth_m_per_N * 1e6, label=f"{name} truth")
    ax[0].plot(acc.t_s, acc.step_model_m_per_N * 1e6, "--", label=mine)
    ax[0].set_xlabel("t (s)")
    ax[0].set_ylabel("tip z / F, unit step (um/N)")
    ax[0].legend()
    w = acc.omega_band_rad_s
    ax[1].semilogy(w, np.abs(acc.frf_truth_m_per_N), label=f"{name} truth")
    ax[1].semilogy(w, np.abs(acc.frf_model_m_per_N), "--", label=mine)
    ax[1].set_ylabel("|H| (m/N)")
    ax[2].plot(w, np.degrees(np.angle(acc.frf_truth_m_per_N)))
    ax[2].plot(w, np.degrees(np.angle(acc.frf_model_m_per_N)), "--")
    ax[2].set_xlabel("omega (rad/s)")
    ax[2].set_ylabel("phase (deg)")
    fig.suptitle(f"{name} truth, zeta = {cmp.damping_ratio}: step error "
                 f"{acc.step_error:.1%}, FRF error {acc.frf_error:.1%}")
    fig.tight_layout()
    return save_png(fig, path)
