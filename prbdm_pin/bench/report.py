"""A benchmark run as numbers to read.

The non-dominated frontier, the Markdown report and the raw JSON mapping.
"""

from __future__ import annotations

import numpy as np

from .config import BenchResult, ModelRow

__all__ = ["frontier_mask", "markdown_report", "plot_modes", "result_dict", "summary_points"]


def frontier_mask(cost: np.ndarray, error: np.ndarray) -> np.ndarray:
    """Return True for points no other point dominates (cost <= and error <=, one of them <)."""
    c, e = np.asarray(cost, dtype=float), np.asarray(error, dtype=float)
    ok = np.isfinite(c) & np.isfinite(e)
    mask = np.zeros(c.size, dtype=bool)
    order = np.lexsort((e, c))  # by cost, ties by error
    best = np.inf
    for i in order:
        if not ok[i]:
            continue
        if e[i] < best:
            mask[i] = True
            best = e[i]
    # equal (cost, error) duplicates of a frontier point are not dominated either
    for i in np.flatnonzero(ok & ~mask):
        mask[i] = bool(np.any(mask & (c == c[i]) & (e == e[i])))
    return mask


def summary_points(result: BenchResult, modes: int) -> list[tuple[str, float, float]]:
    """Return the cost and error of every model configuration able to give ``modes`` frequencies.

    Each entry is (label, mean CPU s per simulated s, worst max frequency error over the first
    ``modes`` modes across beams, %).
    """
    groups: dict[tuple[str, int], list[ModelRow]] = {}
    for r in result.models:
        if r.joints >= modes:
            groups.setdefault((r.kind, r.joints), []).append(r)
    out = []
    for (kind, n), rows in sorted(groups.items()):
        errs = [r.max_freq_error_pct(modes) for r in rows]
        label = {"fitted": f"fitted {n}R", "chain": f"chain N={n}",
                 "mujoco": f"MuJoCo {n}R"}[kind]
        out.append((label, float(np.mean([r.sim_cpu_s_per_s for r in rows])),
                    float(np.max(errs))))
    return out


def _g(v: float, fmt: str = ".3g") -> str:
    return "-" if v is None or not np.isfinite(v) else format(v, fmt)


