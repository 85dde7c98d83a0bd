"""The finite-element truth a PRBDM is fitted against (scikit-fem).

``compute_truth`` runs a modal analysis (Kirchhoff plate by default; 3D solid or 1D beam on
request), labels and selects the bending modes, solves the tip-load case and refuses results it
cannot trust (negative or complex eigenvalues, a failed convergence check).
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError, TruthError
from ..geometry import Beam
from .estimate import ERROR_TOL_PCT, CoarseTruthError
from .request import TruthRequest
from .result import ModalSolution, StaticSolution, Timings, TruthResult

__all__ = [
    "MODELS",
    "LARGE_DEFLECTION",
    "DEFAULT_PLATE_LEVEL",
    "DEFAULT_LARGE_DEFLECTION",
    "TruthRequest",
    "TruthResult",
    "ModalSolution",
    "StaticSolution",
    "Timings",
    "compute_truth",
    "compute_modal",
    "CoarseTruthError",
    "ERROR_TOL_PCT",
]

MODELS = ("plate", "plate-morley", "solid", "beam")
# "calibrated-elastica" (default): the elastica with EI(x) scaled so that its small-load tip is the
# truth model's own linear tip (the frequencies' model); "elastica": the plain 1D elastica;
# "solid": the nonlinear 3D solid (reference, about a minute on a wide panel)
LARGE_DEFLECTION = ("calibrated-elastica", "elastica", "solid", "none")
DEFAULT_LARGE_DEFLECTION = "calibrated-elastica"
# Cheapest level meeting 0.1 % on the five bending modes of the shipped beams
# (scripts/bench_truth.py): the level-0 mesh is graded towards re-entrant corners, which is where
# the error of a uniform mesh concentrates.
DEFAULT_PLATE_LEVEL = 0
# Enough modes that the z mass participation of the unseen modes cannot reorder a 5-mode selection.
DEFAULT_COMPUTED_MODES = 25
CONVERGENCE_TOL = 1e-3


def _check_level(level: object) -> int:
    if isinstance(level, bool) or not isinstance(level, (int, np.integer)) or not 0 <= level <= 6:
        raise BeamInputError(f"mesh_level = {level!r}: must be an integer in [0, 6]")
    return int(level)


def compute_modal(beam: Beam, model: str = "plate", mesh_level: int | None = None,
                  n_modes: int = DEFAULT_COMPUTED_MODES) -> ModalSolution:
    """All computed modes of one model, classified (MPF_z, symmetry, beam MAC).

    Parameters
    ----------
    beam : Beam
    model : {"plate", "plate-morley", "solid", "beam"}
    mesh_level : int, optional
        Refinement level; default the cheapest level meeting 0.1 % for the model.
    n_modes : int
        Number of lowest modes computed.

    Raises
    ------
    TruthError
        A negative, zero or non-finite eigenvalue.
    """
    if model not in MODELS:
        raise BeamInputError(f"model = {model!r}: must be one of {MODELS}")
    if model in ("plate", "plate-morley"):
        from .plate import plate_modal

        level = DEFAULT_PLATE_LEVEL if mesh_level is None else _check_level(mesh_level)
        element = "argyris" if model == "plate" else "morley"
        modal = plate_modal(beam, level, n_modes, element)
    elif model == "solid":
        from .solid import solid_modal

        level = None if mesh_level is None else _check_level(mesh_level)
        modal = solid_modal(beam, level=level, n_modes=n_modes)
    else:
        from .beam import beam_modal

        modal = beam_modal(beam, n_modes=n_modes)
    w = np.asarray(modal.omega_rad_s)
    if not np.all(np.isfinite(w)) or np.any(w <= 0.0):
        bad = np.flatnonzero(~np.isfinite(w) | (w <= 0.0))
        raise TruthError(
            f"{modal.model} model of {beam.name!r} (level {modal.mesh_level}) has "
            f"{bad.size} non-positive or non-finite eigenvalue(s), first at mode {bad[0] + 1} "
            f"({w[bad[0]]:.6g} rad/s): the mesh or the solve cannot be trusted"
        )
    return modal


def _static(beam: Beam, model: str, level: int | None, large: str):
    """Linear solve of the truth model, the large-deflection solve, and the small-load gap
    100 (u_1D / u_model - 1) in % between the 1D beam and the truth model's linear tips."""
    from .beam import beam_static

    linear = nonlinear = None
    beam_lin = beam_static(beam)
    if model == "beam":
        from .beam import beam_static

        linear = beam_lin
    elif model == "solid":
        from .solid import solid_static

        linear = solid_static(beam, level=level)
    else:
        from .static import plate_static

        linear = plate_static(beam, level=level)
    u_model = float(linear.tip_displacement_m[2])
    u_1d = float(beam_lin.tip_displacement_m[2])
    # the ratio is load-independent (both linear); undefined without a vertical load
    gap = 100.0 * (u_1d / u_model - 1.0) if u_model != 0.0 and u_1d != 0.0 else None
    if large == "calibrated-elastica":
        import dataclasses

        from .elastica import elastica_static

        scale = 1.0 if gap is None else 1.0 + gap / 100.0
        nonlinear = dataclasses.replace(elastica_static(beam, ei_scale=scale),
                                        model="calibrated-elastica")
    elif large == "elastica":
        from .elastica import elastica_static

        nonlinear = elastica_static(beam)
    elif large == "solid":
        from .solid import solid_static

        nonlinear = solid_static(beam, nonlinear=True)
    return linear, nonlinear, gap


