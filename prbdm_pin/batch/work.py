"""The per-beam work of a batch.

The beam and fit seed of a task, its geometry features, and :func:`evaluate_beam` (truth + fit
-> one flat record).

Beam i of a random batch is ``random_beam(default_rng(SeedSequence(seed, spawn_key=(i,))))`` and
its fit seed is the first 32-bit word of that sequence's first child, so no result depends on the
scheduling order, the worker count or the shard.
"""

from __future__ import annotations

import os
import time
from typing import TYPE_CHECKING, Any

from .spec import BeamTask

if TYPE_CHECKING:
    from ..member.geometry import Beam

__all__ = ["beam_of", "fit_seed_of", "beam_features", "record_header", "evaluate_beam"]


def _beam_seed_sequence(seed: int, index: int):
    import numpy as np

    return np.random.SeedSequence(seed, spawn_key=(index,))


def beam_of(task: BeamTask) -> Beam:
    """Return the beam of a task: the file's beam, or random beam ``index`` of seed ``seed``."""
    if task.beam is not None:
        return task.beam
    import numpy as np

    from ..member.random_beams import random_beam

    rng = np.random.default_rng(_beam_seed_sequence(task.seed, task.index))
    return random_beam(rng, name=task.name)


def fit_seed_of(task: BeamTask) -> int:
    """Return the fit seed of a task: first 32-bit word of its beam sequence's first child."""
    import numpy as np

    child = _beam_seed_sequence(task.seed, task.index).spawn(1)[0]
    return int(child.generate_state(1, dtype=np.uint32)[0])


def beam_features(beam: Beam) -> dict[str, float]:
    """Return simple geometry features of a beam (for reports): widths in m, mass in kg.

    ``taper_ratio`` is the tip width over the root width; ``mean_width_m`` the planform area over
    the length.
    """
    L = beam.length_m
    root_w = 2.0 * float(beam.half_width_m[0])
    tip_w = 2.0 * float(beam.half_width_m[-1])
    return {
        "length_m": L,
        "thickness_m": beam.thickness_m,
        "root_width_m": root_w,
        "tip_width_m": tip_w,
        "taper_ratio": tip_w / root_w,
        "mean_width_m": beam.planform_area_m2 / L,
        "min_width_m": 2.0 * float(beam.half_width_m.min()),
        "max_width_m": 2.0 * float(beam.half_width_m.max()),
        "n_vertices": int(beam.x_m.size),
        "mass_kg": beam.mass_kg,
        "load_index": beam.load_index() if float(abs(beam.tip_force_N).max()) > 0 else 0.0,
    }


def record_header(task: BeamTask) -> dict[str, Any]:
    """Return the fields every record of ``task`` starts with: the beam and the arguments."""
    s = task.settings
    o = s.options
    # the arguments travel with the record (a resume that lost batch.json still checks them)
    args = {"joints": s.joints, "frequencies": s.n_frequencies, "objective": o.objective.value,
            "stiffness": o.stiffness.value, "starts": o.starts, "truth_model": s.truth_model,
            "eigen_norm": o.eigen_norm.value, "min_fraction": o.min_fraction}
    return {"beam_index": task.index, "beam_name": task.name, "seed": task.seed, **args}


def evaluate_beam(task: BeamTask) -> dict[str, Any]:
    """Run the default per-beam work: truth (cached) then fit; return a flat JSON-ready record.

    An error inside the truth or the fit is part of the result (``status = "failed"``, with
    ``error`` and ``stage``); only interrupts and process deaths escape.
    """
    from ..fitting import fit
    from ..fitting.target import target_from_truth
    from ..truth import TruthRequest

    t0 = time.perf_counter()
    s = task.settings
    rec = record_header(task)
    rec["worker_pid"] = os.getpid()
    stage = "beam"
    try:
        beam = beam_of(task)
        rec.update(beam_features(beam))
        rec["fit_seed"] = fit_seed_of(task)
        stage = "truth"
        t1 = time.perf_counter()
        # the eigen objective needs no static solve
        request = TruthRequest(model=s.truth_model, modes=s.n_frequencies,
                               static=s.options.objective.has_deflection_term,
                               spatial=s.options.axes.spatial)
        truth = request.compute(beam, cache_dir=s.cache_dir)
        rec["truth_s"] = time.perf_counter() - t1
        stage = "fit"
        t2 = time.perf_counter()
        result = fit(beam, target_from_truth(truth, beam.tip_force_N, request), s.joints,
                     s.options.replace(seed=rec["fit_seed"]), workers=1, progress=False)
        rec["fit_s"] = time.perf_counter() - t2
        rec.update(_fit_fields(result, beam.length_m))
        rec["status"] = "ok"
    except Exception as exc:  # noqa: BLE001 -- a failed beam is a result, not a crash
        rec["status"] = "failed"
        rec["stage"] = stage
        rec["error"] = f"{type(exc).__name__}: {exc}"
    rec["wall_s"] = time.perf_counter() - t0
    rec["worker_peak_rss_mb"] = _peak_rss_mb()
    return rec


def _peak_rss_mb() -> float | None:
    # the worker's peak resident memory so far (Linux reports KiB, macOS bytes)
    try:
        import resource
        import sys
    except ImportError:  # not POSIX
        return None
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / 1024**2 if sys.platform == "darwin" else peak / 1024


# One row per beam: the per-pose arrays (model frequencies, springs, per-mode errors) stay in
# fit.json territory; the per-pose eigen errors and factors are kept (their length is the pose
# count), and so are the worst per-mode error and the exported model's per-mode errors.
_FIT_KEYS = ("frequencies", "eigen_norm", "lengths_m", "stiffness_Nm_per_rad", "factors",
             "scf_mean", "omega_truth_rad_s", "eigen_errors_pct", "eigen_loss_pct",
             "worst_mode_error_pct", "omega_export_errors_pct", "worst_export_error_pct",
             "deflection_loss_pct", "displacement_loss_pct", "combined_loss_pct", "mac",
             "success", "nfev", "starts_run", "axes")


def _fit_fields(result: Any, length_m: float) -> dict[str, Any]:
    import numpy as np

    out: dict[str, Any] = {}
    for key in _FIT_KEYS:
        value = getattr(result, key, None)
        if value is None:
            continue
        arr = np.asarray(value)
        out[key] = arr.tolist() if arr.ndim else arr.item()
    lengths = np.asarray(result.lengths_m, dtype=float)
    out["gamma"] = (lengths / length_m).tolist()
    # The paper's "characteristic pivot": the first link's fraction of the length (Sec. 4.1.1).
    out["gamma_1"] = float(lengths[0] / length_m)
    # the kind of each matched truth mode, beside its error (omega_export_errors_pct's order)
    out["mode_kinds"] = [m["kind"] for m in result.modes if m["error_pct"] is not None]
    return out
