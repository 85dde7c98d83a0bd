"""The measurements of a benchmark run.

Fitted nR models, finite-segment chains, the MuJoCo peer and the FE truth levels of every beam
of a :class:`~prbdm_pin.bench.config.BenchConfig`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..errors import BeamInputError, SolveError
from ..files.beam_file import load_beam
from ..member.geometry import Beam
from ..member.random_beams import random_beam
from .config import DAMPING_RATIO, QUICK, BenchConfig, BenchResult, Comparison, ModelRow, TruthRow

__all__ = ["bench_beams", "chain_lengths", "finite_segment_chain", "mujoco_row",
           "run_benchmark", "work_units"]


def chain_lengths(length_m: float, n_joints: int) -> np.ndarray:
    """Link lengths of an N-joint finite-segment chain: [h/2, h, ..., h, h/2], h = L / N, m."""
    return np.r_[0.5, np.ones(n_joints - 1), 0.5] * (length_m / n_joints)


def finite_segment_chain(beam: Beam, n_joints: int):
    """Build the hand-built chain: equal segments, springs at the segment centres, K = E / ∫dx/I."""
    from ..chain.stiffness import finite_segment_stiffness
    from ..model.prbdm_model import build_model

    lengths = chain_lengths(beam.length_m, n_joints)
    frac = min(0.02, 0.25 / n_joints)  # the end half-links are 1/(2N) of L
    k = finite_segment_stiffness(beam, lengths, frac)
    return build_model(beam, lengths, k, min_fraction=frac)


def bench_beams(names: tuple[str, ...], beam_dir: str | Path | None = None) -> list[Beam]:
    """Return the beams of a config.

    Shipped names come from ``beam_dir`` (default ``examples/beams``) and ``random-<seed>``
    stands for ``random_beam(np.random.default_rng(seed))``.
    """
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
    here = Path(__file__).resolve().parents[1]  # the package folder
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
    from ..simulation.response import modal_frf, modal_step_response, prbdm_modal_tip, relative_l2

    mine = prbdm_modal_tip(model)
    t = np.linspace(0.0, 1.0, 2001)
    step = relative_l2(modal_step_response(mine, t, DAMPING_RATIO),
                       modal_step_response(truth_tip, t, DAMPING_RATIO))
    w = np.linspace(0.0, 1.2 * float(truth_tip.omega_rad_s[n_band - 1]), 2001)
    frf = relative_l2(modal_frf(mine, w, DAMPING_RATIO), modal_frf(truth_tip, w, DAMPING_RATIO))
    return 100.0 * step, 100.0 * frf


def _sim_cost(model, force: np.ndarray, duration_s: float) -> tuple[float, float]:
    from ..simulation import simulate

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


def mujoco_row(beam: Beam, model, omega_truth, duration_s: float) -> ModelRow | None:
    """Measure the MuJoCo peer of ``model``: its frequencies and its simulation cost.

    Parameters
    ----------
    beam : Beam
        The beam (its name labels the row).
    model : PrbdmModel
        The chain exported to MJCF.
    omega_truth : array_like
        Truth natural frequencies, rad/s.
    duration_s : float
        Simulated time, s.

    Returns
    -------
    ModelRow or None
        The row (cost in CPU and wall s per simulated s); None without MuJoCo installed.
    """
    try:
        import mujoco
    except ImportError:
        return None
    from ..chain.eigen import generalized_eigh
    from ..files.export import mjcf_text

    m = mujoco.MjModel.from_xml_string(mjcf_text(model, DAMPING_RATIO))
    # the peer's cost is measured with MuJoCo's default (semi-implicit Euler) step, as a MuJoCo
    # user would run a hinge chain; the exported file asks for RK4 (four evaluations a step)
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    k = min(model.n_joints, omega_truth.size)
    w2 = generalized_eigh(np.diag(np.asarray(m.jnt_stiffness, dtype=float)), M, "MuJoCo modes",
                          vectors=False)
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
    from ..truth import DEFAULT_COMPUTED_MODES, compute_modal
    from ..truth.modes import select_modes

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
    from ..fitting import fit
    from ..fitting.target import target_from_truth
    from ..simulation.response import centerline_modal_tip
    from ..truth import compute_truth
    from ..truth.elastica import elastica_static

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
                    loss_tol_pct=config.fit_loss_tol_pct,
                    # Eq. 16: the norm the published error-vs-cost figures were measured in
                    eigen_norm="paper")
            from ..model.prbdm_model import build_model

            model = build_model(beam, r.lengths_m, r.stiffness_Nm_per_rad)
            note = "" if r.eigen_loss_pct <= 1e-3 else f"fit stopped at {r.eigen_loss_pct:.3g} %"
            models.append(_measure(beam, "fitted", model, omega_truth, forces, statics,
                                   truth_tip, config.sim_duration_s, r.wall_time_s,
                                   r.eigen_loss_pct, note))
            if config.mujoco:
                row = mujoco_row(beam, model, omega_truth, config.sim_duration_s)
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
    """Return the number of ``progress`` calls a run of ``config`` makes."""
    return len(config.beams) * (2 + len(config.joints) + len(config.chain_joints))
