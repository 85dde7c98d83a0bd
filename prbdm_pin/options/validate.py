"""The checks at the package's public doors: argument types, paths, ranges, units and caps.

Every public function checks its arguments on entry, and every public dataclass its fields on
construction, through these functions (built on :mod:`prbdm_pin.option_checks` and
:mod:`prbdm_pin.beam_checks`), so a bad value is refused where it enters, with a message that
names the argument, instead of failing deep inside numpy, Pinocchio, pathlib or the OS:

* a value of the wrong type (a beam that is not a :class:`~prbdm_pin.Beam`, a path that is not a
  str or path-like, a complex link length) raises :class:`~prbdm_pin.errors.InputTypeError`, a
  ``TypeError``;
* a value of the right type out of its range, not finite, or implausible in its unit raises
  :class:`~prbdm_pin.errors.BeamInputError`, a ``ValueError``.

The ranges the command line and the API share are defined here once (the number of starts, the
population, the damping ratio ...); the resource caps that can be raised are in
:mod:`prbdm_pin.limits`. The plausibility ranges catch a unit slip (E in GPa, a thickness in mm)
before a solver fails on it or a truth runs for minutes: E in [1e6, 1e13] Pa (soft rubber to
diamond), every size (the length, thickness, half-widths, a hub's radius, a patch's stations) in
[1e-5, 1e3] m (10 um to 1 km), a planform at most ``MAX_WIDTH_RATIO`` times as wide as long.

Free of numpy at import, like :mod:`prbdm_pin.options`, which uses it, and of the model, the
fits and the command line: the beam and the truth import it, and the truth's cache key digests
every module the truth imports (``truth.digest``). The checks of the public functions' object
arguments and output paths, which import those, are in :mod:`prbdm_pin.validate_args`.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

from ..errors import BeamInputError, InputTypeError
from .checks import check_float, check_int, shown

__all__ = [
    "MAX_SEED", "MAX_WORKERS", "MAX_STARTS", "MAX_NFEV", "MAX_SHARD_BEAMS", "MIN_POP", "MAX_POP",
    "MAX_GENERATIONS", "MAX_SWEEP_RAD", "MAX_DAMPING_RATIO", "E_RANGE_PA", "SIZE_RANGE_M",
    "MAX_WIDTH_RATIO", "SPRING_WINDOW", "MAX_HUB_INERTIA_KG_M2",
    "check_type", "check_path", "check_workers", "check_joints", "check_axes",
    "check_damping_ratio",
    "check_modulus", "check_size", "check_planform", "real_vector",
]

# numpy's SeedSequence takes any integer >= 0; fit.json and the batch manifest store the seed as
# a JSON integer that other tools read as 64-bit.
MAX_SEED = 2**63 - 1
# More local processes than this is a typing slip, not a machine (and each one holds a model).
MAX_WORKERS = 1024
# a start holds its lengths and factors from the outset; more starts is a slip, not a study
MAX_STARTS = 100_000
# a least-squares start's evaluation cap: each evaluation is a model build and eigensolve
MAX_NFEV = 100_000
# the batch driver holds one task per beam of its shard
MAX_SHARD_BEAMS = 1_000_000
# NSGA-II's mating needs a few parents; a population holds its designs and objectives in memory
MIN_POP = 4
MAX_POP = 100_000
MAX_GENERATIONS = 1_000_000
# the pose sweep's offset and step: a joint angle beyond a quarter turn bends the tip backwards
MAX_SWEEP_RAD = math.pi / 2
# a damping ratio is in [0, 1): an over-damped run has no oscillation to compare or fit
MAX_DAMPING_RATIO = 1.0
# Young's modulus of a solid, Pa: soft elastomers (1 MPa) to diamond (1.2 TPa), with margin
E_RANGE_PA = (1e6, 1e13)
# every size of a member, m: 10 um (a thin foil) to 1 km
SIZE_RANGE_M = (1e-5, 1e3)
# a planform at most this many times as wide (2 w) as long: a cantilever, not a plate edge
MAX_WIDTH_RATIO = 20.0
# a joint spring within this factor of the finite-segment springs E I / l the beam can have
SPRING_WINDOW = 1e6
# a hub within the size range of the densest solid (osmium, 22.6 t/m^3, 1 km across)
MAX_HUB_INERTIA_KG_M2 = 1e20


def check_type(name: str, value: Any, cls: type | tuple[type, ...], what: str = "") -> Any:
    """Return ``value`` if it is an instance of ``cls``; else :class:`InputTypeError` naming it.

    ``what`` says what is needed (default the class's public name, ``prbdm_pin.Beam``).
    """
    if isinstance(value, cls):
        return value
    if not what:
        classes = cls if isinstance(cls, tuple) else (cls,)
        what = " or ".join(f"a prbdm_pin.{c.__name__}" if c.__module__.startswith("prbdm_pin")
                           else f"a {c.__name__}" for c in classes)
    raise InputTypeError(f"{name} = {shown(value)}: must be {what}, not "
                         f"{type(value).__name__}")


def check_path(name: str, value: Any, what: str = "file") -> Path:
    """Return ``value`` (a str or ``os.PathLike``) as a Path; naming ``name`` otherwise.

    A wrong type (None, bytes, a number) is an :class:`InputTypeError`; an empty path or one
    holding a NUL character a :class:`BeamInputError`.
    """
    if isinstance(value, (bytes, bytearray)) or not isinstance(value, (str, os.PathLike)):
        raise InputTypeError(f"{name} = {shown(value)}: must be a path (str or os.PathLike) of "
                             f"the {what}, not {type(value).__name__}")
    text = os.fspath(value)
    if not isinstance(text, str):
        raise InputTypeError(f"{name} = {shown(value)}: must be a text path (str), not bytes")
    if text.strip() == "":
        raise BeamInputError(f"{name} = {text!r}: must name the {what}")
    if "\x00" in text:
        raise BeamInputError(f"{name} = {text!r}: a path cannot contain a NUL character")
    return Path(text)


def check_workers(value: Any) -> int:
    """``workers``: an integer in 1..``MAX_WORKERS`` (the command line's ``--workers``)."""
    return check_int("workers", value, 1, high=MAX_WORKERS)


def check_joints(value: Any, name: str = "joints") -> int:
    """Return the number of joints n: an integer >= 1 within the cap ``max_joints``.

    The cap (``limits().max_joints``, ``PRBDM_MAX_JOINTS``) is the command line's ``--joints``
    cap: a 1000-joint chain exhausts memory in its sections and mass matrices.
    """
    from .limits import check_cap

    n = check_int(name, value, 1)
    check_cap(name, n, "max_joints")
    return n


def check_axes(value: Any, name: str = "axes"):
    """Return the :class:`~prbdm_pin.options.choices.Axes` spelled ``value`` (``--axes``).

    Raises
    ------
    BeamInputError
        ``value`` is not one of ``y``, ``xy``, ``yz``, ``xyz`` (nor an Axes).
    """
    from .choices import Axes

    if isinstance(value, Axes):
        return value
    if isinstance(value, str) and value in Axes.values():
        return Axes(value)
    raise BeamInputError(f"{name} = {value!r}: must be one of {', '.join(Axes.values())} "
                         "(joint axes at each node: y bending, z in-plane bending, x torsion)")


def check_damping_ratio(name: str, value: Any) -> float:
    """Return a damping ratio: a finite number in [0, 1) (the command line's ``--damping``)."""
    return check_float(name, value, low=0.0, high=MAX_DAMPING_RATIO, high_open=True,
                       unit="dimensionless; an over-damped ratio >= 1 is refused")


def _unit_hint(value: float, lo: float, hi: float, unit: str,
               slips: tuple[tuple[float, str], ...]) -> str:
    """Name the unit slip that would bring ``value`` into [lo, hi], as advice."""
    for factor, slip in slips:
        if lo <= value * factor <= hi:
            return (f"; given in {slip}? it is in {unit} ({value:g} {slip} = "
                    f"{value * factor:.6g} {unit})")
    return f"; check the unit: it is in {unit}"


def check_modulus(name: str, value: Any) -> float:
    """Young's modulus: a finite number in ``E_RANGE_PA``; the message suggests a unit slip."""
    E = check_float(name, value, low=0.0, low_open=True, unit="Pa")
    lo, hi = E_RANGE_PA
    if not lo <= E <= hi:
        hint = _unit_hint(E, lo, hi, "Pa", ((1e9, "GPa"), (1e6, "MPa"), (1e3, "kPa")))
        raise BeamInputError(f"{name} = {E:.6g} Pa: outside the plausible range {lo:g} ... "
                             f"{hi:g} Pa of solids (soft rubber to diamond){hint}")
    return E


def check_size(name: str, value: Any, *, low: float | None = None) -> float:
    """Return a size in m: finite, > 0 (or >= ``low``), within ``SIZE_RANGE_M``.

    ``low=0.0`` admits a size of exactly 0 (a hub's radius, a patch starting at the root). The
    message suggests the unit slip that would bring the value into range.
    """
    v = check_float(name, value, low=0.0, low_open=low is None, unit="m")
    lo, hi = SIZE_RANGE_M
    if (v == 0.0 and low is not None) or lo <= v <= hi:
        return v
    hint = _unit_hint(v, lo, hi, "m", ((1e-3, "mm"), (1e-2, "cm"), (1e-6, "um")))
    raise BeamInputError(f"{name} = {v:.6g} m: outside the plausible range {lo:g} ... {hi:g} m "
                         f"of a member's sizes{hint}")


def check_planform(x_m, half_width_m, thickness_m: float) -> None:
    """Check a beam's sizes: its length, thickness and half-widths, and its width ratio.

    Each lies in ``SIZE_RANGE_M`` (:func:`check_size`), and the planform is at most
    ``MAX_WIDTH_RATIO`` times as wide as long (a 300 m wide, 1 m long "panel" is a
    half-width in mm read as m: its truth would mesh the whole width for minutes).
    """
    L = check_size("length (x[-1])", float(x_m[-1]))
    check_size("thickness", thickness_m)
    i_lo, i_hi = int(half_width_m.argmin()), int(half_width_m.argmax())
    check_size(f"half_width[{i_lo}]", float(half_width_m[i_lo]))
    w = check_size(f"half_width[{i_hi}]", float(half_width_m[i_hi]))
    if 2.0 * w > MAX_WIDTH_RATIO * L:
        raise BeamInputError(
            f"half_width[{i_hi}] = {w:.6g} m: the member would be {2 * w:.6g} m wide, "
            f"{2 * w / L:.3g} times its length L = {L:.6g} m (at most {MAX_WIDTH_RATIO:g} "
            "times: a cantilever, not the clamped edge of a wide plate); half-widths in mm?")


def real_vector(name: str, value: Any, unit: str, size: int | None = None):
    """Return ``value`` as a read-only float vector of finite real numbers.

    Refused, naming ``name``: a string or mapping, complex or non-numeric entries
    (:class:`InputTypeError`); a wrong length, NaN or infinity (:class:`BeamInputError`).
    """
    import numpy as np

    if isinstance(value, (str, bytes, dict)) or value is None:
        raise InputTypeError(f"{name} = {shown(value)}: must be a list of numbers ({unit})")
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):
        raise InputTypeError(f"{name} = {shown(value)}: must be a list of numbers "
                             f"({unit})") from None
    if raw.dtype.kind not in "iuf" or raw.ndim > 1:
        if raw.dtype.kind == "O" and raw.ndim == 1:
            for i, v in enumerate(raw):
                check_float(f"{name}[{i}]", v, unit=unit)
        elif raw.ndim > 1:
            raise BeamInputError(f"{name} has shape {raw.shape}: must be a flat list of "
                                 f"numbers ({unit})")
        else:
            kind = "complex" if raw.dtype.kind == "c" else raw.dtype.name
            raise InputTypeError(f"{name} = {shown(value)}: must be real numbers ({unit}), not "
                                 f"{kind}")
    a = np.array(raw, dtype=float).reshape(-1)
    if size is not None and a.size != size:
        raise BeamInputError(f"{name} has {a.size} entries: must have {size} ({unit})")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        i = int(bad[0])
        raise BeamInputError(f"{name}[{i}] = {a[i]}: must be finite ({unit})")
    a.setflags(write=False)
    return a
