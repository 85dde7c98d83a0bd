"""The chains the compiled kernel and the compiled integrator are checked on (a helper module):
planar 1R-8R, a spatial chain (three axes per node), a hub on each axis and a free bus."""

from __future__ import annotations

import numpy as np

import prbdm_pin as pp
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness


def planar(beam, n: int):
    """An nR chain of equal links on ``beam`` with its finite-segment springs."""
    lengths = np.full(n + 1, 1.0 / (n + 1)) * beam.length_m
    return pp.build_model(beam, lengths, pp.finite_segment_stiffness(beam, lengths))


FOUR = np.array([0.2, 0.3, 0.3, 0.2])


def spatial(beam, axes: str = "xyz"):
    """A 3-node chain with one revolute joint per axis in ``axes`` at each node."""
    lengths = FOUR * beam.length_m
    return pp.build_model(beam, lengths, spatial_stiffness(beam, lengths, axes), axes=axes)


def hub(beam, axis: str):
    """A planar 3R chain on a hub turning about ``axis`` (a heavy hub: no light-hub warning)."""
    lengths = FOUR * beam.length_m
    return pp.build_model(beam, lengths, pp.finite_segment_stiffness(beam, lengths),
                          hub=pp.Hub(5.0, 0.05, axis))


def bus(beam):
    """A planar 3R chain on a free bus (three prismatic, three revolute joints first)."""
    lengths = FOUR * beam.length_m
    return pp.build_model(beam, lengths, pp.finite_segment_stiffness(beam, lengths),
                          support=pp.FreeBus(mass_kg=2.0, inertia_kg_m2=[0.1, 0.2, 0.3]))
