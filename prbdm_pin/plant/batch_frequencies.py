"""``frequencies_batch``: the natural frequencies of many designs in one stacked eigensolve.

For planar clamped chains the mass matrices of every design come from the closed form
(:func:`prbdm_pin.chain.planar_batch.batch_mass`, checked against Pinocchio's CRBA in the
tests) in a few numpy calls, and the frequencies from one stacked symmetric eigensolve
(:func:`prbdm_pin.chain.eigen.eig_scaled`, ``numpy.linalg.eigvalsh`` over the stack of
K^-1/2 M K^-1/2): what ``model.natural_frequencies`` computes for one design. Hubs, free
buses, spatial chains and a chain the closed form does not describe are looped through
``model.natural_frequencies``.
"""

from __future__ import annotations

import numpy as np

from ..chain.eigen import eig_scaled
from ..chain.planar_batch import batch_mass, design_links
from ..model.designs import check_designs, design_rows

__all__ = ["frequencies_batch"]


def frequencies_batch(models, q_rad: np.ndarray | None = None, squared: bool = False
                      ) -> np.ndarray:
    """Natural frequencies of B designs, each at its pose, rad/s ascending, shape (B, nv).

    Parameters
    ----------
    models : sequence of PrbdmModel
        The designs: one joint count and support (``models[i]`` is refused otherwise).
    q_rad : array_like, shape (nv,) or (B, nv), optional
        The pose, shared or one per design, rad; default straight.
    squared : bool
        Return omega^2, rad^2/s^2.

    Returns
    -------
    ndarray, shape (B, nv)
        Row b is ``models[b].natural_frequencies(q_rad[b])``.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> models = [pp.build_model(beam, [0.2, 0.5, 0.3], [k, 1200.0]) for k in (2500.0, 5000.0)]
    >>> w = pp.frequencies_batch(models)
    >>> w.shape, bool(np.allclose(w[1], models[1].natural_frequencies()))
    ((2, 2), True)
    """
    models = check_designs(models)
    B, nv = len(models), int(models[0].pin_model.nv)
    Q = design_rows("q_rad", q_rad, B, nv)
    m0 = models[0]
    links = None
    if m0.hub is None and m0.bus is None and not m0.axes.spatial:
        links = design_links(models)
    if links is None:
        return np.array([m.natural_frequencies(q, squared) for m, q in zip(models, Q,
                                                                             strict=True)])
    M = batch_mass(links, Q)
    s = 1.0 / np.sqrt(np.array([m.stiffness_Nm_per_rad for m in models], dtype=float))
    return eig_scaled(M, s, squared)