def markdown_report(result: BenchResult, machine: str = "") -> str:
    """Return the Markdown table of a run (models, comparisons, frontier, FE truth levels)."""
    cfg = result.config
    loads = ", ".join(f"{a:g}" for a in cfg.load_indices)
    lines = [
        "# Error against cost: fitted PRBDMs, finite-segment chains, FE truth",
        "",
        f"{machine}Run wall time {result.wall_time_s:.1f} s. Beams: {', '.join(cfg.beams)}.",
        "",
        "- Truth frequencies: Kirchhoff plate (Argyris, default mesh level), the "
        f"{result.truth_modes} bending modes of largest z mass participation.",
        "- Fitted nR: joint parametrisation (one factor per joint on the finite-segment springs), "
        "eigen objective on the straight pose, N = n frequencies, multistart of "
        f"{cfg.fit_starts} starts stopped at {cfg.fit_loss_tol_pct:g} % loss. Its n frequencies "
        "are fitted to the truth, so their error is the fit residual, not a prediction.",
        "- Chain N: N equal segments, springs at the segment centres (links h/2, h, ..., h, h/2), "
        "K = E / ∫dx/I (``finite_segment_stiffness``); nothing fitted.",
        f"- Tip error at P L²/(E I_root) = {loads}: |p_model − p_elastica| / |u_elastica|, "
        "against the inextensible elastica with EI(x) (exact for slender strips; for wide plates "
        "it misses the plate stiffening, a few per cent).",
        "- Step: relative L2 error of the tip step response over 1 s; FRF: relative L2 error of "
        "the complex tip FRF over [0, 1.2 ω_k], k = min(n, truth modes); both by modal "
        "superposition with 2 % modal damping, the truth keeping all its modes.",
        f"- Simulation cost: process CPU time of ``simulate`` (default integrator and step) for "
        f"{cfg.sim_duration_s:g} s of a step tip load (the smallest load case), per simulated "
        "second. MuJoCo rows: ``mj_step`` at the exporter's default step (1/20 of the shortest "
        "period).",
        "",
        "## Models",
        "",
        "| beam | model | fit wall s | fit loss % | freq error per mode % | max abs % "
        f"| tip error % ({loads}) | step % | FRF % | CPU s / sim s | note |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in result.models:
        label = {"fitted": f"fitted {r.joints}R", "chain": f"chain N={r.joints}",
                 "mujoco": f"MuJoCo {r.joints}R"}[r.kind]
        fe = " ".join(f"{e:+.4g}" for e in r.freq_errors_pct)
        tips = " / ".join(_g(t) for t in r.tip_errors_pct) if r.tip_errors_pct.size else "-"
        lines.append(
            f"| {r.beam} | {label} | {_g(r.fit_wall_s, '.2f')} | {_g(r.fit_loss_pct)} | {fe} "
            f"| {_g(r.max_freq_error_pct(r.omega_model_rad_s.size))} | {tips} "
            f"| {_g(r.step_error_pct)} | {_g(r.frf_error_pct)} | {_g(r.sim_cpu_s_per_s)} "
            f"| {r.note} |")
    lines += [
        "",
        "## Fitted nR against the smallest chain with ≥ 8n joints",
        "",
        "Frequency error: max |error| over the first n modes.",
        "",
        "| beam | n | fitted max err % | fitted CPU s / sim s | chain N | chain max err % "
        "| chain CPU s / sim s | as accurate | cheaper |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for c in result.comparisons:
        yes = "yes" if c.as_accurate else ("-" if c.chain_joints == 0 else "no")
        ch = "yes" if c.cheaper else ("-" if c.chain_joints == 0 else "no")
        lines.append(
            f"| {c.beam} | {c.joints} | {_g(c.fitted_error_pct, '.4g')} "
            f"| {_g(c.fitted_cost_s_per_s, '.4g')} | {c.chain_joints or '-'} "
            f"| {_g(c.chain_error_pct, '.4g')} | {_g(c.chain_cost_s_per_s, '.4g')} "
            f"| {yes} | {ch} |")
    lines += ["", "## Error against cost (frontier)", "",
              "Per model configuration: mean CPU s per simulated second over the beams, and the "
              "worst (over beams) max frequency error over the first k modes. * marks the "
              "non-dominated points.", "",
              "| first k modes | model | CPU s / sim s | worst max err % | frontier |",
              "|---|---|---|---|---|"]
    for k in plot_modes(result):
        pts = summary_points(result, k)
        mask = frontier_mask(np.array([p[1] for p in pts]), np.array([p[2] for p in pts]))
        for (label, cost, err), m in zip(pts, mask, strict=True):
            star = "*" if m else ""
            lines.append(f"| {k} | {label} | {_g(cost, '.4g')} | {_g(err, '.4g')} | {star} |")
    lines += ["", "## FE truth (plate) per mesh level", "",
              "| beam | level | DOFs | CPU s | wall s | error vs finest level per mode % |",
              "|---|---|---|---|---|---|"]
    for t in result.truths:
        errs = ("(finest run)" if t.errors_pct is None
                else " ".join(f"{e:+.2g}" for e in t.errors_pct))
        lines.append(f"| {t.beam} | {t.level} | {t.dofs} | {t.cpu_s:.2f} | {t.wall_s:.2f} "
                     f"| {errs} |")
    if result.notes:
        lines += ["", "## Notes", ""] + [f"- {s}" for s in result.notes]
    return "\n".join(lines) + "\n"


def result_dict(result: BenchResult) -> dict:
    """Return the raw numbers of a run as JSON-ready lists (frequencies in rad/s, errors in %)."""

    def f(v):
        return None if v is None or not np.isfinite(v) else float(v)

    return {
        "truth_modes": result.truth_modes,
        "load_indices": list(result.config.load_indices),
        "models": [{
            "beam": r.beam, "kind": r.kind, "joints": r.joints, "fit_wall_s": f(r.fit_wall_s),
            "fit_loss_pct": f(r.fit_loss_pct),
            "omega_model_rad_s": [float(v) for v in r.omega_model_rad_s],
            "omega_truth_rad_s": [float(v) for v in r.omega_truth_rad_s],
            "tip_errors_pct": [f(v) for v in r.tip_errors_pct],
            "step_error_pct": f(r.step_error_pct), "frf_error_pct": f(r.frf_error_pct),
            "sim_cpu_s_per_s": f(r.sim_cpu_s_per_s), "sim_wall_s_per_s": f(r.sim_wall_s_per_s),
            "note": r.note} for r in result.models],
        "truths": [{
            "beam": t.beam, "level": t.level, "dofs": t.dofs, "cpu_s": t.cpu_s,
            "wall_s": t.wall_s, "omega_rad_s": [float(v) for v in t.omega_rad_s],
            "errors_pct": None if t.errors_pct is None else [float(v) for v in t.errors_pct]}
            for t in result.truths],
        "wall_time_s": result.wall_time_s,
        "notes": list(result.notes),
    }


def plot_modes(result: BenchResult) -> list[int]:
    """Return the k of the "first k modes" panels and frontier tables: every fitted n."""
    return sorted(set(result.config.joints))
