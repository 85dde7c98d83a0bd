"""Checks of the model argument of the public functions that take a PRBDM."""

from __future__ import annotations

from typing import Any

from ..options.validate import check_type

__all__ = ["check_model"]


def check_model(value: Any, name: str = "model") -> Any:
    """``value`` if it is a :class:`~prbdm_pin.PrbdmModel`; else InputTypeError naming it."""
    from .prbdm_model import PrbdmModel

    return check_type(name, value, PrbdmModel, "a prbdm_pin.PrbdmModel (build_model, "
                      "load_urdf, read_model_json)")
