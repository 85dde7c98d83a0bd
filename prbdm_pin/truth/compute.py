"""``compute_truth``: the finite-element truth of a beam, from the cache or solved and judged.

A modal analysis (Kirchhoff plate by default; 3D solid or 1D beam on request), the bending
modes labelled and selected, the tip-load case solved, and results it cannot trust refused
(negative or complex eigenvalues, a failed convergence check, a coarse error estimate). What is
asked comes as one :class:`~prbdm_pin.truth.request.TruthRequest`, which holds the defaults.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputTypeError, TruthError
from ..member.geometry import Beam
from ..options.limits import limits
from ..version import __version__
from .cache import cache_key, load_cached, store_cached
from .estimate import (
    CoarseTruthError,
    beam_theory_gap,
    error_estimate_pct,
    estimate_skipped,
    next_level_modal,
)
from .modal import compute_modal
from .modes import label_modes, select_modes, selection_warnings
from .request import TruthRequest, request_of
from .result import TruthResult
from .timoshenko_criterion import timoshenko_warnings
from .tip_response import elastica_warnings, tip_response

__all__ = ["compute_truth"]


def compute_truth(beam: Beam, request: TruthRequest | None = None, *, cache_dir=None,
                  **fields) -> TruthResult:
    """Compute the finite-element truth of a beam: bending frequencies and tip-load response.

    Parameters
    ----------
    beam : Beam
    request : TruthRequest, optional
        What truth: the model, the number of modes and their selection, the mesh level, the
        tip-load solve, the accepted error estimate (see :class:`TruthRequest` for each field
        and its default).
    cache_dir : path, optional
        Reuse a result computed with the same inputs and package version (see ``truth.cache``).
    **fields
        Without ``request``, the fields of :class:`TruthRequest` as keywords
        (``compute_truth(beam, model="beam", modes=3)``): the request they build, the others at
        their defaults.

    Returns
    -------
    TruthResult
        Frequencies in rad/s, tip position and displacement in m.

    Raises
    ------
    BeamInputError
        Bad arguments (naming the field).
    TruthError
        Negative/complex eigenvalues, too few bending modes or a failed convergence check;
        ``CoarseTruthError`` (a TruthError) for an error estimate above
        ``request.error_tol_pct``.
    TypeError
        A keyword that is no field of TruthRequest, or a request given with fields.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> truth = pp.compute_truth(beam, model="beam", modes=3)
    >>> truth.omega_rad_s.round(1)  # rad/s
    array([ 51.9, 325.1, 910.2])
    >>> EI, rho_A = 205e9 * 0.05 * 0.01**3 / 12, 7850.0 * 0.05 * 0.01  # N m^2, kg/m
    >>> beta_L = np.array([1.8751041, 4.6940911, 7.8547574])  # Euler-Bernoulli cantilever, L = 1 m
    >>> (beta_L**2 * np.sqrt(EI / rho_A)).round(1)
    array([ 51.9, 325.1, 910.2])
    """
    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r}: must be a prbdm_pin.Beam")
    req = request_of(request, fields, "compute_truth")
    model, modes, mesh_level, selection = req.model, req.modes, req.mesh_level, req.selection
    n_computed = req.computed_modes
    # only the 1D beam adds modes with it: the other models' results and keys are the same
    spatial = req.spatial and model == "beam"

    key = None
    if cache_dir is not None:
        # the estimate's DOF cap decides whether a plate truth carries an estimate: part of the key
        key = cache_key(beam, model=model, mesh_level=mesh_level, modes=modes,
                        selection=selection, static=req.static, n_computed=n_computed,
                        large_deflection=req.large_deflection, version=__version__,
                        estimate_dofs=limits().max_estimate_dofs, spatial=spatial)
        # a convergence check solves the finer level, which no cache entry holds: never skipped
        hit = None if req.check_convergence else load_cached(cache_dir, key, beam.fingerprint())
        if hit is not None:
            return _judged(_recorded(hit, req), beam, req.error_tol_pct)

    modal = compute_modal(beam, model, mesh_level, n_computed, spatial)
    labels = label_modes(modal)
    try:
        index = select_modes(modal, modes, selection)
    except ValueError as exc:
        raise TruthError(f"{beam.name!r}: {exc}") from exc
    if req.check_convergence:
        finer = compute_modal(beam, model, modal.mesh_level + 1, n_computed, spatial)
    else:
        finer = next_level_modal(beam, model, modal, index)
    estimate = error_estimate_pct(modal, finer, index)
    gap_1d, gap_cause = beam_theory_gap(beam, modal, index, labels)
    if req.check_convergence:
        try:
            index_f = select_modes(finer, modes, selection)
        except ValueError as exc:
            raise TruthError(f"{beam.name!r}, finer mesh: {exc}") from exc
        w0, w1 = modal.omega_rad_s[index], finer.omega_rad_s[index_f]
        rel = w0 / w1 - 1.0
        if not np.array_equal(index, index_f) or np.any(np.abs(rel) > req.convergence_rtol) or (
            model == "plate" and np.any(rel < -rise_slack(modal, finer, index, index_f))
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
    elif model == "beam":
        # warned, not switched to Timoshenko: the beam truth's tip, design gradients and the
        # chain's springs are Euler-Bernoulli's, and a switched truth would mix two theories
        notes += timoshenko_warnings(beam, modes)
    if estimate is None and estimate_skipped(model, modal):
        notes.append(f"no discretisation error estimate: the next mesh level of this {model} "
                     f"truth would have about {4 * int(modal.dofs):,} DOFs (above "
                     f"{limits().max_estimate_dofs:,}, many GB; PRBDM_MAX_ESTIMATE_DOFS raises "
                     "it); check_convergence=True compares with it")
    elif estimate is None:
        notes.append(f"no discretisation error estimate for the {model} model (its next mesh "
                     "level costs minutes): check_convergence=True compares with it")
    if req.static:
        lvl = None if model in ("beam",) else mesh_level
        linear, nonlinear, gap = tip_response(beam, model, lvl, req.large_deflection)
        notes += elastica_warnings(beam, model, linear, req.large_deflection)
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
    return _judged(_recorded(result, req), beam, req.error_tol_pct)


def rise_slack(modal, finer, index: np.ndarray, index_f: np.ndarray) -> np.ndarray:
    """How far a selected plate frequency may rise from one mesh level to the next, relative.

    Argyris converges from above, so a frequency that rises with the mesh means a mesh that is
    not converged, beyond what the two eigensolves resolve: at least 1e-5, and 4 times the sum
    of the two eigenpairs' relative residuals (the frequencies of one solve differ by up to 3
    residuals between BLAS kernels, measured on the refined meshes of jagged panels).
    """
    floor = np.full(index.size, 1e-5)
    if modal.eig_residual is None or finer.eig_residual is None:
        return floor
    return np.maximum(floor, 4.0 * (np.asarray(modal.eig_residual)[index]
                                    + np.asarray(finer.eig_residual)[index_f]))


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
