"""One measurement of ``bench_revisions.py``: one public call of prbdm_pin timed in this process.

Run with the revision under test first on ``PYTHONPATH`` (the driver does it), so ``import
prbdm_pin`` is that revision's tree; the call's set-up is not timed, its first call (numba's
compilation or cache load, lazy imports) is not timed either: the one-shot cost is what the
driver's CLI rows measure. Prints one JSON line: the least CPU time of one call over ``--runs``
runs (each the mean of as many calls as fit in ``--budget`` seconds), the file prbdm_pin was
imported from and, for a simulation, the integrator it ran; ``--tip FILE.npy`` saves a
simulation's tip samples for the driver's error against its reference.

Only spellings that both revisions share (0dd6ba3 and later) are used; where one changed, the
call picks the revision's own.

usage: python scripts/bench_revisions_calls.py CALL [--runs 3] [--budget 0.2] [--tip FILE.npy]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import atexit  # noqa: E402
import json  # noqa: E402
import shutil  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import prbdm_pin as pp  # noqa: E402

BEAMS = Path(pp.__file__).resolve().parents[1] / "examples" / "beams"
N_MODEL = 5  # the core-model calls' chain
BATCH = 32  # poses of the batched frequencies
DURATION_S = 1.0
OUTPUT_DT_S = 1e-3
RELEASE_RAD = 0.1
# simulations (the default integrator) and their DOP853 references at rtol 1e-11 (the driver's
# error): chain size and scene
SIMULATIONS = {"simulate 5R step": (5, "step"), "simulate 3R release": (3, "release")}
EXPONENTIAL = ", exponential"


def chain(beam, n: int):
    """The equal-segment chain (links h/2, h, ..., h, h/2) with finite-segment springs."""
    from prbdm_pin.chain.stiffness import finite_segment_stiffness

    h = beam.length_m / n
    lengths = np.r_[h / 2, np.full(n - 1, h), h / 2]
    return pp.build_model(beam, lengths, finite_segment_stiffness(beam, lengths))


def simulation(name: str, reference: bool):
    """A simulation row's call: the default integrator, ``Exponential()`` (a name ending in
    ", exponential": the same integrator at both revisions), or DOP853 at rtol 1e-11."""
    n, load = SIMULATIONS[name.removesuffix(EXPONENTIAL)]
    beam = pp.load_beam(BEAMS / "reference-random.json")
    model = chain(beam, n)
    kw = {"output_dt_s": OUTPUT_DT_S}
    if load == "step":
        kw["tip_force"] = np.asarray(beam.tip_force_N, dtype=float)  # 2500 N along -z
    else:
        kw["q0"] = np.full(n, RELEASE_RAD)
    if reference:
        kw["integrator"] = pp.ScipyIVP("DOP853", rtol=1e-11)
    elif name.endswith(EXPONENTIAL):
        kw["integrator"] = pp.Exponential()
    return lambda: pp.simulate(model, DURATION_S, **kw)


def fit_problem(beam, n: int):
    """The combined joint fit's problem on the beam truth and its first start's design."""
    from prbdm_pin.fitting.multistart import draw_starts
    from prbdm_pin.fitting.problem import make_problem

    truth = pp.compute_truth(beam, model="beam", modes=6, error_tol_pct=None)
    target = pp.target_from_truth(truth, beam.tip_force_N)
    o = pp.FitOptions(objective="combined", stiffness="joint")
    p = make_problem(beam, target, n, o)
    _, lengths, factors = draw_starts(p, 1, 0)[0]
    return target, p, lengths, factors


def make_call(name: str):
    """The zero-argument call timed as ``name``."""
    if name.removesuffix(EXPONENTIAL) in SIMULATIONS or name.startswith("reference "):
        return simulation(name.removeprefix("reference "), name.startswith("reference "))
    beam = pp.load_beam(BEAMS / "reference-random.json")
    model = chain(beam, N_MODEL)
    rng = np.random.default_rng(0)
    q = rng.uniform(0, np.pi / 2 / N_MODEL, N_MODEL)
    Q = rng.uniform(0, np.pi / 2 / N_MODEL, (BATCH, N_MODEL))
    EI, L = beam.root_EI_Nm2, beam.length_m
    tip = np.asarray(beam.tip_force_N, dtype=float)
    if name == "build_model 5R":
        return lambda: chain(beam, N_MODEL)
    if name == "frequencies 5R, one pose":
        return lambda: model.natural_frequencies(q)
    if name == f"frequencies 5R, batch of {BATCH} poses":
        return lambda: model.natural_frequencies_batch(Q)
    if name.startswith("static_deflection 5R"):
        alpha = 0.01 if "small" in name else 10.0  # load index P L^2 / (E I_root)
        F = np.array([0.0, 0.0, -alpha * EI / L**2])
        return lambda: model.static_deflection(F)
    if name == "linearize 5R straight":
        return lambda: pp.linearize(model)
    if name == "linearize 5R loaded":
        return lambda: pp.linearize(model, load_N=tip)
    if name == "fit 3R joint eigen, 4 starts":
        target = fit_problem(beam, 3)[0]
        o = pp.FitOptions(objective="eigen", stiffness="joint", starts=4, seed=0)
        return lambda: pp.fit(beam, target, 3, o, progress=False)
    if name == "evaluate 5R combined joint design":
        from prbdm_pin.fitting.evaluate import evaluate

        _, p, lengths, factors = fit_problem(beam, N_MODEL)
        return lambda: evaluate(p, lengths, factors)
    if name.startswith("export_model 5R"):
        fmt = name.split()[-1].lower()
        tmp = Path(tempfile.mkdtemp(prefix="bench_rev_"))
        atexit.register(shutil.rmtree, tmp, True)
        return lambda: pp.export_model(model, tmp / f"model.{fmt}", fmt)
    if name == "truth: plate modes (uniform-narrow)":
        narrow = pp.load_beam(BEAMS / "uniform-narrow.json")
        return lambda: pp.compute_truth(narrow, model="plate", modes=5)
    raise SystemExit(f"unknown call {name!r}")


def least_cpu_s(fn, runs: int, budget_s: float) -> tuple[float, float, object]:
    """(least mean CPU s, least mean wall s) of one call of fn over ``runs`` runs, and a result.

    The first call (compilation, cache loads) is untimed; a run repeats the call as often as
    fits in ``budget_s`` of the first timed call's CPU.
    """
    out = fn()
    c = time.process_time()
    fn()
    once = max(time.process_time() - c, 1e-7)
    number = max(1, int(budget_s / once))
    cpu = wall = float("inf")
    for _ in range(runs if once < 2.0 else 1):
        c, w = time.process_time(), time.perf_counter()
        for _ in range(number):
            fn()
        cpu = min(cpu, (time.process_time() - c) / number)
        wall = min(wall, (time.perf_counter() - w) / number)
    return cpu, wall, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("call")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--budget", type=float, default=0.2, help="seconds of calls per run")
    ap.add_argument("--tip", help="save a simulation's tip samples (m) to this .npy")
    a = ap.parse_args()
    fn = make_call(a.call)
    cpu, wall, out = least_cpu_s(fn, a.runs, a.budget)
    record = {"call": a.call, "cpu_s": cpu, "wall_s": wall, "prbdm_pin": pp.__file__}
    if a.tip:
        np.save(a.tip, np.asarray(out.tip_position_m))
        record["method"] = str(out.method)
    print(json.dumps(record))


if __name__ == "__main__":
    main()
