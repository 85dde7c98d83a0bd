"""Input and output names of the plant: ``base``, ``base[index]`` or ``base@X`` / ``base@X:Y``.

A station name carries where it reads: ``X`` a station along the beam and ``Y`` a position
across it, in m (``strain@0.25``, ``point_z@0.9:-0.01``), numbers as Python's ``float`` reads
them. Whether the station lies on the model's beam is checked where the model is known
(:mod:`prbdm_pin.model.stations`).

Numpy-free, so that the command line can check them before it loads anything.
"""

from __future__ import annotations

import functools
import re

from ..errors import BeamInputError

__all__ = ["split_name", "parse_names"]

_NAME = re.compile(r"^([a-z_]+)(?:\[(\d+)\])?$")
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_STATION = re.compile(rf"^([a-z_]+)@({_NUMBER})(?::({_NUMBER}))?$")


def split_name(text: object, field: str) -> tuple[str, int | tuple[float, ...] | None]:
    """Split a name: ``"q[3]"`` -> ``("q", 3)``, ``"tip_z"`` -> ``("tip_z", None)``.

    A station name gives its station in m: ``"strain@0.5"`` -> ``("strain", (0.5,))``,
    ``"point_z@0.5:0.01"`` -> ``("point_z", (0.5, 0.01))``.

    Raises BeamInputError naming ``field`` for anything else.
    """
    m = _NAME.match(text) if isinstance(text, str) else None
    if m is not None:
        return m.group(1), None if m.group(2) is None else int(m.group(2))
    m = _STATION.match(text) if isinstance(text, str) else None
    if m is None:
        raise BeamInputError(f"{field} = {text!r}: must be a name such as 'tip_z', 'q[0]' or "
                             "'strain@0.5'")
    return m.group(1), tuple(float(g) for g in m.groups()[1:] if g is not None)


def parse_names(names: object, field: str, indexed: dict[str, int | None],
                plain: tuple[str, ...], stations: dict[str, int] | None = None
                ) -> tuple[tuple[str, str, int | tuple[float, ...] | None], ...]:
    """Check ``names`` against the ``plain`` names, the ``indexed`` and the ``stations`` bases.

    ``names`` is a sequence of str; each indexed base has its count, or None when any index
    >= 0 is accepted; each station base the number of coordinates it takes (1: ``@X``, 2:
    ``@X:Y``). Returns (name, base, index) per entry, the index a tuple of floats (m) for a
    station name (remembered: a linearisation parses the same names several times).

    Raises
    ------
    BeamInputError
        Naming ``field[i]``, the value and what is accepted.
    """
    if isinstance(names, (list, tuple)) and all(isinstance(s, str) for s in names):
        return _parse_remembered(tuple(names), field, tuple(indexed.items()), tuple(plain),
                                 tuple((stations or {}).items()))
    return _parse(names, field, indexed, plain, stations or {})


@functools.lru_cache(maxsize=256)
def _parse_remembered(names: tuple[str, ...], field: str,
                      indexed: tuple[tuple[str, int | None], ...], plain: tuple[str, ...],
                      stations: tuple[tuple[str, int], ...]
                      ) -> tuple[tuple[str, str, int | tuple[float, ...] | None], ...]:
    return _parse(names, field, dict(indexed), plain, dict(stations))


def _parse(names: object, field: str, indexed: dict[str, int | None],
           plain: tuple[str, ...], stations: dict[str, int]
           ) -> tuple[tuple[str, str, int | tuple[float, ...] | None], ...]:
    if isinstance(names, str) or not isinstance(names, (list, tuple)) or not names:
        raise BeamInputError(f"{field} = {names!r}: must be a non-empty sequence of names")
    known = ", ".join([*plain, *(f"{b}[i]" for b in indexed),
                       *(f"{b}@X" + (":Y" if c == 2 else "") for b, c in stations.items())])
    out = []
    for i, text in enumerate(names):
        where = f"{field}[{i}]"
        base, idx = split_name(text, where)
        if isinstance(idx, tuple):
            if base not in stations:
                raise BeamInputError(f"{where} = {text!r}: unknown; must be one of {known}")
            if len(idx) != stations[base]:
                form = "X:Y (m along and across the beam)" if stations[base] == 2 else "X (m)"
                raise BeamInputError(f"{where} = {text!r}: {base} takes the station {form}")
            out.append((text, base, idx))
            continue
        if idx is None and base in plain:
            out.append((text, base, None))
            continue
        if idx is None or base not in indexed:
            raise BeamInputError(f"{where} = {text!r}: unknown; must be one of {known}")
        count = indexed[base]
        if count is not None and idx >= count:
            raise BeamInputError(f"{where} = {text!r}: index {idx} out of range, this model has "
                                 f"{count} (0..{count - 1})" if count else
                                 f"{where} = {text!r}: this model has none")
        out.append((text, base, idx))
    if len({n for n, _, _ in out}) != len(out):
        raise BeamInputError(f"{field} = {list(names)!r}: a name appears twice")
    return tuple(out)
