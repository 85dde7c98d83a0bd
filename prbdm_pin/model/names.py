"""Input and output names of the plant: ``base`` or ``base[index]``.

Numpy-free, so that the command line can check them before it loads anything.
"""

from __future__ import annotations

import functools
import re

from ..errors import BeamInputError

__all__ = ["split_name", "parse_names"]

_NAME = re.compile(r"^([a-z_]+)(?:\[(\d+)\])?$")


def split_name(text: object, field: str) -> tuple[str, int | None]:
    """Split a name: ``"q[3]"`` -> ``("q", 3)``, ``"tip_z"`` -> ``("tip_z", None)``.

    Raises BeamInputError naming ``field`` for anything else.
    """
    m = _NAME.match(text) if isinstance(text, str) else None
    if m is None:
        raise BeamInputError(f"{field} = {text!r}: must be a name such as 'tip_z' or 'q[0]'")
    return m.group(1), None if m.group(2) is None else int(m.group(2))


def parse_names(names: object, field: str, indexed: dict[str, int | None],
                plain: tuple[str, ...]) -> tuple[tuple[str, str, int | None], ...]:
    """Check ``names`` against the ``plain`` names and the ``indexed`` bases.

    ``names`` is a sequence of str; each indexed base has its count, or None when any index
    >= 0 is accepted. Returns (name, base, index) per entry (remembered: a linearisation
    parses the same names several times).

    Raises
    ------
    BeamInputError
        Naming ``field[i]``, the value and what is accepted.
    """
    if isinstance(names, (list, tuple)) and all(isinstance(s, str) for s in names):
        return _parse_remembered(tuple(names), field, tuple(indexed.items()), tuple(plain))
    return _parse(names, field, indexed, plain)


@functools.lru_cache(maxsize=256)
def _parse_remembered(names: tuple[str, ...], field: str,
                      indexed: tuple[tuple[str, int | None], ...], plain: tuple[str, ...]
                      ) -> tuple[tuple[str, str, int | None], ...]:
    return _parse(names, field, dict(indexed), plain)


def _parse(names: object, field: str, indexed: dict[str, int | None],
           plain: tuple[str, ...]) -> tuple[tuple[str, str, int | None], ...]:
    if isinstance(names, str) or not isinstance(names, (list, tuple)) or not names:
        raise BeamInputError(f"{field} = {names!r}: must be a non-empty sequence of names")
    known = ", ".join([*plain, *(f"{b}[i]" for b in indexed)])
    out = []
    for i, text in enumerate(names):
        where = f"{field}[{i}]"
        base, idx = split_name(text, where)
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
