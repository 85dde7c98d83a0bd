"""``prbdm simulate --input NAME=SIGNAL``: open-loop input signals of time.

Each is checked with a message naming the option and the value (numpy-free, so they are
refused before any import).

SIGNAL is one of

- ``A``: a step of A (the input's unit) at t = 0;
- ``step:A:T0``: 0 before T0 (s), A from T0 on;
- ``pulse:A:T1``: A from 0 to T1 (s), 0 after (a rest-to-rest torque pulse);
- ``sine:A:F``: A sin(2 pi F t), F in Hz.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from ..errors import BeamInputError

__all__ = ["InputSignal", "parse_input", "parse_inputs"]

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


def parse_input(text: str) -> InputSignal:
    """``NAME=SIGNAL`` (see the module notes) as an :class:`InputSignal`."""
    from ..model.names import split_name

    where = f"--input = {text!r}"
    name, sep, signal = text.partition("=")
    if not sep or not signal:
        raise BeamInputError(f"{where}: must be NAME=SIGNAL, e.g. hub_torque=0.5 or "
                             "strain[0]=sine:2:10")
    split_name(name.strip(), where)
    kind, _, rest = signal.partition(":")
    if not rest:
        kind, values = "step", [signal, "0"]
    else:
        values = rest.split(":")
    if kind not in _KINDS or len(values) != _KINDS[kind]:
        raise BeamInputError(f"{where}: SIGNAL must be A, step:A:T0, pulse:A:T1 or sine:A:F")
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
