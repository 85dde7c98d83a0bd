"""Measured data for :func:`~prbdm_pin.fitting.calibrate.calibrate` beyond a ring-down.

Three CSV kinds, told apart by the header (:func:`read_calibration_data`):

- a **free ring-down**: ``t_s`` then outputs only (:mod:`.calibration_data`);
- a **driven trajectory**: ``t_s``, one column per measured input, one per measured output.
  An input column is named as :func:`prbdm_pin.linearize` names inputs, with or without its
  unit (``tip_force_z`` or ``tip_force_z_N``, ``base_accel_z`` or ``base_accel_z_m_s2``,
  ``joint_torque[0]`` or ``joint_torque[0]_N_m``), or with the ``u:`` prefix ``prbdm
  simulate``'s trajectory CSV writes (``u:tip_force_z``); every other column is an output
  (``tip_z_m``, ``y:tip_z``). The times must be uniform: the model holds each input sample
  over the step that follows it (a zero-order hold);
- an **FRF**: ``f_hz`` (Hz, strictly increasing, > 0), then per measured transfer function
  two columns ``OUTPUT/INPUT_re`` and ``OUTPUT/INPUT_im``, its real and imaginary parts
  (the output's unit per the input's: ``tip_z/tip_force_z_re`` in m/N), each name with or
  without its unit (``tip_z_m/tip_force_z_N_re``). The convention is the phasor's:
  y = H u for u = e^{i 2 pi f t}.

Every value must be finite; bad data is refused naming the column and the row.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..model.inputs import INPUT_UNITS
from .calibration_data import MIN_SAMPLES, RingDown, channel_name, read_table, ring_down

__all__ = ["DrivenTrajectory", "FrequencyResponse", "driven_trajectory", "frequency_response",
           "is_input", "read_calibration_data"]

STEP_RTOL = 1e-6  # uniform steps: each within this of the median (a printed time's rounding)


@dataclass(frozen=True, eq=False)
class DrivenTrajectory:
    """A trajectory driven by measured inputs.

    Attributes
    ----------
    t_s : ndarray (N,)
        Uniform sample times, s.
    u : ndarray (N, m)
        The inputs, each in its unit (N, N m, m/s^2), held over the step after each sample.
    inputs : tuple of str
        Their names as :func:`prbdm_pin.linearize` spells them.
    y : ndarray (N, c)
        The measured outputs, SI units.
    channels : tuple of str
        The outputs' names as :func:`prbdm_pin.linearize` spells them.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> t = np.linspace(0.0, 0.1, 11)  # s
    >>> run = pp.DrivenTrajectory(t_s=t, u=np.ones((11, 1)), inputs=("tip_force_z",),
    ...                           y=np.zeros((11, 1)), channels=("tip_z",))
    >>> run.u.shape, run.y.shape
    ((11, 1), (11, 1))
    """

    t_s: np.ndarray
    u: np.ndarray
    inputs: tuple[str, ...]
    y: np.ndarray
    channels: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class FrequencyResponse:
    """Measured transfer functions (an FRF) at a set of frequencies.

    Attributes
    ----------
    f_hz : ndarray (N,)
        Frequencies, Hz, strictly increasing and positive.
    H : ndarray (N, c), complex
        Output per unit input of each transfer function (SI units of output / input).
    outputs, inputs : tuple of str
        Each transfer function's output and input, as :func:`prbdm_pin.linearize` names them.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> f = np.linspace(1.0, 20.0, 10)  # Hz
    >>> H = 1e-3 / (1 - (f / 9.0)**2 + 0.04j * f / 9.0)  # m/N
    >>> frf = pp.FrequencyResponse(f_hz=f, H=H[:, None], outputs=("tip_z",),
    ...                            inputs=("tip_force_z",))
    >>> frf.H.shape
    (10, 1)
    """

    f_hz: np.ndarray
    H: np.ndarray
    outputs: tuple[str, ...]
    inputs: tuple[str, ...]

    @property
    def channels(self) -> tuple[str, ...]:
        """Each transfer function as ``OUTPUT/INPUT``."""
        return tuple(f"{o}/{i}" for o, i in zip(self.outputs, self.inputs, strict=True))


def is_input(name: str) -> bool:
    """Return whether ``name`` (unit and ``u:`` prefix dropped) is one of linearize's inputs."""
    return channel_name(name).split("[")[0] in INPUT_UNITS


