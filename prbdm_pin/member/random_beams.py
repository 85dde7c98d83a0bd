"""Random planforms as in the paper's Section 2.1, the beams of the batch studies."""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError, InputTypeError
from .checks import finite_positive
from .geometry import Beam
from .material import STEEL_4340, Material

__all__ = ["random_beam"]


def random_beam(
    rng: np.random.Generator,
    p: int = 10,
    *,
    length_m: float = 1.0,
    width_scale: float = 0.5,
    min_half_width_m: float = 0.02,
    thickness_m: float | tuple[float, float] = 0.01,
    material: Material = STEEL_4340,
    tip_force_N: tuple[float, float, float] = (0.0, 0.0, -2500.0),
    name: str | None = None,
) -> Beam:
    """Draw a random planform as in the paper's Section 2.1.

    ``p`` sorted uniform stations in (0, 1) plus 0 and 1 give x (scaled by ``length_m``); ``p + 2``
    uniform numbers scaled by ``width_scale`` (the published code's 0.5, so the panel is at most
    1 m wide) give the half-widths. A draw can come out near zero, which makes a link massless
    and the model singular, so half-widths are floored at ``min_half_width_m`` (default 20 mm, 2 %
    of the 1 m span). ``thickness_m`` is a value in m or a (low, high) range drawn uniformly.

    Parameters
    ----------
    rng : numpy.random.Generator
        The only source of randomness.
    p : int
        Number of interior sections (>= 0).
    length_m : float
        Span L, m.
    width_scale : float
        Scale of the uniform half-width draws, m.
    min_half_width_m : float
        Floor of the half-widths, m.
    thickness_m : float or tuple of float
        Thickness, m, or a (low, high) range in m drawn uniformly.
    material : Material
        The material (default AISI 4340 steel).
    tip_force_N : tuple of float
        The static tip load (Fx, Fy, Fz), N.
    name : str, optional
        The beam's name.

    Returns
    -------
    Beam
        The drawn beam.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.random_beam(np.random.default_rng(0), p=3)
    >>> beam.x_m.shape, beam.half_width_m.shape
    ((5,), (5,))
    >>> float(beam.x_m[0]), float(beam.x_m[-1])  # m: the clamp and the span
    (0.0, 1.0)
    >>> bool(np.all(np.diff(beam.x_m) > 0)), bool(beam.half_width_m.min() >= 0.02)
    (True, True)
    >>> again = pp.random_beam(np.random.default_rng(0), p=3)  # the same seed, the same beam
    >>> bool(np.array_equal(again.half_width_m, beam.half_width_m))
    True
    """
    if isinstance(p, bool) or not isinstance(p, (int, np.integer)) or p < 0:
        raise BeamInputError(f"p = {p!r}: must be an integer >= 0")
    finite_positive("length", length_m)
    finite_positive("width_scale", width_scale)
    finite_positive("min_half_width", min_half_width_m)
    if not isinstance(rng, np.random.Generator):
        raise InputTypeError(f"rng = {rng!r}: must be a numpy.random.Generator")
    # strictly inside (0, 1) and distinct: Generator.random is in [0, 1), redraw the rare ties
    while True:
        xi = np.sort(rng.random(p))
        if p == 0 or (xi[0] > 0.0 and np.all(np.diff(xi) > 0.0)):
            break
    x = np.concatenate([[0.0], xi, [1.0]]) * length_m
    w = np.maximum(width_scale * rng.random(p + 2), min_half_width_m)
    if isinstance(thickness_m, tuple):
        lo, hi = (finite_positive("thickness", v) for v in thickness_m)
        if hi < lo:
            raise BeamInputError(f"thickness = {thickness_m}: needs low <= high")
        t = float(rng.uniform(lo, hi))
    else:
        t = finite_positive("thickness", thickness_m)
    return Beam(
        x_m=x, half_width_m=w, thickness_m=t, material=material,
        tip_force_N=np.asarray(tip_force_N, dtype=float),
        name=name or "random",
        description=f"Random planform (paper Sec. 2.1), p = {p}, half-width scale {width_scale}, "
        f"floor {min_half_width_m} m",
    )
