"""The figure of a simulated response: tip, outputs, inputs and joint angles against time.

Drawn into the axes given (``axes=``) or a new figure without pyplot (see
:mod:`prbdm_pin.views.plots`), written when given a path (PNG, PDF or SVG by the suffix).
"""

from __future__ import annotations

import os

import numpy as np

from ..errors import BeamInputError
from .plots import figure_format, new_figure, save_png

__all__ = ["plot_response"]


def plot_response(model, tr, force_N: np.ndarray, damping_ratio: float,
                  path: str | os.PathLike | None = None, *, axes=None):
    """Draw the response of a simulation; write it to ``path`` when given; return the Figure.

    One row each: the tip displacement (mm, z and x from the straight pose), every output of the
    plant in its unit, the inputs (when any) and the beam's joint angles (rad, one labelled line
    per joint), against t (s). The title names the model (and its hub), the step tip force
    ``force_N`` (N) and the ``damping_ratio``. ``axes``: one axes per row to draw into
    (default: a new figure); ``path``: PNG, PDF or SVG by the suffix.
    """
    if path is not None:
        figure_format(path)
    rows = 2 + len(tr.output_names) + int(bool(tr.input_names))
    if axes is None:
        fig = new_figure((7.0, 2.2 + 1.6 * rows))
        axes = [fig.add_subplot(rows, 1, k + 1) for k in range(rows)]
        own = True
    else:
        axes = list(np.ravel(axes))
        if len(axes) < rows:
            raise BeamInputError(f"axes: {len(axes)} given for {rows} rows (tip, outputs, "
                                 "inputs, joint angles); give one per row")
        fig, own = axes[0].figure, False
    # the tip at rest in the frame the run records it in (a free bus's: relative to the bus)
    rest = getattr(model, "member", model).tip_position()
    axes[0].plot(tr.t_s, (tr.tip_position_m[:, 2] - rest[2]) * 1e3, label="z")
    axes[0].plot(tr.t_s, (tr.tip_position_m[:, 0] - rest[0]) * 1e3, label="x")
    axes[0].set_ylabel("tip displacement (mm)")
    axes[0].legend(fontsize=7)
    k = 1
    for name, unit in zip(tr.output_names, tr.output_units, strict=True):
        axes[k].plot(tr.t_s, tr.output(name), label=name)
        axes[k].set_ylabel(f"{name} ({unit})", fontsize=8)
        axes[k].legend(fontsize=7)
        k += 1
    if tr.input_names:
        for name, unit in zip(tr.input_names, tr.input_units, strict=True):
            axes[k].plot(tr.t_s, tr.input(name), label=f"{name} ({unit})")
        axes[k].set_ylabel("inputs")
        axes[k].legend(fontsize=7)
        k += 1
    first = getattr(model, "n_free", int(model.hub is not None))
    names = _joint_labels(model, tr.q_rad.shape[1] - first)
    for j, name in enumerate(names):
        axes[k].plot(tr.t_s, tr.q_rad[:, first + j], label=name)
    axes[k].set_ylabel("joint angles (rad)")
    axes[k].legend(fontsize=6, ncol=min(len(names), 4))
    axes[k].set_xlabel("t (s)")
    hub = "" if model.hub is None else (f", hub {model.hub.inertia_kg_m2:g} kg m^2 at "
                                        f"{model.hub.radius_m:g} m about {model.hub.axis}")
    if own:
        fig.suptitle(f"{model.n_joints}R PRBDM{hub}, F = {np.asarray(force_N).tolist()} N, "
                     f"zeta = {damping_ratio}", fontsize=9)
        fig.tight_layout()
    if path is not None:
        save_png(fig, path, bbox_inches=None if own else "tight")
    return fig


def _joint_labels(model, n: int) -> list[str]:
    """Return the names of the beam's ``n`` joint coordinates (``joint_j`` or ``joint_j_a``)."""
    axes = getattr(model, "spring_axes", None)
    if axes is None or len(axes) != n:
        return [f"joint {j + 1}" for j in range(n)]
    per = max(1, n // max(1, model.n_joints))
    return [f"joint {c // per + 1}" + (f" ({a})" if per > 1 else "")
            for c, a in enumerate(axes)]