def _finite(what: str, name: str, col: np.ndarray) -> None:
    bad = np.flatnonzero(~np.isfinite(col))
    if bad.size:
        raise BeamInputError(f"{what}: {name}: not finite at row {int(bad[0])} "
                             f"({float(col[bad[0]])})")


def driven_trajectory(t_s, u, inputs, y, channels, what: str = "data") -> DrivenTrajectory:
    """Return a checked :class:`DrivenTrajectory` (module notes).

    Raises
    ------
    BeamInputError
        Naming the column: a value not finite (and its row), a time not increasing or a step
        not uniform (the row), fewer than 8 samples, a name that is not an input, a repeat.
    """
    if isinstance(inputs, str) or not isinstance(inputs, (list, tuple)) or not inputs:
        raise InputTypeError(f"{what}: inputs = {inputs!r:.60}: must be a list of input names")
    for name in inputs:
        if not isinstance(name, str) or not is_input(name):
            raise BeamInputError(f"{what}: {name!r:.40}: not an input of linearize "
                                 f"({', '.join(sorted(INPUT_UNITS))})")
    base = ring_down(t_s, y, channels, what)  # times and outputs checked as a ring-down's
    try:
        U = np.array(u, dtype=float)
    except (TypeError, ValueError):
        raise InputTypeError(f"{what}: u must be numbers") from None
    if U.ndim == 1:
        U = U[:, None]
    if U.shape != (base.t_s.size, len(inputs)):
        raise BeamInputError(f"{what}: u {U.shape}: need {base.t_s.size} rows of "
                             f"{len(inputs)} input(s)")
    names = tuple(channel_name(n) for n in inputs)
    if len(set(names)) != len(names):
        raise BeamInputError(f"{what}: inputs {list(inputs)}: an input is repeated")
    for j, name in enumerate(inputs):
        _finite(what, name, U[:, j])
    dt = np.diff(base.t_s)
    typical = float(np.median(dt))
    off = np.flatnonzero(np.abs(dt - typical) > STEP_RTOL * typical)
    if off.size:
        i = int(off[0]) + 1
        raise BeamInputError(f"{what}: t_s: step {float(dt[i - 1])!r} to row {i} is not the "
                             f"median step {typical!r}: a driven trajectory needs uniform "
                             "samples (the input is held between them)")
    U.setflags(write=False)
    return DrivenTrajectory(t_s=base.t_s, u=U, inputs=names, y=base.y, channels=base.channels)


def frequency_response(f_hz, H, outputs, inputs, what: str = "data") -> FrequencyResponse:
    """Return a checked :class:`FrequencyResponse` (module notes).

    Raises
    ------
    BeamInputError
        Naming the column: a value not finite (and its row), a frequency not increasing or
        not positive, fewer than 8 frequencies, an input that is not one, a repeat.
    """
    try:
        f = np.array(f_hz, dtype=float)
        G = np.array(H, dtype=complex)
    except (TypeError, ValueError):
        raise InputTypeError(f"{what}: f_hz and H must be numbers") from None
    if G.ndim == 1:
        G = G[:, None]
    if not isinstance(outputs, (list, tuple)) or not isinstance(inputs, (list, tuple)) \
            or len(outputs) != len(inputs) or f.ndim != 1 or G.shape != (f.size, len(outputs)) \
            or not outputs:
        raise BeamInputError(f"{what}: f_hz {f.shape} and H {G.shape}: need N frequencies and "
                             f"N rows of one column per (output, input) pair")
    outs = tuple(channel_name(str(o)) for o in outputs)
    ins = tuple(channel_name(str(i)) for i in inputs)
    for o, i in zip(outputs, inputs, strict=True):
        if not is_input(str(i)):
            raise BeamInputError(f"{what}: {o}/{i}: {i!r} is not an input of linearize "
                                 f"({', '.join(sorted(INPUT_UNITS))})")
    pairs = list(zip(outs, ins, strict=True))
    if len(set(pairs)) != len(pairs):
        raise BeamInputError(f"{what}: a transfer function is repeated")
    _finite(what, "f_hz", f)
    for j, (o, i) in enumerate(pairs):
        _finite(what, f"{o}/{i}_re", G[:, j].real)
        _finite(what, f"{o}/{i}_im", G[:, j].imag)
    if f.size < MIN_SAMPLES:
        raise BeamInputError(f"{what}: f_hz: {f.size} frequencies; need at least {MIN_SAMPLES}")
    if f[0] <= 0.0:
        raise BeamInputError(f"{what}: f_hz: {float(f[0])!r} at row 0: frequencies must be "
                             "positive")
    step = np.flatnonzero(np.diff(f) <= 0.0)
    if step.size:
        i = int(step[0]) + 1
        raise BeamInputError(f"{what}: f_hz: not increasing at row {i} ({float(f[i - 1])!r} "
                             f"then {float(f[i])!r})")
    for a in (f, G):
        a.setflags(write=False)
    return FrequencyResponse(f_hz=f, H=G, outputs=outs, inputs=ins)


