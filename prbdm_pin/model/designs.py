"""Checks of a batch of designs: models of one joint count and support, and per-design rows.

What the batched simulation, frequencies and linearisation take before any work.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import BeamInputError, InputTypeError

__all__ = ["check_designs", "design_rows"]


def check_designs(models, count: int | None = None, name: str = "models") -> list:
    """Return the designs as a list, each a PrbdmModel of the first one's joints and support.

    One model stands for ``count`` designs (default one). Raises BeamInputError naming the
    entry (``models[3]: 4 joints, the batch has 5``) or an empty batch; InputTypeError for
    what is not a model.
    """
    from .prbdm_model import PrbdmModel

    if isinstance(models, PrbdmModel):
        models = [models] * (count or 1)
    elif not isinstance(models, Sequence) or isinstance(models, (str, bytes)):
        raise InputTypeError(f"{name} = {models!r:.60}: must be a PrbdmModel or a sequence "
                             "of them")
    models = list(models)
    if not models:
        raise BeamInputError(f"{name}: the batch is empty; give at least one PrbdmModel")
    for i, m in enumerate(models):
        if not isinstance(m, PrbdmModel):
            raise InputTypeError(f"{name}[{i}] = {m!r:.60}: must be a PrbdmModel")
    first = models[0]
    key = _key(first)
    for i, m in enumerate(models[1:], start=1):
        if _key(m) == key:
            continue
        if m.pin_model.nv != first.pin_model.nv or m.n_joints != first.n_joints:
            raise BeamInputError(f"{name}[{i}]: {m.n_joints} joints ({m.pin_model.nv} "
                                 f"coordinates), the batch has {first.n_joints} "
                                 f"({first.pin_model.nv})")
        if _support(m) != _support(first):
            raise BeamInputError(f"{name}[{i}]: support {_support(m)}, the batch has "
                                 f"{_support(first)}")
    if count is not None and len(models) != count:
        raise BeamInputError(f"{name}: {len(models)} models for {count} signals; give one "
                             "per design (or one model)")
    return models


def _key(model) -> tuple:
    # what must agree, compared cheaply (a batch checks every design)
    return (model.pin_model.nv, model.lengths_m.size, model.hub is None, model.bus is None,
            model.axes)


def _support(model) -> str:
    kind = "free bus" if model.bus is not None else "hub" if model.hub is not None else \
        "clamped"
    return f"{kind}, axes {model.axes.value!r}"


def design_rows(name: str, value, B: int, n: int) -> np.ndarray:
    """Return ``value`` as B rows of n finite numbers (one shared row is repeated; None: 0).

    Raises BeamInputError naming ``name`` otherwise.
    """
    if value is None:
        return np.zeros((B, n))
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        a = np.full(1, np.nan)
    if a.shape == (n,):
        a = np.tile(a, (B, 1))
    if a.shape != (B, n) or not np.all(np.isfinite(a)):
        raise BeamInputError(f"{name} has shape {np.shape(a)}: must be {n} finite numbers, or "
                             f"({B}, {n}): one row per design")
    return a
