"""One static load case of a fit: a tip force (and moment) with the truth's tip under it.

Also the read-only array helper the fit's dataclasses share.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError
from ..options.validate import real_vector

__all__ = ["LoadCase", "read_only"]

def read_only(a, shape: tuple | None = None) -> np.ndarray:
    """Return a read-only float copy of ``a``, reshaped to ``shape`` when given.

    Frozen dataclasses hold arrays nobody can change under them.
    """
    a = np.array(a, dtype=float)
    if shape is not None:
        a = a.reshape(shape)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class LoadCase:
    """A static load case of the truth: a dead tip force and the truth's tip under it.

    Attributes
    ----------
    tip_force_N : ndarray, shape (3,)
        Force at the tip, N (world).
    tip_position_m, tip_displacement_m : ndarray, shape (3,)
        Truth large-deflection tip position and displacement under it, m.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> case = pp.LoadCase(tip_force_N=[0, 0, -10.0], tip_position_m=[1.0, 0, -0.004],
    ...                    tip_displacement_m=[0, 0, -0.004])
    >>> case.tip_force_N
    array([  0.,   0., -10.])
    >>> pp.LoadCase(tip_force_N=[0, 0, -10.0], tip_position_m=[1.0, 0, 0],
    ...             tip_displacement_m=[0, 0, 0])
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: tip_displacement_m = 0: a load case needs a deflection
    """

    tip_force_N: np.ndarray
    tip_position_m: np.ndarray
    tip_displacement_m: np.ndarray

    def __post_init__(self) -> None:
        """Check the three vectors are 3 finite reals and the deflection nonzero; freeze them."""
        for name, unit in (("tip_force_N", "N"), ("tip_position_m", "m"),
                           ("tip_displacement_m", "m")):
            object.__setattr__(self, name, real_vector(name, getattr(self, name), unit, 3))
        if not np.linalg.norm(self.tip_displacement_m) > 0.0:
            raise BeamInputError("tip_displacement_m = 0: a load case needs a deflection")
