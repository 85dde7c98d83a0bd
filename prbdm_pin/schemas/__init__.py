"""JSON Schemas (draft 2020-12) of the files the package reads and writes: beam, fit, model.

``beam.schema.json`` describes beam JSON, ``fit.schema.json`` what ``prbdm fit`` writes and
``model.schema.json`` a model JSON (``prbdm export --format json``, ``prbdm calibrate``). They are
shipped with the package for editors and other tools; the package's own readers check more than
a schema can (orderings, positivity of a law between stations) and name the field.
"""

from __future__ import annotations

import json
from importlib import resources
from typing import Any

from ..errors import BeamInputError, InputTypeError

__all__ = ["SCHEMA_NAMES", "load_schema"]

SCHEMA_NAMES = ("beam", "fit", "model")


def load_schema(name: str) -> dict[str, Any]:
    """Return the JSON Schema of a file kind.

    Parameters
    ----------
    name : {"beam", "fit", "model"}
        The file kind.

    Returns
    -------
    dict
        The schema; its ``$id`` is what the others' ``$ref`` name.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> schema = pp.load_schema("beam")
    >>> sorted(schema["required"])
    ['x']
    >>> pp.load_schema("truss")
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: name = 'truss': must be one of beam, fit, model
    """
    if not isinstance(name, str):
        raise InputTypeError(f"name = {type(name).__name__}: must be a str, one of "
                             f"{', '.join(SCHEMA_NAMES)}")
    if name not in SCHEMA_NAMES:
        raise BeamInputError(f"name = {name!r}: must be one of {', '.join(SCHEMA_NAMES)}")
    text = resources.files(__name__).joinpath(f"{name}.schema.json").read_text("utf-8")
    return json.loads(text)
