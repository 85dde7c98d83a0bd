"""The runs of ``bench_mujoco_accuracy.py``: one scene, the package's ``simulate`` at a sweep of
each integrator's accuracy setting, timed in CPU time, and what both engines share (the scene,
a run's record, its error, the timing; MuJoCo's side is ``mujoco_accuracy_mjcf``).

A scene is a chain, a load (a step tip force from rest or a release from a bent pose) and a
damping ratio (the stiffness form C = beta K, the form the MJCF's joint ``damping`` carries).
Every run samples the tip on the same 1 ms grid over the same simulated time; its error is
``max_t |tip(t) - tip_ref(t)| / max_t |tip_ref(t) - tip_ref(0)|`` (Euclidean norms, the
reference's peak excursion from its start: the peak deflection on a step, about twice the
initial deflection on a release).
"""

from __future__ import annotations

import _thread
import dataclasses
import functools
import inspect
import math
import signal
import threading
import time
from dataclasses import dataclass

import numpy as np

OUTPUT_DT_S = 1e-3
TARGETS = (1e-2, 1e-3, 1e-4)  # 1 %, 0.1 %, 0.01 % of the peak
# the sweeps, loosest first: solve_ivp-style tolerances, the exponential integrator's step
# control, fixed steps (s) that divide the 1 ms output or are multiples of it, MuJoCo's steps
RTOLS = tuple(10.0 ** -k for k in range(3, 12))
STEP_RTOLS = (1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7)
FIXED_DTS_S = (2e-3, 1e-3, 5e-4, 2.5e-4, 1e-4, 5e-5, 2.5e-5, 1e-5, 5e-6, 2.5e-6, 1e-6)
MUJOCO_DTS_S = (1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1e-4, 5e-5, 2.5e-5, 1e-5, 5e-6, 2.5e-6,
                1e-6)


@dataclass(frozen=True)
class Scene:
    """One case: the chain, the load and the damping, and the reference's tip samples."""

    label: str
    n_joints: int
    load: str  # "step" or "release"
    damping_ratio: float
    model: object
    kwargs: dict  # simulate's keyword arguments that set the scene
    force_N: np.ndarray  # the step tip force (zero on a release)
    q0_rad: np.ndarray
    ref_tip_m: np.ndarray  # (samples, 3) on the 1 ms grid
    peak_m: float
    q_scale_rad: float  # the reference's largest joint angle
    ref_cpu_s: float


@dataclass(frozen=True)
class Run:
    """One setting of one engine on one scene; CPU s per simulated s."""

    case: str
    engine: str  # "mujoco" or "package"
    method: str
    knob: str
    value: float
    error: float
    cpu_s_per_s: float
    steps: int
    bare_cpu_s_per_s: float = math.nan  # MuJoCo: mj_step alone, no tip read
    failure: str = ""

    @property
    def setting(self) -> str:
        """The method and its setting as the table prints them."""
        if self.knob == "default":
            return f"default ({self.method})"
        return f"{self.method} {self.knob}={self.value:.3g}"


def tip_error(tip_m: np.ndarray, scene: Scene, stride: int = 1) -> float:
    """Max |tip - reference| over the samples, over the peak; ``tip_m`` every ``stride`` ms."""
    ref = scene.ref_tip_m[::stride]
    if tip_m.shape != ref.shape or not np.all(np.isfinite(tip_m)):
        return math.inf
    return float(np.linalg.norm(tip_m - ref, axis=1).max()) / scene.peak_m


class OverCap(BaseException):
    """A run stopped at its CPU-time cap (not an Exception: no handler in the package may
    take it for a failure of its own)."""


def _over_cap(signum, frame):
    raise OverCap


