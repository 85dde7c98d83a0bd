"""The design parameters of a trajectory gradient: their groups, names and units."""

from __future__ import annotations

from collections.abc import Sequence

from ..errors import BeamInputError, InputTypeError

__all__ = ["PARAMETER_GROUPS", "parameter_groups", "parameter_names"]

# the groups of design parameters, in the order their columns take
PARAMETER_GROUPS = ("springs", "stations", "beta", "dampers", "gain", "initial")


def parameter_groups(parameters) -> tuple[str, ...]:
    """Return the groups asked for, in column order; refuse unknown or repeated ones."""
    if isinstance(parameters, str) or not isinstance(parameters, Sequence):
        raise InputTypeError(f"parameters = {parameters!r:.80}: must be a sequence of names "
                             f"among {', '.join(PARAMETER_GROUPS)}")
    for i, p in enumerate(parameters):
        if p not in PARAMETER_GROUPS:
            raise BeamInputError(f"parameters[{i}] = {p!r}: unknown; must be among "
                                 f"{', '.join(PARAMETER_GROUPS)}")
    if len(set(parameters)) != len(parameters):
        raise BeamInputError(f"parameters = {list(parameters)}: each group once")
    return tuple(g for g in PARAMETER_GROUPS if g in parameters)


def parameter_names(groups, n: int, inputs: tuple[str, ...], units: tuple[str, ...]):
    """Return the columns' names and units for ``groups`` of an n-joint chain."""
    names, out_units = [], []
    for g in groups:
        if g == "springs":
            names += [f"k[{j}]" for j in range(n)]
            out_units += ["N m/rad"] * n
        elif g == "stations":
            names += [f"x[{j + 1}]" for j in range(n)]
            out_units += ["m"] * n
        elif g == "beta":
            names.append("beta")
            out_units.append("s")
        elif g == "dampers":
            names += [f"c[{j}]" for j in range(n)]
            out_units += ["N m s/rad"] * n
        elif g == "initial":
            names += [f"q0[{j}]" for j in range(n)] + [f"v0[{j}]" for j in range(n)]
            out_units += ["rad"] * n + ["rad/s"] * n
        else:
            for name, unit in zip(inputs, units, strict=True):
                names += [f"G[{name},q[{j}]]" for j in range(n)]
                names += [f"G[{name},v[{j}]]" for j in range(n)]
                out_units += [f"{unit}/rad"] * n + [f"{unit} s/rad"] * n
    return tuple(names), tuple(out_units)
