"""``compute_truth``: the finite-element truth of a beam, from the cache or solved and judged.

A modal analysis (Kirchhoff plate by default; 3D solid or 1D beam on request), the bending
modes labelled and selected, the tip-load case solved, and results it cannot trust refused
(negative or complex eigenvalues, a failed convergence check, a coarse error estimate).
"""

from __future__ import annotations

import numpy as np

from .. import __version__
from ..errors import BeamInputError, InputTypeError, TruthError
from ..geometry import Beam
from .cache import cache_key, load_cached, store_cached
from .estimate import (
    ERROR_TOL_PCT,
    ESTIMATE_MAX_DOFS,
    CoarseTruthError,
    beam_theory_gap,
    error_estimate_pct,
    estimate_skipped,
    next_level_modal,
)
from .modal import compute_modal
from .modes import SELECTIONS, label_modes, select_modes, selection_warnings
from .result import TruthResult
from .settings import (
    DEFAULT_COMPUTED_MODES,
    DEFAULT_LARGE_DEFLECTION,
    LARGE_DEFLECTION,
    MODELS,
    check_mesh_level,
)
from .tip_response import elastica_warnings, tip_response

__all__ = ["CONVERGENCE_TOL", "compute_truth"]

# largest relative change of a selected frequency to the next mesh level (check_convergence)
CONVERGENCE_TOL = 1e-3


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
    """Compute the finite-element truth of a beam: bending frequencies and tip-load response.

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
        (its distance to the nonlinear solid is measured by scripts/target_consistency.py).
        ``elastica``: the plain 1D elastica (exact for slender strips).
        ``solid``: the nonlinear 3D solid (the reference, and by far the costliest).
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
    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r}: must be a prbdm_pin.Beam")
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
        check_mesh_level(mesh_level)
    if error_tol_pct is not None and not (
            isinstance(error_tol_pct, (int, float, np.floating))
            and not isinstance(error_tol_pct, bool) and error_tol_pct > 0.0):
        raise BeamInputError(f"error_tol_pct = {error_tol_pct!r}: must be a number > 0 (%) "
                             "or None")

    request = None
    if n_computed == max(DEFAULT_COMPUTED_MODES, 2 * int(modes)):
        from .request import TruthRequest

        request = TruthRequest(model=model, modes=int(modes), mesh_level=mesh_level,
                               selection=selection, large_deflection=large_deflection,
                               error_tol_pct=error_tol_pct)
    key = None
    if cache_dir is not None:
        key = cache_key(beam, model=model, mesh_level=mesh_level, modes=modes,
                        selection=selection, static=static, n_computed=n_computed,
                        large_deflection=large_deflection, version=__version__)
        hit = load_cached(cache_dir, key, beam.fingerprint())
        if hit is not None:
            return _judged(_recorded(hit, request), beam, error_tol_pct)

    modal = compute_modal(beam, model, mesh_level, n_computed)
    labels = label_modes(modal)
    try:
        index = select_modes(modal, modes, selection)
    except ValueError as exc:
        raise TruthError(f"{beam.name!r}: {exc}") from exc
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
        linear, nonlinear, gap = tip_response(beam, model, lvl, large_deflection)
        notes += elastica_warnings(beam, model, linear, large_deflection)
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
        store_cached(cache_dir, key, result)
    return _judged(_recorded(result, request), beam, error_tol_pct)


def _recorded(result: TruthResult, request) -> TruthResult:
    """Record the call that made ``result`` on it (``TruthResult.request``; not cached)."""
    object.__setattr__(result, "_request", request)
    return result


def _judged(result: TruthResult, beam: Beam, error_tol_pct: float | None) -> TruthResult:
    """Return ``result``; TruthError when a selected mode's error estimate exceeds the tolerance."""
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