class _Watchdog:
    """Stop the main thread's run once the process has spent ``cap_s`` of CPU since entry.

    A thread polls the process's CPU clock every 20 ms and interrupts the main thread with
    SIGUSR1 (no signal is sent: ``_thread.interrupt_main`` runs its handler there). A
    profiling timer (``setitimer(ITIMER_PROF)``) would be simpler, but while one is armed Linux
    reads the process's CPU time from its tick-sampled timer, so runs under a few ms measure 0.
    """

    def __init__(self, cap_s: float | None):
        self.cap_s = cap_s
        self.stop = threading.Event()

    def _watch(self, c0: float) -> None:
        while not self.stop.wait(0.02):
            if time.process_time() - c0 > self.cap_s:
                _thread.interrupt_main(signal.SIGUSR1)
                return

    def __enter__(self):
        if self.cap_s:
            self.old = signal.signal(signal.SIGUSR1, _over_cap)
            self.thread = threading.Thread(target=self._watch, args=(time.process_time(),),
                                           daemon=True)
            self.thread.start()
        return self

    def __exit__(self, *exc):
        if self.cap_s:
            self.stop.set()
            self.thread.join()
            signal.signal(signal.SIGUSR1, self.old)
        return False


def best_cpu(fn, repeats: int, cheap_s: float = 0.2, cap_s: float | None = None):
    """Least process CPU time of ``fn()`` (s) and its last result; repeated (up to
    ``repeats`` runs) only while a run is cheaper than ``cheap_s``, where timing noise is
    largest against the run.

    ``cap_s``: a run is stopped after this much CPU time and :class:`OverCap` raised, so that
    one slow setting cannot take the whole budget.
    """
    cpu, out = math.inf, None
    for _ in range(max(1, repeats)):
        with _Watchdog(cap_s):
            c0 = time.process_time()
            out = fn()
            cpu = min(cpu, time.process_time() - c0)
        if cpu >= cheap_s:
            break
    return cpu, out


# --- the package -----------------------------------------------------------------------------
def package_methods(names: tuple[str, ...] | None = None) -> list[tuple[str, object]]:
    """The package's integrators, cheapest first as far as known: (name, constructor).

    ``Compiled`` is taken when ``prbdm_pin.options.integrators`` has it; then the exponential
    integrator, the solve_ivp methods, the trapezoidal rule and Gauss-Legendre.
    """
    from prbdm_pin.options import integrators as integ
    from prbdm_pin.options.choices import IVP_METHODS

    out: list[tuple[str, object]] = []
    # each looked up by name, so that a run on a tree without one of them (an integrator added
    # or removed) still measures the others
    for cls_name in ("Compiled", "Exponential"):
        cls = getattr(integ, cls_name, None)
        if cls is not None:
            out.append((getattr(cls, "method", "") or cls_name.lower(), cls))
    out += [(m, functools.partial(integ.ScipyIVP, m)) for m in IVP_METHODS]
    for cls_name in ("Trapezoidal", "Gauss"):
        cls = getattr(integ, cls_name, None)
        if cls is not None:
            out.append((cls.method, cls))
    if names is not None:
        out = [(n, c) for n, c in out if n in names]
    return out


def knob_of(ctor) -> tuple[str, tuple[float, ...]]:
    """The setting swept for an integrator class and its values: ``rtol`` where it has one,
    else the exponential integrator's ``step_rtol``, else a fixed step ``dt_s``."""
    names = _field_names(ctor)
    if "rtol" in names:
        return "rtol", RTOLS
    if "step_rtol" in names:
        return "step_rtol", STEP_RTOLS
    return "dt_s", FIXED_DTS_S


def _field_names(ctor) -> set[str]:
    """The keyword arguments an integrator class takes (its fields, for a dataclass)."""
    cls = ctor.func if isinstance(ctor, functools.partial) else ctor
    if dataclasses.is_dataclass(cls):
        return {f.name for f in dataclasses.fields(cls)}
    return set(inspect.signature(cls).parameters)


def _settings(ctor, knob: str, value: float, q_scale_rad: float) -> dict:
    kw = {knob: value}
    if knob == "rtol" and "atol" in _field_names(ctor):
        # the joint-angle scale of the motion (the default takes it from q0, which is zero
        # on a step load)
        kw["atol"] = value * q_scale_rad
    return kw