ELASTICA_PLATE_TOL = 0.01


def _elastica_warning(beam: Beam, model: str, linear, large: str) -> list[str]:
    """Warn when the 1D elastica misses plate action that the linear 2D/3D solve shows.

    The elastica is a 1D model: on wide panels the plate is stiffer (anticlastic curvature is
    restrained), which the linear plate or solid tip deflection reveals against the linear 1D beam
    at no extra cost.
    """
    if large != "elastica" or model == "beam" or linear is None:
        return []
    from .beam import beam_static

    u_2d = float(linear.tip_displacement_m[2])
    u_1d = float(beam_static(beam).tip_displacement_m[2])
    if u_1d == 0.0:
        return []
    gap = abs(u_2d / u_1d - 1.0)
    if gap <= ELASTICA_PLATE_TOL:
        return []
    return [
        f"the large-deflection truth is the 1D elastica, but the linear {model} tip deflection "
        f"differs from the 1D beam's by {100 * gap:.1f} %: plate action matters here; use "
        f"large_deflection='solid' (--large-deflection solid) for a 3D nonlinear reference"
    ]


def compute_truth(
    beam: Beam,
    model: str = "plate",
    modes: int = 5,
    mesh_level: int | None = None,
    selection: str = "paper",
    static: bool = True,
    cache_dir=None,
    *,
    n_computed: int = DEFAULT_COMPUTED_MODES,
    large_deflection: str = DEFAULT_LARGE_DEFLECTION,
    check_convergence: bool = False,
    error_tol_pct: float | None = ERROR_TOL_PCT,
) -> TruthResult:
    """The finite-element truth of a beam: selected bending frequencies and tip-load response.

    Parameters
    ----------
    beam : Beam
    model : {"plate", "plate-morley", "solid", "beam"}
        ``plate`` (default): Kirchhoff plate, Argyris elements in element-local coordinates.
        ``plate-morley``: cheap cross-check from below. ``solid``: 3D elasticity. ``beam``: 1D
        Euler-Bernoulli (exact for slender strips only, 2-15 % off for wide panels).
    modes : int
        Number N of bending modes to select.
    mesh_level : int, optional
        Mesh refinement; default the cheapest level meeting 0.1 %.
    selection : {"paper", "shape"}
        ``paper``: the N modes of largest z mass participation, ascending; ``shape``: the lowest
        N symmetric modes with MAC >= 0.8 against a 1D beam mode.
    static : bool
        Also solve the tip-load case under ``beam.tip_force_N``.
    cache_dir : path, optional
        Reuse a result computed with the same inputs and package version (see ``truth.cache``).
    n_computed : int
        Modes computed before selection (20-40 so that the selection is complete).
    large_deflection : {"calibrated-elastica", "elastica", "solid", "none"}
        Geometrically nonlinear tip solve. ``calibrated-elastica`` (default): the 1D elastica
        with EI(x) scaled by u_1D / u_model, the ratio of the 1D beam's and the truth model's
        linear tip deflections, so that at small load it is the model the frequencies come from
        (0.44 % and 0.57 % from the nonlinear 3D solid's tip displacement on the tapered and the
        reference panel, 0.16 % and 0.08 % of the tip position; scripts/target_consistency.py).
        ``elastica``: the plain 1D elastica (exact for slender strips; 1.30 % and 0.23 % off).
        ``solid``: the nonlinear 3D solid (the reference; 14 s and 90 s of CPU time).
    check_convergence : bool
        Also solve one mesh level finer and raise TruthError if a selected frequency moves by
        more than 0.1 % or increases (Argyris converges from above).
    error_tol_pct : float or None
        Refuse (TruthError) a truth whose error estimate for a selected mode exceeds this, in %
        (default 0.5); None accepts any. The estimate (``error_estimate_pct``: twice the change to
        the next mesh level, see ``truth.estimate``) is computed and cached either way.

    Returns
    -------
    TruthResult

    Raises
    ------
    BeamInputError
        Bad arguments.
    TruthError
        Negative/complex eigenvalues, too few bending modes or a failed convergence check;
        ``CoarseTruthError`` (a TruthError) for an error estimate above ``error_tol_pct``.
    """
    from .. import __version__
    from .modes import SELECTIONS, label_modes, select_modes, selection_warnings

    if not isinstance(beam, Beam):
        raise BeamInputError(f"beam = {beam!r}: must be a prbdm_pin.Beam")
    if model not in MODELS:
        raise BeamInputError(f"model = {model!r}: must be one of {MODELS}")
    if selection not in SELECTIONS:
        raise BeamInputError(f"selection = {selection!r}: must be one of {SELECTIONS}")
    if large_deflection not in LARGE_DEFLECTION:
        raise BeamInputError(
            f"large_deflection = {large_deflection!r}: must be one of {LARGE_DEFLECTION}"
        )
    if isinstance(modes, bool) or not isinstance(modes, (int, np.integer)) or modes < 1:
        raise BeamInputError(f"modes = {modes!r}: must be an integer >= 1")
    if isinstance(n_computed, bool) or not isinstance(n_computed, (int, np.integer)):
        raise BeamInputError(f"n_computed = {n_computed!r}: must be an integer")
    n_computed = max(int(n_computed), 2 * int(modes))
    if mesh_level is not None:
        _check_level(mesh_level)
    if error_tol_pct is not None and not (
            isinstance(error_tol_pct, (int, float, np.floating))
            and not isinstance(error_tol_pct, bool) and error_tol_pct > 0.0):
        raise BeamInputError(f"error_tol_pct = {error_tol_pct!r}: must be a number > 0 (%) "
                             "or None")

    key = None
    if cache_dir is not None:
        from .cache import cache_key, load_cached

        key = cache_key(beam, model=model, mesh_level=mesh_level, modes=modes,
                        selection=selection, static=static, n_computed=n_computed,
                        large_deflection=large_deflection, version=__version__)
        hit = load_cached(cache_dir, key, beam.fingerprint())
        if hit is not None:
            return _judged(hit, beam, error_tol_pct)

    modal = compute_modal(beam, model, mesh_level, n_computed)
    labels = label_modes(modal)
    try:
        index = select_modes(modal, modes, selection)
    except ValueError as exc:
        raise TruthError(f"{beam.name!r}: {exc}") from exc
    from .estimate import (
        ESTIMATE_MAX_DOFS,
        beam_theory_gap,
        error_estimate_pct,
        estimate_skipped,
        next_level_modal,
    )

    if check_convergence:
        finer = compute_modal(beam, model, modal.mesh_level + 1, n_computed)
    else:
        finer = next_level_modal(beam, model, modal, index)
    estimate = error_estimate_pct(modal, finer, index)
    gap_1d, gap_cause = beam_theory_gap(beam, modal, index, labels)
    if check_convergence:
        try:
            index_f = select_modes(finer, modes, selection)
        except ValueError as exc:
            raise TruthError(f"{beam.name!r}, finer mesh: {exc}") from exc
        w0, w1 = modal.omega_rad_s[index], finer.omega_rad_s[index_f]
        rel = w0 / w1 - 1.0
        if not np.array_equal(index, index_f) or np.any(np.abs(rel) > CONVERGENCE_TOL) or (
            model == "plate" and np.any(rel < -1e-5)
        ):
            raise TruthError(
                f"{beam.name!r}: {model} model not converged between mesh levels "
                f"{modal.mesh_level} and {finer.mesh_level}: selected modes {index + 1} vs "
                f"{index_f + 1}, relative change {np.array2string(rel, precision=5)}"
            )
    linear = nonlinear = gap = None
    notes = list(selection_warnings(modal, index, labels))
    if model in ("plate", "plate-morley"):
        notes += beam.kirchhoff_warnings(modes)
    if estimate is None and estimate_skipped(model, modal):
        notes.append(f"no discretisation error estimate: the next mesh level of this {model} "
                     f"truth would have about {4 * int(modal.dofs):,} DOFs (above "
                     f"{ESTIMATE_MAX_DOFS:,}, many GB); check_convergence=True compares with it")
    elif estimate is None:
        notes.append(f"no discretisation error estimate for the {model} model (its next mesh "
                     "level costs minutes): check_convergence=True compares with it")
    if static:
        lvl = None if model in ("beam",) else mesh_level
        linear, nonlinear, gap = _static(beam, model, lvl, large_deflection)
        notes += _elastica_warning(beam, model, linear, large_deflection)
    result = TruthResult(
        beam_fingerprint=beam.fingerprint(),
        model=model,
        mesh_level=int(modal.mesh_level),
        selection=selection,
        omega_rad_s=_ro(modal.omega_rad_s[index]),
        mode_index=_ro(index),
        mpf_z_fraction=_ro(modal.mpf_z_fraction[index]),
        mac_beam=_ro(modal.mac_beam[index]),
        labels=labels,
        modal=modal,
        static_linear=linear,
        static_nonlinear=nonlinear,
        version=__version__,
        warnings=tuple(notes),
        static_theory_gap_pct=gap,
        error_estimate_pct=None if estimate is None else _ro(estimate),
        error_estimate_level=None if finer is None else int(finer.mesh_level),
        beam_gap_pct=_ro(gap_1d),
        beam_gap_cause=gap_cause,
    )
    if key is not None:
        from .cache import store_cached

        store_cached(cache_dir, key, result)
    return _judged(result, beam, error_tol_pct)


def _judged(result: TruthResult, beam: Beam, error_tol_pct: float | None) -> TruthResult:
    """``result``, or TruthError when a selected mode's error estimate exceeds the tolerance."""
    est = result.error_estimate_pct
    if error_tol_pct is None or est is None or np.all(est <= error_tol_pct):
        return result
    k = int(np.argmax(est))
    raise CoarseTruthError(
        f"{beam.name!r}: selected mode {k + 1} ({result.omega_rad_s[k]:.6g} rad/s) of the "
        f"{result.model} truth at mesh level {result.mesh_level} has an estimated error of "
        f"{est[k]:.3g} % (from its change to level {result.error_estimate_level}), above "
        f"{error_tol_pct:g} %: raise the mesh level (mesh_level={result.mesh_level + 1}, "
        f"--mesh {result.mesh_level + 1}) or accept it (error_tol_pct=None, --accept-coarse)")


def _ro(a: np.ndarray) -> np.ndarray:
    a = np.array(a)
    a.setflags(write=False)
    return a
