"""Beam input: material, planform and thickness; validation, beam JSON, random beams.

Conventions: the beam axis is x with the clamped root at x = 0 and the tip at x = L; the
planform is symmetric about the x axis with a piecewise-linear half-width w(x) through the
vertices (x_k, w_k); the thickness t is uniform and bending is out of plane (deflection along z).
Two vertices may share a station x_k (never more, and never at the root or the tip): a width step,
where the half-width jumps; w(x) is right-continuous there (the tip-side value).
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import BeamInputError
from .jsonfile import field_str, read_json
from .limits import check_cap

__all__ = [
    "Material",
    "Beam",
    "STEEL_4340",
    "beam_from_dict",
    "beam_to_dict",
    "load_beam",
    "save_beam",
    "random_beam",
    "atomic_write_text",
]


def _finite_positive(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise BeamInputError(f"{name} = {value!r}: must be a number")
    v = float(value)
    if not math.isfinite(v):
        raise BeamInputError(f"{name} = {v}: must be finite")
    if v <= 0.0:
        raise BeamInputError(f"{name} = {v}: must be > 0")
    return v


def _float_array(name: str, value: Any, unit: str) -> np.ndarray:
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__"):
        raise BeamInputError(f"{name} = {value!r}: must be a list of numbers ({unit})")
    for i, v in enumerate(value):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
            raise BeamInputError(f"{name}[{i}] = {v!r}: must be a number ({unit})")
    arr = np.array(value, dtype=float).reshape(-1)
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        i = int(bad[0])
        raise BeamInputError(f"{name}[{i}] = {arr[i]}: must be finite ({unit})")
    return arr


def _check_representable(x: np.ndarray, w: np.ndarray, t: float, material: Material) -> None:
    """Reject units so extreme that derived quantities leave double precision's normal range.

    E I = E 2 w t^3 / 12, the mass and the load index L^2 / (E I) must be normal positive floats;
    otherwise they underflow to 0 or overflow (e.g. a thickness in mm read as m, cubed).
    """
    tiny, huge = np.finfo(float).tiny, np.finfo(float).max
    L = float(x[-1])
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        t3 = np.float64(t) ** 3
        EI = material.E_Pa * 2.0 * np.array([w.min(), w.max()]) * t3 / 12.0
        area = 2.0 * float(np.sum(0.5 * (w[1:] + w[:-1]) * np.diff(x)))
        mass = np.array([material.rho_kg_m3 * t * area])
        index = np.float64(L) ** 2 / EI
        # the section integrals form 2 w^3 and 2 w x^2 before the Gauss weights and rho t
        # scale them, and the links' inertias are of the order of m (L^2 + w^2 + t^2)
        wmax = np.float64(w.max())
        integrand = np.array([2.0 * wmax**3, 2.0 * wmax * np.float64(L) ** 2]) * 64.0
        inertia = mass * (np.float64(L) ** 2 + wmax**2 + np.float64(t) ** 2)
    fields_EI = f"thickness = {t!r} m, half_width = {w.min():g} ... {w.max():g} m, " \
        f"material.E = {material.E_Pa!r} Pa"
    checks = (
        (fields_EI, "E I = E 2 w t^3 / 12", EI, "N m^2"),
        (f"x (L = {L!r} m), half_width, thickness = {t!r} m, material.rho = "
         f"{material.rho_kg_m3!r} kg/m^3", "mass", mass, "kg"),
        (f"x (L = {L!r} m), {fields_EI}", "L^2 / (E I)", index, "1/N"),
        (f"x (L = {L!r} m), half_width = {w.min():g} ... {w.max():g} m", "the section "
         "integrands 2 w^3, 2 w L^2 (x 64)", integrand, "m^3"),
        (f"x (L = {L!r} m), half_width, thickness = {t!r} m, material.rho = "
         f"{material.rho_kg_m3!r} kg/m^3", "the links' inertia m (L^2 + w^2 + t^2)", inertia,
         "kg m^2"),
    )
    for fields, what, q, unit in checks:
        if not np.all(np.isfinite(q) & (q >= tiny) & (q <= huge)):
            raise BeamInputError(
                f"{fields}: {what} = {q.min():.3g} ... {q.max():.3g} {unit} is outside double "
                "precision's normal range (check the units: SI, m, Pa, kg/m^3)"
            )


def _check_stations(x: np.ndarray, w: np.ndarray) -> None:
    """x non-decreasing from 0 to L, at most two vertices per station, steps inside (0, L) with
    different half-widths (a repeated vertex is not a step and would only hide a typo)."""
    dx = np.diff(x)
    bad = np.flatnonzero(dx < 0.0)
    if bad.size:
        i = int(bad[0]) + 1
        raise BeamInputError(
            f"x[{i}] = {x[i]} m: must not decrease (x[{i - 1}] = {x[i - 1]} m)"
        )
    same = np.flatnonzero(dx == 0.0)
    for j in same:
        i = int(j) + 1
        if j + 1 in same:
            raise BeamInputError(
                f"x[{i - 1}] = x[{i}] = x[{i + 1}] = {x[i]} m: at most two vertices may share a "
                "station (a width step)"
            )
        if x[i] == 0.0:
            raise BeamInputError(
                f"x[{i}] = {x[i]} m: a width step at the root is meaningless (the clamp holds "
                f"the first section); give one vertex at x = 0"
            )
        if i == x.size - 1:
            raise BeamInputError(
                f"x[{i}] = {x[i]} m: a width step at the tip is meaningless (the beam ends "
                f"there); give one vertex at x = L"
            )
        if w[i] == w[i - 1]:
            raise BeamInputError(
                f"x[{i}] = x[{i - 1}] = {x[i]} m with half_width {w[i]} m on both: a repeated "
                "vertex, not a width step (remove one, or give the two half-widths)"
            )


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class Material:
    """Linear elastic isotropic material.

    Attributes
    ----------
    name : str
    E_Pa : float
        Young's modulus in Pa.
    rho_kg_m3 : float
        Density in kg/m^3.
    nu : float
        Poisson's ratio (dimensionless, in (-1, 0.5)).
    """

    name: str = "steel AISI 4340"
    E_Pa: float = 205e9
    rho_kg_m3: float = 7850.0
    nu: float = 0.28

    def __post_init__(self) -> None:
        # a control character makes the URDF/MJCF that carry the name unreadable XML
        field_str("material.name", self.name)
        _finite_positive("material.E", self.E_Pa)
        _finite_positive("material.rho", self.rho_kg_m3)
        if isinstance(self.nu, bool) or not isinstance(self.nu, (int, float, np.floating)):
            raise BeamInputError(f"material.nu = {self.nu!r}: must be a number")
        if not (math.isfinite(self.nu) and -1.0 < self.nu < 0.5):
            raise BeamInputError(f"material.nu = {self.nu}: must be in (-1, 0.5)")

    @property
    def G_Pa(self) -> float:
        """Shear modulus in Pa."""
        return self.E_Pa / (2.0 * (1.0 + self.nu))


STEEL_4340 = Material()


@dataclass(frozen=True, eq=False)
class Beam:
    """A clamped-free compliant member of uniform thickness and symmetric planform.

    Attributes
    ----------
    x_m : ndarray, shape (k,)
        Planform vertex stations in m; x_m[0] = 0 (the clamp), non-decreasing, x_m[-1] = L. Two
        equal stations x_k = x_(k+1) inside (0, L) are a width step: the half-width jumps from
        w_k to w_(k+1) there.
    half_width_m : ndarray, shape (k,)
        Half-width w(x_k) in m (> 0); the width is 2 w, linear between vertices.
    thickness_m : float
        Uniform thickness t in m.
    material : Material
    tip_force_N : ndarray, shape (3,)
        The load case: a force at the tip in world axes, N.
    name, description : str
    """

    x_m: np.ndarray
    half_width_m: np.ndarray
    thickness_m: float
    material: Material = field(default_factory=Material)
    tip_force_N: np.ndarray = field(default_factory=lambda: np.zeros(3))
    name: str = "beam"
    description: str = ""

    def __post_init__(self) -> None:
        field_str("name", self.name)
        field_str("description", self.description)
        x = _float_array("x", self.x_m, "m")
        w = _float_array("half_width", self.half_width_m, "m")
        if x.size < 2:
            raise BeamInputError(f"x has {x.size} entries: needs at least 2 (root and tip)")
        if w.size != x.size:
            raise BeamInputError(
                f"half_width has {w.size} entries: must match x ({x.size} entries)"
            )
        if x[0] != 0.0:
            raise BeamInputError(f"x[0] = {x[0]} m: must be 0 (the clamped root)")
        _check_stations(x, w)
        bad = np.flatnonzero(w <= 0.0)
        if bad.size:
            i = int(bad[0])
            raise BeamInputError(f"half_width[{i}] = {w[i]} m: must be > 0")
        t = _finite_positive("thickness", self.thickness_m)
        if not isinstance(self.material, Material):
            raise BeamInputError(f"material = {self.material!r}: must be a Material")
        f = _float_array("tip_force", self.tip_force_N, "N")
        if f.size != 3:
            raise BeamInputError(f"tip_force has {f.size} entries: must be [Fx, Fy, Fz] in N")
        _check_representable(x, w, t, self.material)
        object.__setattr__(self, "x_m", _readonly(x))
        object.__setattr__(self, "half_width_m", _readonly(w))
        object.__setattr__(self, "thickness_m", t)
        object.__setattr__(self, "tip_force_N", _readonly(f))
        steps = np.flatnonzero(np.diff(x) == 0.0)
        steps.setflags(write=False)
        object.__setattr__(self, "_steps", steps)  # read in the fit's inner loop

    # Derived geometry -------------------------------------------------------------------------
    @property
    def length_m(self) -> float:
        """Beam length L in m."""
        return float(self.x_m[-1])

    @property
    def step_index(self) -> np.ndarray:
        """Indices k of the width steps, x_m[k] == x_m[k + 1] (int, possibly empty)."""
        return self._steps

    @property
    def intervals_m(self) -> tuple[np.ndarray, np.ndarray]:
        """Starts and ends (m) of the vertex intervals of positive length, where w is linear
        (the zero-length "intervals" of width steps left out)."""
        keep = np.diff(self.x_m) > 0.0
        return self.x_m[:-1][keep], self.x_m[1:][keep]

    def half_width_at(self, x_m: np.ndarray | float, side: str = "right") -> np.ndarray:
        """Half-width w(x) in m at stations ``x_m`` (m), linear between vertices.

        At a width step w is right-continuous (``side="right"``, the tip-side value); ``"left"``
        gives the root-side limit there. Elsewhere both are the same.
        """
        if side not in ("left", "right"):
            raise ValueError(f"side = {side!r}: must be 'left' or 'right'")
        w = np.interp(x_m, self.x_m, self.half_width_m)
        k = self.step_index
        if not k.size:
            return w
        # np.interp leaves a repeated abscissa to its implementation: set it explicitly
        x = np.asarray(x_m, dtype=float)
        w = np.array(w, dtype=float)
        for xs, ws in zip(self.x_m[k], self.half_width_m[k + 1 if side == "right" else k],
                          strict=True):
            w[x == xs] = ws
        return w[()] if w.ndim == 0 else w

    def area_moment_at(self, x_m: np.ndarray | float, side: str = "right") -> np.ndarray:
        """Bending area moment I_yy(x) = 2 w(x) t^3 / 12 in m^4 (``side`` as in
        :meth:`half_width_at`)."""
        return 2.0 * self.half_width_at(x_m, side) * self.thickness_m**3 / 12.0

    @property
    def planform_area_m2(self) -> float:
        """Planform area in m^2 (exact for the piecewise-linear outline; a step's zero-length
        interval adds nothing)."""
        return float(2.0 * np.trapezoid(self.half_width_m, self.x_m))

    @property
    def mass_kg(self) -> float:
        """Total mass in kg."""
        return self.planform_area_m2 * self.thickness_m * self.material.rho_kg_m3

    @property
    def root_EI_Nm2(self) -> float:
        """Bending stiffness E I at the root section, N m^2 (the load index uses it)."""
        return float(self.material.E_Pa * self.area_moment_at(0.0))

    def load_index(self, force_N: float | None = None) -> float:
        """Load index P L^2 / (E I_root) of a tip force magnitude (default: this beam's load)."""
        P = float(np.linalg.norm(self.tip_force_N)) if force_N is None else float(force_N)
        return P * self.length_m**2 / self.root_EI_Nm2

    def kirchhoff_warnings(self, modes: int = 5, tol_pct: float = 1.0) -> tuple[str, ...]:
        """Where a Kirchhoff plate (the ``plate`` truths) misrepresents this beam, as warnings.

        Kirchhoff theory neglects transverse shear and rotary inertia. By Timoshenko (and
        Mindlin) theory they lower bending mode m of wavenumber k_m = beta_m / L by about
        (k_m r)^2 (1 + E / (kappa G)) / 2 (r^2 = t^2 / 12, kappa = 5/6): 0.60 (t/L)^2 for
        mode 1 and a factor beta_m^2 / beta_1^2 more for mode m (about 0.6 % at t = L/10 on
        mode 1, 1 % at t = L/45 on mode 4). A warning when that exceeds ``tol_pct`` (%) for the
        highest of ``modes`` modes. Across the width a Kirchhoff plate needs the width to exceed
        the thickness: a section thicker than wide is a bar whose softer, lateral bending in the
        plane of the planform a plate cannot have (at t/width = 0.2, the shipped narrow
        strips, the plate stays within a few tenths of a percent of Euler-Bernoulli theory).

        Parameters
        ----------
        modes : int
            Bending modes the truth selects.
        tol_pct : float
            Estimated shear and rotary-inertia error that triggers a warning, %.
        """
        m = max(int(modes), 1)
        roots = (1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349)
        beta = roots[m - 1] if m <= 4 else (m - 0.5) * np.pi
        t, L = self.thickness_m, self.length_m
        shear = 1.0 + self.material.E_Pa / (5.0 / 6.0 * self.material.G_Pa)
        est = 100.0 * 0.5 * (beta * t / L) ** 2 / 12.0 * shear
        out = []
        advice = "use the 3D solid (prbdm truth --model solid, prbdm fit --truth-model solid)"
        if est > tol_pct:
            out.append(
                f"thickness = {t:g} m is {t / L:.3g} L: past Kirchhoff plate theory for "
                f"{m} mode{'s' if m > 1 else ''} (transverse shear and rotary inertia, which "
                f"it neglects, lower mode {m} by "
                f"{f'about {est:.2g} %' if est < 10 else 'far more than 10 %'}); {advice}"
            )
        b = 2.0 * float(self.half_width_m.min())
        if t > b:
            out.append(
                f"thickness = {t:g} m exceeds the narrowest width {b:g} m: that section is a bar, "
                f"not a plate (Kirchhoff theory needs t << width; its lateral, in-plane bending "
                f"is softer than the plate's and absent from it); {advice}"
            )
        return tuple(out)

    def with_tip_force(self, tip_force_N: np.ndarray) -> Beam:
        """A copy with another tip force (N)."""
        return Beam(
            self.x_m, self.half_width_m, self.thickness_m, self.material,
            np.asarray(tip_force_N, dtype=float), self.name, self.description,
        )

    def fingerprint(self) -> str:
        """A stable SHA-256 hex digest of the beam's physical content (for caches)."""
        import hashlib

        d = beam_to_dict(self)
        d.pop("name", None)
        d.pop("description", None)
        return hashlib.sha256(json.dumps(d, sort_keys=True).encode()).hexdigest()


_KEYS_REQUIRED = {"x", "half_width", "thickness"}
_KEYS_OPTIONAL = {"length", "material", "tip_force", "name", "description"}
_MATERIAL_KEYS = {"name", "E", "rho", "nu"}


def beam_from_dict(d: Any, *, check_caps: bool = False) -> Beam:
    """Build a :class:`Beam` from the beam-JSON mapping (SI units), validating every field
    (keys and defaults as in :func:`load_beam`: no ``tip_force`` means no load).

    ``check_caps`` (the readers of beam, fit.json and model files set it) also refuses more
    than ``limits().max_vertices`` vertices; a mapping built in code is not capped.
    """
    if not isinstance(d, dict):
        raise BeamInputError(f"beam = {type(d).__name__}: must be a JSON object")
    unknown = set(d) - _KEYS_REQUIRED - _KEYS_OPTIONAL
    if unknown:
        raise BeamInputError(f"unknown key(s) {sorted(unknown)}: allowed are "
                             f"{sorted(_KEYS_REQUIRED | _KEYS_OPTIONAL)}")
    missing = _KEYS_REQUIRED - set(d)
    if missing:
        raise BeamInputError(f"missing key(s) {sorted(missing)}")
    # before any array is built: a 200k-vertex planform exhausts the solvers, not the parser
    for key in ("x", "half_width") if check_caps else ():
        if isinstance(d[key], list):
            check_cap(f"{key} (vertices)", len(d[key]), "max_vertices")
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
        length = _finite_positive("length", d["length"])
        if not math.isclose(length, beam.length_m, rel_tol=1e-12, abs_tol=0.0):
            raise BeamInputError(
                f"length = {length} m: must equal the last x vertex ({beam.length_m} m)"
            )
    return beam


def beam_to_dict(beam: Beam) -> dict[str, Any]:
    """The beam-JSON mapping of ``beam`` (SI units)."""
    m = beam.material
    return {
        "name": beam.name,
        "description": beam.description,
        "length": beam.length_m,
        "x": [float(v) for v in beam.x_m],
        "half_width": [float(v) for v in beam.half_width_m],
        "thickness": beam.thickness_m,
        "material": {"name": m.name, "E": m.E_Pa, "rho": m.rho_kg_m3, "nu": m.nu},
        "tip_force": [float(v) for v in beam.tip_force_N],
    }


def load_beam(path: str | os.PathLike) -> Beam:
    """Read a beam JSON file; any defect raises :class:`BeamInputError` naming the field.

    Required keys: ``x``, ``half_width`` (m), ``thickness`` (m). Optional: ``length`` (m, checked
    against the last x), ``material`` (default steel AISI 4340), ``name``, ``description`` and
    ``tip_force`` ([Fx, Fy, Fz] in N): without it the beam has no load, [0, 0, 0] N, which is
    enough for eigen (frequency) fits; deflection, combined and Pareto fits refuse a zero load.
    The file is read by :func:`prbdm_pin.jsonfile.read_json` (size, UTF-8, depth, integer
    length, finiteness); at most ``limits().max_vertices`` vertices (``PRBDM_MAX_VERTICES``);
    names hold no control characters.
    """
    return beam_from_dict(read_json(path, "beam file"), check_caps=True)


def atomic_write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (temporary file in the same folder, then rename)."""
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    from .atomic import mkstemp

    fd, tmp = mkstemp(p.parent, prefix=f".{p.name}.", suffix=".tmp")  # 0666 & ~umask
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, p)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return p


def save_beam(beam: Beam, path: str | os.PathLike) -> Path:
    """Write ``beam`` as beam JSON (atomically)."""
    return atomic_write_text(path, json.dumps(beam_to_dict(beam), indent=2) + "\n")


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
    """A random planform as in the paper's Sec. 2.1.

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
    """
    if isinstance(p, bool) or not isinstance(p, (int, np.integer)) or p < 0:
        raise BeamInputError(f"p = {p!r}: must be an integer >= 0")
    _finite_positive("length", length_m)
    _finite_positive("width_scale", width_scale)
    _finite_positive("min_half_width", min_half_width_m)
    if not isinstance(rng, np.random.Generator):
        raise BeamInputError(f"rng = {rng!r}: must be a numpy.random.Generator")
    # strictly inside (0, 1) and distinct: Generator.random is in [0, 1), redraw the rare ties
    while True:
        xi = np.sort(rng.random(p))
        if p == 0 or (xi[0] > 0.0 and np.all(np.diff(xi) > 0.0)):
            break
    x = np.concatenate([[0.0], xi, [1.0]]) * length_m
    w = np.maximum(width_scale * rng.random(p + 2), min_half_width_m)
    if isinstance(thickness_m, tuple):
        lo, hi = (_finite_positive("thickness", v) for v in thickness_m)
        if hi < lo:
            raise BeamInputError(f"thickness = {thickness_m}: needs low <= high")
        t = float(rng.uniform(lo, hi))
    else:
        t = _finite_positive("thickness", thickness_m)
    return Beam(
        x_m=x, half_width_m=w, thickness_m=t, material=material,
        tip_force_N=np.asarray(tip_force_N, dtype=float),
        name=name or "random",
        description=f"Random planform (paper Sec. 2.1), p = {p}, half-width scale {width_scale}, "
        f"floor {min_half_width_m} m",
    )
