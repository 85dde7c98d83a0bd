"""Beam JSON: the mapping read into a validated :class:`~prbdm_pin.member.geometry.Beam`.

And the beam written back as a file.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

from ..errors import BeamInputError, InputTypeError
from ..io.atomic import atomic_write_json
from ..io.jsonfile import field_str, read_json
from ..member.checks import finite_positive
from ..member.geometry import Beam, beam_to_dict
from ..member.material import STEEL_4340, Material
from ..member.section_member import round_beam, table_beam
from ..member.section_table import TABLE_FIELDS, TABLE_REQUIRED, SectionTable
from ..options.limits import check_cap

__all__ = ["beam_from_dict", "load_beam", "save_beam"]

_KEYS_REQUIRED = {"x", "half_width", "thickness"}
_KEYS_OPTIONAL = {"length", "material", "tip_force", "name", "description"}
_KEYS_SECTION = {"x", "section"}
_MATERIAL_KEYS = {"name", "E", "rho", "nu"}
_ROUND_KEYS = {"kind", "outer_diameter", "inner_diameter"}


def _section(d: dict) -> dict:
    """Return the ``"section"`` mapping of a round member, keys checked (values: by the Beam)."""
    sec = d["section"]
    if not isinstance(sec, dict):
        raise InputTypeError(f"section = {sec!r}: must be an object such as "
                             '{"kind": "round", "outer_diameter": [...]}')
    kind = sec.get("kind")
    if kind == "table":
        return _table(sec)
    if kind != "round":
        raise BeamInputError(f"section.kind = {kind!r}: unknown; use \"round\" (outer_diameter, "
                             "inner_diameter lists aligned with x) or \"table\" (EI_y_Nm2, ...)")
    unknown = set(sec) - _ROUND_KEYS
    if unknown:
        raise BeamInputError(f"unknown key(s) in section {sorted(unknown)}: allowed are "
                             f"{sorted(_ROUND_KEYS)}")
    if "outer_diameter" not in sec:
        raise BeamInputError("section.outer_diameter missing: a round section needs the "
                             "outer diameters (m, a list aligned with x)")
    for key in ("outer_diameter", "inner_diameter"):
        if key in sec and not isinstance(sec[key], list):
            raise InputTypeError(f"section.{key} = {sec[key]!r}: must be a list aligned with "
                                 "x (m)")
    return sec


def _table(sec: dict) -> dict:
    """Check a table section's keys: the required lists present, no unknown key."""
    allowed = {"kind", *TABLE_FIELDS}
    unknown = set(sec) - allowed
    if unknown:
        raise BeamInputError(f"unknown key(s) in section {sorted(unknown)}: allowed are "
                             f"{sorted(allowed)}")
    missing = [k for k in TABLE_REQUIRED if k not in sec]
    if missing:
        raise BeamInputError(f"section.{missing[0]} missing: a section table needs "
                             f"{', '.join(TABLE_REQUIRED)} (lists aligned with x; rhoI_x_kg_m "
                             "optional, rhoI_y_kg_m + rhoI_z_kg_m by default)")
    for key in set(sec) - {"kind"}:
        if not isinstance(sec[key], list):
            raise InputTypeError(f"section.{key} = {sec[key]!r}: must be a list aligned with "
                                 f"x ({TABLE_FIELDS[key]})")
    return sec


