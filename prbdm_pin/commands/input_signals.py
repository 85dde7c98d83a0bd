"""``prbdm simulate --input NAME=SIGNAL``: open-loop input signals of time.

Each is checked with a message naming the option and the value (numpy-free, so they are
refused before any import).

SIGNAL is one of

- ``A``: a step of A (the input's unit) at t = 0;
- ``step:A:T0``: 0 before T0 (s), A from T0 on;
- ``pulse:A:T1``: A from 0 to T1 (s), 0 after (a rest-to-rest torque pulse);
- ``sine:A:F``: A sin(2 pi F t), F in Hz;
- ``FILE.csv``: samples (time s, value) read from a CSV file (a header row is skipped),
  linearly interpolated between samples and held at the first and last value outside them;
  times strictly increasing, values finite, at least two rows.
"""

from __future__ import annotations

import bisect
import csv
import math
from collections.abc import Callable
from dataclasses import dataclass

from ..errors import BeamInputError

__all__ = ["InputSignal", "SampledSignal", "read_rows", "read_samples", "parse_input",
           "parse_inputs"]

_KINDS = {"step": 2, "pulse": 2, "sine": 2}


@dataclass(frozen=True)
class InputSignal:
    """One ``--input``: the input's name, the signal's kind and its two parameters.

    The amplitude is in the input's unit; T0 or T1 in s, or F in Hz.
    """

    name: str
    kind: str
    amplitude: float
    parameter: float

    def value(self, t_s: float) -> float:
        """Return the input at time ``t_s`` (s)."""
        if self.kind == "step":
            return self.amplitude if t_s >= self.parameter else 0.0
        if self.kind == "pulse":
            return self.amplitude if t_s < self.parameter else 0.0
        return self.amplitude * math.sin(2.0 * math.pi * self.parameter * t_s)


@dataclass(frozen=True)
class SampledSignal:
    """One ``--input NAME=FILE.csv``: samples of time (s) and value (the input's unit)."""

    name: str
    t_s: tuple[float, ...]
    values: tuple[float, ...]

    def value(self, t_s: float) -> float:
        """Return the input at ``t_s`` (s): linear between samples, held outside them."""
        t, v = self.t_s, self.values
        if t_s <= t[0]:
            return v[0]
        if t_s >= t[-1]:
            return v[-1]
        i = bisect.bisect_right(t, t_s)
        w = (t_s - t[i - 1]) / (t[i] - t[i - 1])
        return v[i - 1] + w * (v[i] - v[i - 1])


def read_rows(path: str, where: str) -> list[list[str]]:
    """Return the non-blank rows of a CSV file; BeamInputError naming ``where`` if unreadable."""
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            return [r for r in csv.reader(fh) if r and any(c.strip() for c in r)]
    except (OSError, UnicodeDecodeError) as exc:
        raise BeamInputError(f"{where}: cannot read {path!r} ({exc.strerror or exc})") from None


def read_samples(path: str, where: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Read (time s, value) rows of a CSV file; BeamInputError naming ``where`` otherwise."""
    rows = read_rows(path, where)
    t, v = [], []
    for i, row in enumerate(rows):
        try:
            a, b = (float(c) for c in row)
        except ValueError:
            if i == 0:
                continue  # a header
            a = b = math.nan
        if len(row) != 2 or not (math.isfinite(a) and math.isfinite(b)):
            raise BeamInputError(f"{where}: row {i + 1} = {row!r:.60}: must be two finite "
                                 "numbers, time (s) and value")
        if t and a <= t[-1]:
            raise BeamInputError(f"{where}: row {i + 1}: time {a:g} s does not increase "
                                 f"(previous {t[-1]:g} s)")
        t.append(a)
        v.append(b)
    if len(t) < 2:
        raise BeamInputError(f"{where}: needs at least two rows (time s, value)")
    return tuple(t), tuple(v)


def parse_input(text: str) -> InputSignal | SampledSignal:
    """``NAME=SIGNAL`` (see the module notes) as an :class:`InputSignal` or a file's samples."""
    from ..model.names import split_name

    where = f"--input = {text!r}"
    name, sep, signal = text.partition("=")
    if not sep or not signal:
        raise BeamInputError(f"{where}: must be NAME=SIGNAL, e.g. hub_torque=0.5 or "
                             "strain[0]=sine:2:10")
    split_name(name.strip(), where)
    if signal.strip().lower().endswith(".csv"):
        return SampledSignal(name.strip(), *read_samples(signal.strip(), where))
    kind, _, rest = signal.partition(":")
    if not rest:
        kind, values = "step", [signal, "0"]
    else:
        values = rest.split(":")
    if kind not in _KINDS or len(values) != _KINDS[kind]:
        raise BeamInputError(f"{where}: SIGNAL must be A, step:A:T0, pulse:A:T1, sine:A:F or "
                             "FILE.csv")
    try:
        a, p = (float(v) for v in values)
    except ValueError:
        a = p = math.nan
    bound = {"step": "T0 >= 0 (s)", "pulse": "T1 > 0 (s)", "sine": "F > 0 (Hz)"}[kind]
    if not (math.isfinite(a) and math.isfinite(p)) or p < 0.0 or (kind != "step" and p == 0.0):
        raise BeamInputError(f"{where}: needs a finite amplitude A and {bound}")
    return InputSignal(name.strip(), kind, a, p)


def parse_inputs(texts: list[str]) -> tuple[tuple[str, ...], Callable[[float], list] | None]:
    """Return the ``--input`` options as (names, u(t) -> list of values); ((), None) if none."""
    signals = [parse_input(t) for t in texts]
    names = tuple(s.name for s in signals)
    if len(set(names)) != len(names):
        raise BeamInputError(f"--input: {names!r} names an input twice")
    if not signals:
        return (), None
    return names, (lambda t: [s.value(t) for s in signals])
