"""A calibration's files: ``calibration.json``, the calibrated ``model.json`` and a plot.

``calibration.json`` holds ``"parameters": {NAME: {"value": ..., "std_error": ...}}`` (``E`` in
Pa, ``rho`` in kg/m^3, ``damping[k]`` the ratio of mode k + 1), the scales, the calibrated
frequencies, the residual RMS per channel, the data's kind (``"data"``: ``"ring-down"``,
``"driven"`` or ``"frf"``), its size and its channels (and inputs), and the ``hub`` the model was
calibrated on (null when clamped; ``{"inertia_kg_m2", "radius_m", "axis"}``, its ratios then
those of the flexible modes). ``model.json`` is the calibrated
chain as ``prbdm export --format json`` writes it (a model JSON every loader reads), with the
per-mode ratios in its ``damping`` record (``form`` ``"modal"``: fitted ratios for the fitted
modes, the given ratio for the others). ``calibration.png`` draws each channel's data and the
calibrated model's response against time, or for an FRF its magnitude and phase against
frequency.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..fitting.calibrate import CalibrationResult
from ..fitting.calibration_measured import DrivenTrajectory, FrequencyResponse
from ..io.atomic import atomic_write_text
from ..io.output_folder import output_folder
from ..io.provenance import provenance
from ..options.validate import check_type
from ..version import __version__
from ..views.plots import new_figure, save_figure
from .model_json import model_dict

__all__ = ["CALIBRATION_FILES", "calibration_record", "plot_calibration", "write_calibration"]

CALIBRATION_FILES = ("calibration.json", "model.json", "calibration.png")


def calibration_record(result: CalibrationResult) -> dict:
    """Return the JSON-ready record of ``result`` (module notes)."""
    return {
        "format": "prbdm-calibration/1",
        "version": __version__,
        "parameters": {n: {"value": float(v), "std_error": float(s)} for n, v, s in
                       zip(result.parameters, result.values, result.std_errors, strict=True)},
        "E_scale": result.E_scale,
        "rho_scale": result.rho_scale,
        "damping_ratio": [float(v) for v in result.damping_ratio],
        "model_damping_ratio": [float(v) for v in result.model_damping_ratio],
        "omega_rad_s": [float(v) for v in result.omega_rad_s],
        "residual_rms": dict(result.residual_rms),
        "data": _kind(result.data),
        "samples": int(result.data.y.shape[0] if hasattr(result.data, "y")
                       else result.data.f_hz.size),
        "hub": _hub(result.model),
        "channels": list(result.data.channels),
        **({"inputs": list(result.data.inputs)} if hasattr(result.data, "inputs") else {}),
    }


def _hub(model) -> dict | None:
    hub = getattr(model, "hub", None)
    return None if hub is None else {"inertia_kg_m2": hub.inertia_kg_m2,
                                     "radius_m": hub.radius_m, "axis": hub.axis}


def _kind(data) -> str:
    if isinstance(data, FrequencyResponse):
        return "frf"
    return "driven" if isinstance(data, DrivenTrajectory) else "ring-down"


def _unit(channel: str) -> str:
    """Return the unit of a data channel (an output, or an FRF's OUTPUT/INPUT); "?" if unknown."""
    from ..model.bus_outputs import bus_output_unit
    from ..model.inputs import input_unit
    from ..views.bode import unit_ratio

    try:
        if "/" in channel:
            out, inp = channel.split("/", 1)
            return unit_ratio(bus_output_unit(out), input_unit(inp))
        return bus_output_unit(channel)
    except (KeyError, ValueError, BeamInputError):
        return "?"


def plot_calibration(result: CalibrationResult, path: str | os.PathLike | None = None):
    """Draw each channel's data against the calibrated model; return the Figure.

    A ring-down or a driven run: one axes per channel against time; an FRF: a magnitude and a
    phase axes per transfer function against frequency. Every axis names its unit.

    Parameters
    ----------
    result : CalibrationResult
    path : path-like, optional
        Also write the figure there (PNG, PDF or SVG by the suffix, atomically).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> w = np.sqrt(1.1) * model.natural_frequencies()[0]  # rad/s: E 10 % up
    >>> t = np.arange(500) * 2e-3  # s
    >>> y = 1e-3 * np.exp(-0.01 * w * t) * np.cos(w * np.sqrt(1 - 0.01**2) * t)  # m
    >>> cal = pp.calibrate(model, pp.RingDown(t_s=t, y=y[:, None], channels=("tip_z",)),
    ...                    ("E", "damping[0]"))
    >>> fig = pp.plot_calibration(cal)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['tip_z (m)']
    """
    check_type("result", result, CalibrationResult, "a CalibrationResult")
    d = result.data
    c = len(d.channels)
    if isinstance(d, FrequencyResponse):
        fig = new_figure((7.0, 3.6 * c + 0.6))
        for j, ch in enumerate(d.channels):
            mag = fig.add_subplot(2 * c, 1, 2 * j + 1)
            mag.semilogy(d.f_hz, np.abs(d.H[:, j]), ".", ms=2, color="0.5", label="data")
            mag.semilogy(d.f_hz, np.abs(result.fitted[:, j]), "-", lw=0.8, color="C0",
                         label="calibrated model")
            mag.set_ylabel(f"|{ch}| ({_unit(ch)})")
            mag.legend(loc="upper right", fontsize="small")
            ph = fig.add_subplot(2 * c, 1, 2 * j + 2, sharex=mag)
            ph.plot(d.f_hz, np.degrees(np.angle(d.H[:, j])), ".", ms=2, color="0.5")
            ph.plot(d.f_hz, np.degrees(np.angle(result.fitted[:, j])), "-", lw=0.8, color="C0")
            ph.set_ylabel("phase (deg)")
        ph.set_xlabel("f (Hz)")
    else:
        fig = new_figure((7.0, 2.2 * c + 0.6))
        for j, ch in enumerate(d.channels):
            ax = fig.add_subplot(c, 1, j + 1)
            ax.plot(d.t_s, d.y[:, j], ".", ms=2, color="0.5", label="data")
            ax.plot(d.t_s, result.fitted[:, j], "-", lw=0.8, color="C0",
                    label="calibrated model")
            ax.set_ylabel(f"{ch} ({_unit(ch)})")
            ax.legend(loc="upper right", fontsize="small")
        ax.set_xlabel("t (s)")
    fig.tight_layout()
    if path is not None:
        save_figure(fig, path)
    return fig


def write_calibration(result: CalibrationResult, out: str | os.PathLike) -> Path:
    """Write ``calibration.json``, ``model.json`` and ``calibration.png`` into ``out``.

    All together or none (:func:`~prbdm_pin.io.output_folder.output_folder`).

    Parameters
    ----------
    result : CalibrationResult
    out : path
        The folder.

    Returns
    -------
    Path
        The folder written.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> w = np.sqrt(1.1) * model.natural_frequencies()[0]  # rad/s: E 10 % up
    >>> t = np.arange(500) * 2e-3  # s
    >>> y = 1e-3 * np.exp(-0.01 * w * t) * np.cos(w * np.sqrt(1 - 0.01**2) * t)  # m, ratio 0.01
    >>> data = pp.RingDown(t_s=t, y=y[:, None], channels=("tip_z",))
    >>> cal = pp.calibrate(model, data, ("E", "damping[0]"))
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> out = pp.write_calibration(cal, folder / "cal")
    >>> sorted(p.name for p in out.iterdir())
    ['calibration.json', 'calibration.png', 'model.json']
    """
    if not isinstance(result, CalibrationResult):
        raise InputTypeError(f"result = {result!r:.60}: must be a CalibrationResult")
    record = calibration_record(result)
    model = model_dict(result.model, result.model_damping_ratio, damping_form="modal")
    with output_folder(out, CALIBRATION_FILES) as stage:
        # a calibration draws nothing at random: the seed is null
        atomic_write_text(stage / "calibration.json",
                          json.dumps({**provenance(), **record}, indent=2) + "\n")
        atomic_write_text(stage / "model.json", json.dumps({**model, **provenance()}, indent=2)
                          + "\n")
        plot_calibration(result, stage / "calibration.png")
    return Path(os.path.abspath(out))
