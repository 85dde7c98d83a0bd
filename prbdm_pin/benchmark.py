"""Error against cost: fitted nR PRBDMs beside hand-built finite-segment chains and the FE truth.

For every beam of a :class:`BenchConfig` this measures

- **fitted nR models** (``fit(..., stiffness="joint", objective="eigen")``: joint parametrisation,
  eigen objective on the straight pose, N = n frequencies): fit wall time, the error of each of the
  first n bending frequencies against the plate truth (``compute_truth``, default level, cached);
- **finite-segment chains** (N equal segments, half segments at both ends so that the springs sit
  at the segment centres, K = ``finite_segment_stiffness``), the model a user builds by hand;
- for both: the tip error at load indices P L^2 / (E I_root) (default 1e-3, 1, 5) against the
  inextensible elastica (``truth.elastica.elastica_static``: exact for slender strips, a few
  per cent off for wide plates, whose plate-bending stiffness it ignores), relative to the elastica
  tip displacement; the dynamic error (tip step response over 1 s and tip FRF, both by modal
  superposition, :mod:`prbdm_pin.response`, against the truth's modes with 2 % modal damping); the
  simulation cost (process CPU time of ``simulate`` per simulated second, step tip load, default
  integrator and step);
- **the FE truth** at several plate mesh levels: CPU time of the modal solve and frequency error
  against the finest level run;
- optionally a **MuJoCo peer**: the fitted nR model exported as an MJCF hinge chain
  (``export.mjcf_text``), its frequencies from MuJoCo's own mass matrix and joint stiffness, its
  cost from ``mj_step`` at the exporter's default time step with MuJoCo's default Euler
  integrator (MuJoCo imported lazily).

The results are plain frozen dataclasses; :func:`markdown_report` and :func:`plot_error_vs_cost`
turn them into a table and a log-log figure with the non-dominated frontier marked.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import BeamInputError, SolveError
from .geometry import Beam, load_beam, random_beam

__all__ = [
    "BenchConfig",
    "QUICK",
    "FULL",
    "ModelRow",
    "TruthRow",
    "Comparison",
    "BenchResult",
    "chain_lengths",
    "finite_segment_chain",
    "bench_beams",
    "run_benchmark",
    "frontier_mask",
    "markdown_report",
    "result_dict",
    "plot_error_vs_cost",
]

SHIPPED = ("uniform-narrow", "square-plate", "reference-random")
RANDOM_SEEDS = (11, 12, 13, 14, 15)
DAMPING_RATIO = 0.02


@dataclass(frozen=True)
class BenchConfig:
    """What a benchmark run covers.

    Attributes
    ----------
    beams : tuple of str
        Shipped beam names (``examples/beams``) and/or ``"random-<seed>"`` for
        ``random_beam(np.random.default_rng(seed))``.
    joints : tuple of int
        n of the fitted nR models.
    chain_joints : tuple of int
        N of the finite-segment chains.
    truth_levels : tuple of int
        Plate mesh levels timed for the FE truth rows (errors against the last).
    load_indices : tuple of float
        P L^2 / (E I_root) of the tip-error load cases.
    sim_duration_s : float
        Simulated time of each cost measurement, s.
    fit_starts : int
        Multistart size of each fit (stopped early at ``fit_loss_tol``).
    fit_loss_tol_pct : float
        Eigen loss (%) at which a fit stops drawing starts.
    mujoco : bool
        Add the MuJoCo peer when ``mujoco`` is importable.
    """

    beams: tuple[str, ...]
    joints: tuple[int, ...]
    chain_joints: tuple[int, ...]
    truth_levels: tuple[int, ...]
    load_indices: tuple[float, ...] = (1e-3, 1.0, 5.0)
    sim_duration_s: float = 0.5
    fit_starts: int = 16
    fit_loss_tol_pct: float = 1e-6
    mujoco: bool = True

    def __post_init__(self) -> None:
        if not self.beams or not self.joints or not self.chain_joints:
            raise BeamInputError("BenchConfig: beams, joints and chain_joints must be non-empty")
        for name, vals, lo in (("joints", self.joints, 1), ("chain_joints", self.chain_joints, 1)):
            if any(int(v) != v or v < lo for v in vals):
                raise BeamInputError(f"{name} = {vals}: must be integers >= {lo}")
        if not (self.sim_duration_s > 0 and math.isfinite(self.sim_duration_s)):
            raise BeamInputError(f"sim_duration_s = {self.sim_duration_s}: must be > 0 (s)")


FULL = BenchConfig(
    beams=SHIPPED + tuple(f"random-{s}" for s in RANDOM_SEEDS),
    joints=tuple(range(1, 9)),
    chain_joints=(2, 4, 8, 16, 32, 64),
    truth_levels=(0, 1, 2),
)
QUICK = BenchConfig(
    beams=("uniform-narrow", "reference-random"),
    joints=(2, 4),
    chain_joints=(4, 16, 32),
    truth_levels=(0,),
    sim_duration_s=0.1,
    fit_starts=8,
    mujoco=False,
)


@dataclass(frozen=True, eq=False)
class ModelRow:
    """One model of one beam.

    Attributes
    ----------
    beam : str
    kind : str
        ``"fitted"``, ``"chain"`` or ``"mujoco"`` (the fitted model run in MuJoCo).
    joints : int
    fit_wall_s : float
        Fit wall time, s (NaN for chains).
    fit_loss_pct : float
        Eigen loss of the fit, % (NaN for chains).
    omega_model_rad_s, omega_truth_rad_s : ndarray, shape (k,)
        The model's first k = min(joints, truth modes) frequencies and the truth's, rad/s.
    tip_errors_pct : ndarray, shape (loads,)
        |p_model - p_elastica| / |u_elastica| per load index, % (NaN: statics failed/not run).
    step_error_pct, frf_error_pct : float
        Relative L2 error of the tip step response and FRF, % (NaN: not run).
    sim_cpu_s_per_s, sim_wall_s_per_s : float
        CPU and wall time per simulated second, s/s.
    note : str
    """

    beam: str
    kind: str
    joints: int
    fit_wall_s: float
    fit_loss_pct: float
    omega_model_rad_s: np.ndarray
    omega_truth_rad_s: np.ndarray
    tip_errors_pct: np.ndarray
    step_error_pct: float
    frf_error_pct: float
    sim_cpu_s_per_s: float
    sim_wall_s_per_s: float
    note: str = ""

    @property
    def freq_errors_pct(self) -> np.ndarray:
        """Signed relative error of each compared frequency, %."""
        return 100.0 * (self.omega_model_rad_s / self.omega_truth_rad_s - 1.0)

    def max_freq_error_pct(self, modes: int) -> float:
        """Largest |error| over the first ``modes`` frequencies, % (NaN if fewer are available)."""
        e = self.freq_errors_pct
        return float(np.max(np.abs(e[:modes]))) if e.size >= modes else float("nan")


@dataclass(frozen=True, eq=False)
class TruthRow:
    """The plate truth of one beam at one mesh level.

    Attributes
    ----------
    beam : str
    level, dofs : int
    cpu_s, wall_s : float
        Modal solve and mode selection, s.
    omega_rad_s : ndarray
        Selected bending frequencies, rad/s.
    errors_pct : ndarray or None
        Error of each against the finest level run, % (None for the finest itself).
    """

    beam: str
    level: int
    dofs: int
    cpu_s: float
    wall_s: float
    omega_rad_s: np.ndarray
    errors_pct: np.ndarray | None


@dataclass(frozen=True)
class Comparison:
    """Fitted nR model against the smallest finite-segment chain with >= 8n joints run.

    ``chain_joints`` is 0 when no chain that large was run.
    """

    beam: str
    joints: int
    fitted_error_pct: float
    fitted_cost_s_per_s: float
    chain_joints: int
    chain_error_pct: float
    chain_cost_s_per_s: float

    @property
    def as_accurate(self) -> bool:
        """The fitted model's max frequency error is at most the chain's."""
        return self.chain_joints > 0 and self.fitted_error_pct <= self.chain_error_pct

    @property
    def cheaper(self) -> bool:
        """The fitted model simulates at lower CPU cost than the chain."""
        return self.chain_joints > 0 and self.fitted_cost_s_per_s < self.chain_cost_s_per_s


@dataclass(frozen=True, eq=False)
class BenchResult:
    """Everything one run measured."""

    config: BenchConfig
    models: tuple[ModelRow, ...]
    truths: tuple[TruthRow, ...]
    comparisons: tuple[Comparison, ...]
    truth_modes: int
    wall_time_s: float
    notes: tuple[str, ...] = field(default_factory=tuple)


# --- models ---------------------------------------------------------------------------------
def chain_lengths(length_m: float, n_joints: int) -> np.ndarray:
    """Link lengths of an N-joint finite-segment chain: [h/2, h, ..., h, h/2], h = L / N, m."""
    return np.r_[0.5, np.ones(n_joints - 1), 0.5] * (length_m / n_joints)


def finite_segment_chain(beam: Beam, n_joints: int):
    """The hand-built chain: equal segments, springs at the segment centres, K = E / ∫dx/I."""
    from .model import build_model
    from .stiffness import finite_segment_stiffness

    lengths = chain_lengths(beam.length_m, n_joints)
    frac = min(0.02, 0.25 / n_joints)  # the end half-links are 1/(2N) of L
    k = finite_segment_stiffness(beam, lengths, frac)
    return build_model(beam, lengths, k, min_fraction=frac)


def bench_beams(names: tuple[str, ...], beam_dir: str | Path | None = None) -> list[Beam]:
    """The beams of a config: shipped names from ``beam_dir`` (default ``examples/beams``) and
    ``random-<seed>`` for ``random_beam(np.random.default_rng(seed))``."""
    d = Path(beam_dir) if beam_dir is not None else _examples_dir()
    out = []
    for name in names:
        if name.startswith("random-"):
            try:
                seed = int(name.split("-", 1)[1])
            except ValueError:
                raise BeamInputError(f"beam = {name!r}: random beams are 'random-<seed>'") from None
            b = random_beam(np.random.default_rng(seed))
            out.append(b if b.name == name else _renamed(b, name))
        else:
            out.append(load_beam(d / f"{name}.json"))
    return out


def _renamed(beam: Beam, name: str) -> Beam:
    from dataclasses import replace

    return replace(beam, name=name)


def _examples_dir() -> Path:
    here = Path(__file__).resolve().parent
    for cand in (here.parent / "examples" / "beams", here / "examples"):
        if cand.is_dir():
            return cand
    try:
        from importlib.resources import files

        return Path(str(files("prbdm_pin.examples")))
    except (ModuleNotFoundError, TypeError):
        raise BeamInputError("examples/beams: shipped beams not found") from None


def _load_direction(beam: Beam) -> np.ndarray:
    f = np.asarray(beam.tip_force_N, dtype=float)
    f = np.array([f[0], 0.0, f[2]])
    nrm = float(np.linalg.norm(f))
    return f / nrm if nrm > 0 else np.array([0.0, 0.0, -1.0])


def _tip_errors(model, forces: list[np.ndarray], ref: list) -> tuple[np.ndarray, str]:
    out, notes = [], []
    for F, s in zip(forces, ref, strict=True):
        if s is None:
            out.append(float("nan"))
            continue
        try:
            _, tip = model.static_deflection(F)
        except SolveError as exc:
            out.append(float("nan"))
            notes.append(f"statics failed: {exc}")
            continue
        out.append(100.0 * float(np.linalg.norm(tip - s.tip_position_m)
                                 / np.linalg.norm(s.tip_displacement_m)))
    return np.array(out), "; ".join(notes)


def _dynamic_errors(model, truth_tip, n_band: int) -> tuple[float, float]:
    """Step (1 s) and FRF (band [0, 1.2 omega_truth[n_band-1]]) errors, %; truth: all its modes."""
    from .response import modal_frf, modal_step_response, prbdm_modal_tip, relative_l2

    mine = prbdm_modal_tip(model)
    t = np.linspace(0.0, 1.0, 2001)
    step = relative_l2(modal_step_response(mine, t, DAMPING_RATIO),
                       modal_step_response(truth_tip, t, DAMPING_RATIO))
    w = np.linspace(0.0, 1.2 * float(truth_tip.omega_rad_s[n_band - 1]), 2001)
    frf = relative_l2(modal_frf(mine, w, DAMPING_RATIO), modal_frf(truth_tip, w, DAMPING_RATIO))
    return 100.0 * step, 100.0 * frf


def _sim_cost(model, force: np.ndarray, duration_s: float) -> tuple[float, float]:
    from .simulation import simulate

    t0, c0 = time.perf_counter(), time.process_time()
    simulate(model, duration_s, tip_force=force, damping_ratio=DAMPING_RATIO)
    return (time.process_time() - c0) / duration_s, (time.perf_counter() - t0) / duration_s


def _measure(beam: Beam, kind: str, model, omega_truth, forces, statics, truth_tip,
             duration_s: float, fit_wall_s=float("nan"), fit_loss_pct=float("nan"),
             note: str = "") -> ModelRow:
    k = min(model.n_joints, omega_truth.size)
    omega = np.asarray(model.natural_frequencies(), dtype=float)[:k]
    tips, tip_note = _tip_errors(model, forces, statics)
    step, frf = _dynamic_errors(model, truth_tip, k)
    cpu, wall = _sim_cost(model, forces[0], duration_s)
    notes = "; ".join(s for s in (note, tip_note) if s)
    return ModelRow(beam.name, kind, model.n_joints, fit_wall_s, fit_loss_pct, omega,
                    np.asarray(omega_truth[:k], dtype=float), tips, step, frf, cpu, wall, notes)


def _mujoco_row(beam: Beam, model, omega_truth, duration_s: float) -> ModelRow | None:
    try:
        import mujoco
    except ImportError:
        return None
    from scipy.linalg import eigh

    from .export import mjcf_text

    m = mujoco.MjModel.from_xml_string(mjcf_text(model, DAMPING_RATIO))
    # the peer's cost is measured with MuJoCo's default (semi-implicit Euler) step, as a MuJoCo
    # user would run a hinge chain; the exported file asks for RK4 (four evaluations a step)
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    k = min(model.n_joints, omega_truth.size)
    w2 = eigh(np.diag(np.asarray(m.jnt_stiffness, dtype=float)), M, eigvals_only=True)
    omega = np.sqrt(w2)[:k]
    steps = max(1, int(round(duration_s / m.opt.timestep)))
    t0, c0 = time.perf_counter(), time.process_time()
    for _ in range(steps):
        mujoco.mj_step(m, d)
    cpu, wall = time.process_time() - c0, time.perf_counter() - t0
    dur = steps * m.opt.timestep
    nan = float("nan")
    return ModelRow(beam.name, "mujoco", model.n_joints, nan, nan, omega,
                    np.asarray(omega_truth[:k], dtype=float), np.full(0, nan), nan, nan,
                    cpu / dur, wall / dur, f"mj_step, dt = {m.opt.timestep:.3g} s")


def _truth_rows(beam: Beam, levels: tuple[int, ...], modes: int) -> list[TruthRow]:
    from .truth import DEFAULT_COMPUTED_MODES, compute_modal
    from .truth.modes import select_modes

    raw = []
    for level in levels:
        t0, c0 = time.perf_counter(), time.process_time()
        modal = compute_modal(beam, "plate", level, DEFAULT_COMPUTED_MODES)
        idx = select_modes(modal, modes, "paper")
        raw.append((level, int(modal.dofs), time.process_time() - c0, time.perf_counter() - t0,
                    np.asarray(modal.omega_rad_s)[idx]))
    finest = raw[-1][4]
    return [TruthRow(beam.name, lv, dofs, cpu, wall, w,
                     None if i == len(raw) - 1 else 100.0 * (w / finest - 1.0))
            for i, (lv, dofs, cpu, wall, w) in enumerate(raw)]


def _comparisons(models: list[ModelRow]) -> list[Comparison]:
    out = []
    for f in (r for r in models if r.kind == "fitted"):
        n = f.joints
        chains = sorted((r for r in models if r.kind == "chain" and r.beam == f.beam
                         and r.joints >= 8 * n), key=lambda r: r.joints)
        c = chains[0] if chains else None
        out.append(Comparison(
            f.beam, n, f.max_freq_error_pct(n), f.sim_cpu_s_per_s,
            c.joints if c else 0, c.max_freq_error_pct(n) if c else float("nan"),
            c.sim_cpu_s_per_s if c else float("nan")))
    return out


def run_benchmark(
    config: BenchConfig = QUICK,
    cache_dir: str | Path | None = None,
    beam_dir: str | Path | None = None,
    progress: Callable[[str], None] | None = None,
) -> BenchResult:
    """Run the benchmark of ``config``.

    Parameters
    ----------
    config : BenchConfig
    cache_dir : path, optional
        Truth cache (``compute_truth(cache_dir=...)``): reruns skip the plate solves.
    beam_dir : path, optional
        Where the shipped beams are (default ``examples/beams``).
    progress : callable, optional
        Called with a short label after every unit of work (the CLI drives a tqdm bar with it).

    Returns
    -------
    BenchResult
    """
    from .fitting import fit
    from .response import centerline_modal_tip
    from .target import target_from_truth
    from .truth import compute_truth
    from .truth.elastica import elastica_static

    tick = progress or (lambda label: None)
    t_start = time.perf_counter()
    modes = max(max(config.joints), 1)
    models: list[ModelRow] = []
    truths: list[TruthRow] = []
    notes: list[str] = []
    for beam in bench_beams(config.beams, beam_dir):
        truth = compute_truth(beam, modes=modes, static=False, cache_dir=cache_dir)
        omega_truth = np.asarray(truth.omega_rad_s, dtype=float)
        truth_tip = centerline_modal_tip(truth.modal, beam, truth.mode_index)
        EI, L = beam.root_EI_Nm2, beam.length_m
        forces = [a * EI / L**2 * _load_direction(beam) for a in config.load_indices]
        statics = []
        for a, F in zip(config.load_indices, forces, strict=True):
            try:
                statics.append(elastica_static(beam, F))
            except SolveError as exc:
                statics.append(None)
                notes.append(f"{beam.name}: elastica at P L^2/EI = {a:g} failed ({exc})")
        tick(f"{beam.name}: truth")
        target = target_from_truth(truth, beam.tip_force_N)
        for n in config.joints:
            if n > omega_truth.size:
                notes.append(f"{beam.name}: {n}R skipped, truth has {omega_truth.size} modes")
                continue
            r = fit(beam, target, n, frequencies=n, objective="eigen", stiffness="joint",
                    starts=config.fit_starts, seed=0, progress=False,
                    loss_tol=config.fit_loss_tol_pct,
                    # Eq. 16: the norm the published error-vs-cost figures were measured in
                    eigen_norm="paper")
            from .model import build_model

            model = build_model(beam, r.lengths_m, r.stiffness_Nm_per_rad)
            note = "" if r.eigen_loss_pct <= 1e-3 else f"fit stopped at {r.eigen_loss_pct:.3g} %"
            models.append(_measure(beam, "fitted", model, omega_truth, forces, statics,
                                   truth_tip, config.sim_duration_s, r.wall_time_s,
                                   r.eigen_loss_pct, note))
            if config.mujoco:
                row = _mujoco_row(beam, model, omega_truth, config.sim_duration_s)
                if row is not None:
                    models.append(row)
            tick(f"{beam.name}: {n}R fit")
        for N in config.chain_joints:
            model = finite_segment_chain(beam, N)
            models.append(_measure(beam, "chain", model, omega_truth, forces, statics,
                                   truth_tip, config.sim_duration_s))
            tick(f"{beam.name}: chain N = {N}")
        truths.extend(_truth_rows(beam, config.truth_levels, modes))
        tick(f"{beam.name}: FE levels")
    return BenchResult(config, tuple(models), tuple(truths), tuple(_comparisons(models)), modes,
                       time.perf_counter() - t_start, tuple(notes))


def work_units(config: BenchConfig) -> int:
    """Number of ``progress`` calls a run of ``config`` makes."""
    return len(config.beams) * (2 + len(config.joints) + len(config.chain_joints))


# --- frontier, table, figure ----------------------------------------------------------------
def frontier_mask(cost: np.ndarray, error: np.ndarray) -> np.ndarray:
    """True for points no other point dominates (cost <= and error <=, one of them <)."""
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
    """(label, mean CPU s per simulated s, worst max frequency error over the first ``modes``
    modes across beams, %) of every model configuration able to give ``modes`` frequencies."""
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
    """The Markdown table of a run (models, comparisons, frontier points, FE truth levels)."""
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
    for k in _plot_modes(result):
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
    """The raw numbers of a run as JSON-ready lists (frequencies in rad/s, errors in %)."""

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


def _plot_modes(result: BenchResult) -> list[int]:
    return sorted(set(result.config.joints))


def plot_error_vs_cost(result: BenchResult, path: str | Path) -> Path:
    """Log-log error against simulation cost, one panel per k (first k modes), frontier marked;
    a last panel shows the FE truth levels (modal-solve CPU against error vs the finest level).
    Writes a PNG atomically."""
    from .plots import _pyplot, _save

    plt = _pyplot()
    ks = _plot_modes(result)
    fe = [t for t in result.truths if t.errors_pct is not None]
    panels = len(ks) + (1 if fe else 0)
    ncol = min(panels, 3)  # a grid, so that the figure stays readable at any k
    nrow = -(-panels // ncol)
    fig, grid = plt.subplots(nrow, ncol, figsize=(4.6 * ncol, 3.9 * nrow), squeeze=False)
    axes = grid.ravel()
    for ax in axes[panels:]:
        ax.set_visible(False)
    style = {"fitted": ("o", "C0"), "chain": ("s", "C1"), "MuJoCo": ("^", "C2")}
    for ax, k in zip(axes, ks, strict=False):
        pts = summary_points(result, k)
        cost = np.array([p[1] for p in pts])
        err = np.maximum(np.array([p[2] for p in pts]), 1e-10)
        mask = frontier_mask(cost, err)
        for (label, c, e) in zip([p[0] for p in pts], cost, err, strict=True):
            mk, col = style[label.split()[0]]
            ax.loglog(c, e, mk, color=col, ms=6)
            ax.annotate(label.split()[-1], (c, e), fontsize=7, xytext=(3, 3),
                        textcoords="offset points")
        order = np.argsort(cost[mask])
        ax.loglog(cost[mask][order], err[mask][order], "k--", lw=1, label="frontier")
        for kind, (mk, col) in style.items():
            ax.plot([], [], mk, color=col, label=kind)
        ax.set_xlabel("CPU s per simulated s")
        ax.set_ylabel(f"max freq. error, first {k} modes (%)")
        ax.set_title(f"first {k} modes (worst over beams)")
        ax.legend(fontsize=7)
        ax.grid(True, which="both", alpha=0.3)
    if fe:
        ax = axes[panels - 1]
        for t in fe:
            ax.loglog(t.cpu_s, max(float(np.max(np.abs(t.errors_pct))), 1e-10), "d")
            ax.annotate(f"{t.beam} L{t.level}", (t.cpu_s, float(np.max(np.abs(t.errors_pct)))),
                        fontsize=7)
        ax.set_xlabel("modal solve CPU s")
        ax.set_ylabel("max error vs finest level (%)")
        ax.set_title("FE truth (plate)")
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    out = _save(fig, path)
    plt.close(fig)
    return out