def package_run(scene: Scene, method: str, knob: str, value: float, integrator,
                repeats: int, cap_s: float | None = None) -> Run:
    """One ``simulate`` call on ``scene`` (the whole call timed), ``integrator`` None: default;
    stopped after ``cap_s`` of CPU."""
    from prbdm_pin.simulation import simulate

    extra = {} if integrator is None else {"integrator": integrator}
    try:
        cpu, tr = best_cpu(lambda: simulate(scene.model, 1.0, output_dt_s=OUTPUT_DT_S,
                                            **scene.kwargs, **extra), repeats, cap_s=cap_s)
    except OverCap:
        return Run(scene.label, "package", method, knob, value, math.inf, cap_s, 0,
                   failure=f"stopped at the CPU cap ({cap_s:g} s)")
    except Exception as exc:  # noqa: BLE001 - a failing integrator is a result, recorded
        return Run(scene.label, "package", method, knob, value, math.inf, math.nan, 0,
                   failure=f"{type(exc).__name__}: {str(exc)[:120]}")
    if integrator is None:
        method = str(tr.method)  # the default's choice
    return Run(scene.label, "package", method, knob, value, tip_error(tr.tip_position_m, scene),
               cpu, int(tr.steps))


def warm_up(scene: Scene, ctor) -> None:
    """One short, untimed and uncapped run of the integrator ``ctor`` builds (None: the
    default) on ``scene``: a compiled integrator compiles (or loads its cache) on its first
    call in a process, a one-off cost the timed runs leave out (a cap would stop it)."""
    from prbdm_pin.simulation import simulate

    extra = {} if ctor is None else {"integrator": ctor()}
    try:
        simulate(scene.model, 0.01, output_dt_s=OUTPUT_DT_S, **scene.kwargs, **extra)
    except Exception:  # noqa: BLE001, S110 - the timed runs record what fails
        pass


def package_sweep(scene: Scene, methods, repeats: int, max_run_cpu_s: float,
                  log=print) -> list[Run]:
    """The default run, then each method from its loosest setting to the first that reaches
    the tightest target.

    A method's sweep stops early when a run costs more than ``max_run_cpu_s`` or more than the
    cheapest run of any method that reached the tightest target: its tighter settings cost
    more, so neither can be the cheapest at any target.
    """
    warm_up(scene, None)
    runs = [package_run(scene, "default", "default", math.nan, None, repeats)]
    log(runs[-1])
    for name, ctor in methods:
        knob, values = knob_of(ctor)
        warm_up(scene, ctor)
        stalled = failed = 0
        for value in values:
            try:
                integ = ctor(**_settings(ctor, knob, value, scene.q_scale_rad))
            except Exception as exc:  # noqa: BLE001 - a setting the class refuses is a result
                runs.append(Run(scene.label, "package", name, knob, value, math.inf, math.nan,
                                0, failure=f"{type(exc).__name__}: {str(exc)[:120]}"))
                log(runs[-1])
                break
            run = package_run(scene, name, knob, value, integ, repeats, max_run_cpu_s)
            runs.append(run)
            log(run)
            if run.failure.startswith("stopped"):
                break
            failed = failed + 1 if run.failure else 0
            if failed >= 3:
                break
            if run.failure:
                continue  # a finer setting may converge
            tight = [r.cpu_s_per_s for r in runs if r.error <= TARGETS[-1]]
            if run.error <= TARGETS[-1] or run.cpu_s_per_s > max_run_cpu_s \
                    or (tight and run.cpu_s_per_s > min(tight)):
                break
            # an error floor (the fixed-step schemes' phase error in the stiff modes): two
            # finer settings in a row that do not gain 10 % end the sweep
            prev = [r.error for r in runs[:-1]
                    if r.method == name and r.knob == knob and not r.failure]
            stalled = stalled + 1 if prev and run.error > 0.9 * prev[-1] else 0
            if stalled >= 2:
                break
    return runs


def cheapest(runs: list[Run], target: float) -> Run | None:
    """The least CPU run whose error is within ``target``, or None."""
    ok = [r for r in runs if r.error <= target]
    return min(ok, key=lambda r: r.cpu_s_per_s) if ok else None