def _frf_columns(what: str, head: list[str]) -> list[tuple[str, str, int, int]]:
    """Return (output, input, real column, imaginary column) per transfer function."""
    cols = {h: j for j, h in enumerate(head)}
    if len(cols) != len(head):
        raise BeamInputError(f"{what}: header: a column is repeated")
    pairs = []
    for j, h in enumerate(head[1:], start=1):
        if h.endswith("_im"):
            if h[:-3] + "_re" not in cols:
                raise BeamInputError(f"{what}: {h}: no real column {h[:-3] + '_re'}")
            continue
        if not h.endswith("_re") or h.count("/") != 1:
            raise BeamInputError(f"{what}: {h}: an FRF column must be OUTPUT/INPUT_re or "
                                 "OUTPUT/INPUT_im (e.g. tip_z_m/tip_force_z_N_re)")
        im = h[:-3] + "_im"
        if im not in cols:
            raise BeamInputError(f"{what}: {h}: no imaginary column {im}")
        out, inp = h[:-3].split("/")
        pairs.append((out, inp, j, cols[im]))
    if not pairs:
        raise BeamInputError(f"{what}: header: f_hz needs OUTPUT/INPUT_re and _im columns")
    return pairs


def read_calibration_data(path: str | os.PathLike
                          ) -> RingDown | DrivenTrajectory | FrequencyResponse:
    """Read calibration data, its kind told by the header (module notes).

    Parameters
    ----------
    path : str or path-like
        The CSV file: ``t_s`` then outputs (a ring-down), ``t_s`` with input columns (a driven
        trajectory) or ``f_hz`` with ``OUTPUT/INPUT_re`` and ``_im`` columns (an FRF).

    Returns
    -------
    RingDown, DrivenTrajectory or FrequencyResponse

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> f = np.linspace(1.0, 20.0, 10)  # Hz
    >>> H = 1e-3 / (1 - (f / 9.0)**2 + 0.04j * f / 9.0)  # m/N, one mode at 9 Hz
    >>> np.savetxt(folder / "frf.csv", np.c_[f, H.real, H.imag], delimiter=",", comments="",
    ...            header="f_hz,tip_z/tip_force_z_re,tip_z/tip_force_z_im")
    >>> data = pp.read_calibration_data(folder / "frf.csv")
    >>> type(data).__name__, data.outputs, data.inputs, data.H.shape
    ('FrequencyResponse', ('tip_z',), ('tip_force_z',), (10, 1))
    """
    what, head, vals = read_table(path)
    if head and head[0] == "f_hz":
        pairs = _frf_columns(what, head)
        for j, h in enumerate(head):  # each column named, before re and im are combined
            _finite(what, h, vals[:, j])
        H = np.column_stack([vals[:, r] + 1j * vals[:, i] for _, _, r, i in pairs])
        return frequency_response(vals[:, 0], H, [p[0] for p in pairs], [p[1] for p in pairs],
                                  what)
    if not head or head[0] != "t_s" or len(head) < 2:
        raise BeamInputError(f"{what}: header {','.join(head)!r:.80}: must be t_s then one "
                             "column per output and input (e.g. t_s,tip_force_z_N,tip_z_m), or "
                             "f_hz then OUTPUT/INPUT_re and _im columns")
    for h in head[1:]:
        if h.startswith("u:") and not is_input(h):
            raise BeamInputError(f"{what}: {h}: not an input of linearize "
                                 f"({', '.join(sorted(INPUT_UNITS))})")
    ins = [j for j, h in enumerate(head) if j and is_input(h)]
    outs = [j for j, h in enumerate(head) if j and j not in ins]
    if not ins:
        return ring_down(vals[:, 0], vals[:, 1:], head[1:], what)
    if not outs:
        raise BeamInputError(f"{what}: header: inputs ({', '.join(head[j] for j in ins)}) but "
                             "no measured output column")
    return driven_trajectory(vals[:, 0], vals[:, ins], [head[j] for j in ins], vals[:, outs],
                             [head[j] for j in outs], what)
