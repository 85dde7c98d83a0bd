"""The report of a batch study and its Markdown.

Distributions and correlations over the latest record of every beam.

Losses, link-length fractions (gamma_1 is the paper's "characteristic pivot"), and SCF_mean
against simple geometry features (taper ratio, mean width). Several output folders (the shards
of one study) are merged; their manifests must agree except for the shard. numpy and scipy load
when a report is computed, not when the batch package is imported (its workers pin BLAS first).
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import BeamInputError
from .files import missing_shards, read_manifest
from .manifest import MANIFEST
from .records import RESULTS_JSONL, latest_records, read_records

if TYPE_CHECKING:
    import numpy as np

__all__ = ["Distribution", "Correlation", "BatchReport", "load_study", "missing_warning",
           "summarise", "to_markdown", "loss_lines", "column_values", "LOSS_KEYS", "FEATURES",
           "QUANTILES"]

# the worst per-mode errors (over the fitted poses; of the exported model at q = 0) sit beside
# the eigen loss: a small loss can hide a large error of one mode
LOSS_KEYS = ("eigen_loss_pct", "worst_mode_error_pct", "worst_export_error_pct",
             "deflection_loss_pct", "displacement_loss_pct", "combined_loss_pct")
FEATURES = ("taper_ratio", "mean_width_m")
QUANTILES = (0.0, 0.05, 0.25, 0.5, 0.75, 0.95, 1.0)


@dataclass(frozen=True)
class Distribution:
    """Quantiles (``QUANTILES``) and mean of one quantity over the fitted beams."""

    name: str
    count: int
    mean: float
    quantiles: tuple[float, ...]


@dataclass(frozen=True)
class Correlation:
    """Spearman rank correlation of ``y`` with ``x`` over the fitted beams."""

    x: str
    y: str
    count: int
    rho: float
    p_value: float


@dataclass(frozen=True)
class BatchReport:
    """What ``batch-report`` found.

    Attributes
    ----------
    n_beams, n_ok, n_failed : int
    failures : tuple of (reason, count)
        Most frequent first (reasons cut at the first line).
    losses : tuple of Distribution
    gammas : tuple of Distribution
        Link-length fractions gamma_1 .. gamma_{n+1} (gamma_1: root link, first joint position).
    scf_mean : Distribution or None
    correlations : tuple of Correlation
        SCF_mean, gamma_1 and the fitted loss against taper ratio and mean width.
    settings : dict
        The batch manifest's fit settings (for the header).
    """

    n_beams: int
    n_ok: int
    n_failed: int
    failures: tuple[tuple[str, int], ...]
    losses: tuple[Distribution, ...]
    gammas: tuple[Distribution, ...]
    scf_mean: Distribution | None
    correlations: tuple[Correlation, ...]
    settings: dict


def load_study(dirs: list[str]) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """Latest record of every beam over the given batch folders, and their common manifest.

    The manifest gains ``missing_shards`` (indices of the shards of the study not given; empty
    when complete) and ``n_shards``.
    """
    records: list[dict[str, Any]] = []
    common: dict[str, Any] | None = None
    shards: list[tuple[int, int]] = []
    for d in dirs:
        folder = Path(d)
        mpath = folder / MANIFEST
        if not mpath.exists():
            raise BeamInputError(f"dir = {d!r}: no {MANIFEST} (not a batch output folder)")
        manifest = read_manifest(mpath)
        key = {k: v for k, v in manifest.items() if k not in ("shard", "version", "beams")}
        if common is None:
            common = key
        elif key != common:
            raise BeamInputError(f"dir = {d!r}: its batch.json differs from {dirs[0]!r} "
                                 f"(other seed or settings): not shards of one study")
        shards.append(tuple(manifest.get("shard", (0, 1))))
        records.extend(read_records(folder / RESULTS_JSONL))
    n_shards, missing = missing_shards(shards)
    return latest_records(records), {**(common or {}), "n_shards": n_shards,
                                     "missing_shards": missing}


def missing_warning(rep: BatchReport) -> str | None:
    """One line on the shards of the study that the report does not cover, or None."""
    missing = rep.settings.get("missing_shards") or []
    if not missing:
        return None
    n = rep.settings.get("n_shards")
    listed = ", ".join(f"{i}/{n}" for i in missing)
    total = rep.settings.get("n_beams")
    of = f" of the study's {total}" if isinstance(total, int) else ""
    return (f"warning: shard{'s' if len(missing) > 1 else ''} {listed} of {n} not given: this "
            f"report covers {rep.n_beams}{of} beams")


def _num(x: Any) -> float:
    return math.nan if x is None else float(x)


def column_values(records: list[dict[str, Any]], key: str) -> np.ndarray:
    """Field ``key`` of every record as floats (NaN where missing or null)."""
    import numpy as np

    return np.array([_num(r.get(key)) for r in records], dtype=float)


def _distribution(name: str, values: np.ndarray) -> Distribution:
    import numpy as np

    v = values[np.isfinite(values)]
    if v.size == 0:
        return Distribution(name, 0, math.nan, tuple(math.nan for _ in QUANTILES))
    return Distribution(name, int(v.size), float(v.mean()),
                        tuple(float(q) for q in np.quantile(v, QUANTILES)))


def _correlation(x_name: str, x: np.ndarray, y_name: str, y: np.ndarray) -> Correlation:
    import numpy as np
    from scipy.stats import spearmanr

    ok = np.isfinite(x) & np.isfinite(y)
    if ok.sum() < 3 or np.ptp(x[ok]) == 0 or np.ptp(y[ok]) == 0:  # undefined: no ranks
        return Correlation(x_name, y_name, int(ok.sum()), math.nan, math.nan)
    res = spearmanr(x[ok], y[ok])
    return Correlation(x_name, y_name, int(ok.sum()), float(res.statistic), float(res.pvalue))


def summarise(records: list[dict[str, Any]], settings: dict | None = None) -> BatchReport:
    """Distributions and correlations over the latest record of every beam."""
    import numpy as np

    ok = [r for r in records if r.get("status") == "ok"]
    failed = [r for r in records if r.get("status") != "ok"]
    reasons = Counter(str(r.get("error", "unknown")).splitlines()[0][:120] for r in failed)
    losses = tuple(_distribution(k, column_values(ok, k)) for k in LOSS_KEYS
                   if np.isfinite(column_values(ok, k)).any())
    n_links = max((len(r.get("gamma") or []) for r in ok), default=0)
    gammas = tuple(
        _distribution(f"gamma_{j + 1}", np.array(
            [_num(r["gamma"][j]) if len(r.get("gamma") or []) > j else math.nan for r in ok]))
        for j in range(n_links))
    scf = column_values(ok, "scf_mean")
    fitted = _fitted_loss_key(settings)
    corr = tuple(
        _correlation(f, column_values(ok, f), y, column_values(ok, y))
        for y in ("scf_mean", "gamma_1", fitted) for f in FEATURES
    )
    return BatchReport(
        n_beams=len(records), n_ok=len(ok), n_failed=len(failed),
        failures=tuple(reasons.most_common()),
        losses=losses, gammas=gammas,
        scf_mean=_distribution("scf_mean", scf) if np.isfinite(scf).any() else None,
        correlations=corr, settings=dict(settings or {}),
    )


def _fitted_loss_key(settings: dict | None) -> str:
    objective = ((settings or {}).get("settings") or {}).get("objective", "eigen")
    return f"{objective}_loss_pct"


def _fmt(v: float) -> str:
    if not math.isfinite(v):
        return "-"
    return f"{v:.4g}"


def to_markdown(rep: BatchReport, plots: list[str]) -> str:
    """Return the report as Markdown."""
    s = rep.settings.get("settings", {})
    lines = ["# Batch study report", ""]
    src = (f"{rep.settings.get('n_beams')} random beams, seed {rep.settings.get('seed')}"
           if rep.settings.get("source") == "random" else "beam files")
    lines += [
        f"{src}; {s.get('joints')} joints, {s.get('frequencies') or s.get('joints')} "
        f"frequencies, objective {s.get('objective')} ({s.get('eigen_norm', 'paper')} eigen "
        f"norm), stiffness {s.get('stiffness')}, "
        f"{s.get('starts')} starts, truth model {s.get('truth_model')}.",
        "",
        f"Beams with a record: {rep.n_beams}; fitted: {rep.n_ok}; failed: {rep.n_failed}.",
        "",
    ]
    warning = missing_warning(rep)
    if warning is not None:
        lines += [f"**{warning[0].upper()}{warning[1:]}.**", ""]
    head = "| quantity | n | mean | " + " | ".join(
        "min" if q == 0 else "max" if q == 1 else f"{q:.0%}" for q in QUANTILES) + " |"
    sep = "|" + "---|" * (3 + len(QUANTILES))

    def table(title: str, dists) -> None:
        lines.extend([f"## {title}", "", head, sep])
        for d in dists:
            lines.append(f"| {d.name} | {d.count} | {_fmt(d.mean)} | "
                         + " | ".join(_fmt(q) for q in d.quantiles) + " |")
        lines.append("")

    if rep.losses:
        table("Losses and worst per-mode errors (%; worst_mode_error_pct: max |omega_model / "
              "omega_truth - 1| over the fitted poses and modes, worst_export_error_pct: of the "
              "exported model at the straight pose)", rep.losses)
    if rep.gammas:
        table("Link-length fractions (gamma_1: root link, the paper's characteristic pivot)",
              rep.gammas)
    if rep.scf_mean is not None:
        table("SCF_mean (Eq. 25; joint stiffness: mean joint factor)", [rep.scf_mean])
    if rep.correlations:
        lines += ["## Against geometry (Spearman rank correlation)", "",
                  "| y | x | n | rho | p |", "|---|---|---|---|---|"]
        for c in rep.correlations:
            lines.append(f"| {c.y} | {c.x} | {c.count} | {_fmt(c.rho)} | {_fmt(c.p_value)} |")
        lines += ["", "taper_ratio = tip width / root width; mean_width_m = planform area / "
                      "length.", ""]
    if rep.failures:
        lines += ["## Failures", "", "| reason | beams |", "|---|---|"]
        lines += [f"| {reason.replace('|', '/')} | {n} |" for reason, n in rep.failures]
        lines.append("")
    if plots:
        lines += ["## Plots", ""] + [f"![{Path(p).stem}]({Path(p).name})" for p in plots] + [""]
    return "\n".join(lines)


def loss_lines(rep: BatchReport) -> list[str]:
    """Median and maximum of the eigen loss and the worst per-mode errors, one line each."""
    return [f"{d.name}: median {_fmt(d.quantiles[QUANTILES.index(0.5)])}, "
            f"max {_fmt(d.quantiles[-1])}"
            for d in rep.losses
            if d.name in ("eigen_loss_pct", "worst_mode_error_pct", "worst_export_error_pct")]