def beam_from_dict(d: Any, *, check_caps: bool = False) -> Beam:
    """Build a :class:`Beam` from the beam-JSON mapping (SI units), validating every field.

    Keys and defaults are as in :func:`load_beam`: no ``tip_force`` means no load.

    ``check_caps`` (the readers of beam, fit.json and model files set it) also refuses more
    than ``limits().max_vertices`` vertices; a mapping built in code is not capped.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.beam_from_dict({"length": 1.0, "x": [0.0, 1.0], "half_width": [0.025, 0.025],
    ...                           "thickness": 0.01,
    ...                           "material": {"E": 205e9, "rho": 7850.0, "nu": 0.28}})
    >>> round(beam.mass_kg, 3)  # kg, 7850 kg/m^3 x 1 m x 0.05 m x 0.01 m
    3.925
    >>> pp.beam_from_dict({"x": [0.0, 1.0]})
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: missing key(s) ['half_width', 'thickness']
    """
    if not isinstance(d, dict):
        raise InputTypeError(f"beam = {type(d).__name__}: must be a JSON object (a dict)")
    section = _section(d) if "section" in d else None
    required = _KEYS_SECTION if section is not None else _KEYS_REQUIRED
    unknown = set(d) - required - _KEYS_OPTIONAL
    if unknown:
        why = " (a section replaces half_width and thickness)" if section is not None else ""
        raise BeamInputError(f"unknown key(s) {sorted(unknown)}{why}: allowed are "
                             f"{sorted(required | _KEYS_OPTIONAL)}")
    missing = required - set(d)
    if missing:
        raise BeamInputError(f"missing key(s) {sorted(missing)}")
    # before any array is built: a 200k-vertex planform exhausts the solvers, not the parser
    for key in (("x",) if section else ("x", "half_width", "thickness")) if check_caps else ():
        if isinstance(d[key], list):
            check_cap(f"{key} (vertices)", len(d[key]), "max_vertices")
    for key in (set(section) - {"kind"}) if check_caps and section else ():
        if isinstance(section.get(key), list):
            check_cap(f"section.{key} (stations)", len(section[key]), "max_vertices")
    mat_d = d.get("material", {})
    if not isinstance(mat_d, dict):
        raise BeamInputError(f"material = {mat_d!r}: must be an object with E, rho, nu")
    unknown = set(mat_d) - _MATERIAL_KEYS
    if unknown:
        raise BeamInputError(f"unknown key(s) in material {sorted(unknown)}: allowed are "
                             f"{sorted(_MATERIAL_KEYS)}")
    name = field_str("material.name", mat_d.get("name", STEEL_4340.name))
    material = Material(
        name=name,
        E_Pa=mat_d.get("E", STEEL_4340.E_Pa),
        rho_kg_m3=mat_d.get("rho", STEEL_4340.rho_kg_m3),
        nu=mat_d.get("nu", STEEL_4340.nu),
    )
    for key in ("name", "description"):
        if key in d:
            field_str(key, d[key])
    if section is not None and section["kind"] == "table":
        table = SectionTable(**{k: v for k, v in section.items() if k != "kind"})
        beam = table_beam(d["x"], table, material, d.get("tip_force", [0.0, 0.0, 0.0]),
                          d.get("name", "beam"), d.get("description", ""))
    elif section is not None:
        beam = round_beam(d["x"], section["outer_diameter"], section.get("inner_diameter"),
                          material, d.get("tip_force", [0.0, 0.0, 0.0]),
                          d.get("name", "beam"), d.get("description", ""))
    else:
        beam = Beam(
            x_m=d["x"],
            half_width_m=d["half_width"],
            thickness_m=d["thickness"],
            material=material,
            tip_force_N=d.get("tip_force", [0.0, 0.0, 0.0]),
            name=d.get("name", "beam"),
            description=d.get("description", ""),
        )
    if "length" in d:
        length = finite_positive("length", d["length"])
        if not math.isclose(length, beam.length_m, rel_tol=1e-12, abs_tol=0.0):
            raise BeamInputError(
                f"length = {length} m: must equal the last x vertex ({beam.length_m} m)"
            )
    return beam


def load_beam(path: str | os.PathLike) -> Beam:
    """Read a beam JSON file; any defect raises :class:`BeamInputError` naming the field.

    Required keys: ``x``, ``half_width`` (m), ``thickness`` (m: a number, or a list aligned with
    ``x``, the piecewise-linear law t(x), > 0 at every station). Optional: ``length`` (m, checked
    against the last x), ``material`` (default steel AISI 4340), ``name``, ``description`` and
    ``tip_force`` ([Fx, Fy, Fz] in N): without it the beam has no load, [0, 0, 0] N, which is
    enough for eigen (frequency) fits; deflection, combined and Pareto fits refuse a zero load.
    The file is read by :func:`prbdm_pin.io.jsonfile.read_json` (size, UTF-8, depth, integer
    length, finiteness). A round member replaces ``half_width`` and ``thickness`` by
    ``"section": {"kind": "round", "outer_diameter": [...], "inner_diameter": [...]}`` (m,
    lists aligned with ``x``; the inner one optional, a solid rod without it); its material
    gives E, G and rho. A table member gives ``"section": {"kind": "table", "EI_y_Nm2": [...],
    "EI_z_Nm2", "GJ_Nm2", "rhoA_kg_m", "rhoI_y_kg_m", "rhoI_z_kg_m": [...]}`` (lists aligned
    with ``x``, units in the names; ``rhoI_x_kg_m`` optional, rhoI_y + rhoI_z by default); its
    material is optional and changes no result. At most ``limits().max_vertices`` vertices
    (``PRBDM_MAX_VERTICES``); names hold no control characters.

    Parameters
    ----------
    path : str or path-like
        The beam JSON file.

    Returns
    -------
    Beam
        The validated beam (SI units).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> path = pp.save_beam(beam, folder / "beam.json")
    >>> again = pp.load_beam(path)
    >>> again.length_m, round(again.mass_kg, 3)
    (1.0, 3.925)
    """
    return beam_from_dict(read_json(path, "beam file"), check_caps=True)


def save_beam(beam: Beam, path: str | os.PathLike) -> Path:
    """Write ``beam`` as beam JSON (atomically).

    Parameters
    ----------
    beam : Beam
        The beam; the file holds it in SI units (m, Pa, kg/m^3, N).
    path : str or path-like
        The file to write; its folder is created when missing.

    Returns
    -------
    pathlib.Path
        The file written.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> path = pp.save_beam(beam, folder / "beam.json")
    >>> pp.load_beam(path).fingerprint() == beam.fingerprint()
    True
    """
    from ..io.paths import check_out_file
    from ..options.validate import check_type

    check_type("beam", beam, Beam)
    check_out_file("path", path)
    return atomic_write_json(path, beam_to_dict(beam))
