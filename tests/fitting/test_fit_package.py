"""The fit package's pieces a caller can move between processes: the pymoo problem and repair
pickle, and a fit's process pool pins BLAS in its workers without touching the caller's
environment."""

from __future__ import annotations

import math
import os
import pickle

import numpy as np
import pytest

from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.fitting import LengthRepair, ParetoProblem, pareto_objectives_batch
from prbdm_pin.fitting.pool import fit_pool
from prbdm_pin.fitting.problem import make_problem
from prbdm_pin.fitting.target import FitTarget
from prbdm_pin.options.objects import FitOptions
from prbdm_pin.workers import BLAS_THREAD_VARS, pool_scope

BEAMS = "examples/beams"
BETA_L = np.array([1.8751040687120, 4.6940911329742])


@pytest.fixture(scope="module")
def problem():
    beam = load_beam(f"{BEAMS}/uniform-narrow.json")
    b = 2 * beam.half_width_m[0]
    EI = beam.material.E_Pa * b * beam.thickness_m**3 / 12
    rhoA = beam.material.rho_kg_m3 * b * beam.thickness_m
    omega = BETA_L**2 * math.sqrt(EI / (rhoA * beam.length_m**4))
    L = beam.length_m
    tip = np.array([L * (1 - 0.056433), 0.0, -0.301721 * L])
    target = FitTarget(omega, beam.tip_force_N, tip, tip - np.array([L, 0.0, 0.0]))
    return make_problem(beam, target, 2, FitOptions(frequencies=2, stiffness="paper", eps_rad=0.1,
                                                   eigen_norm="paper"))


def _rows(problem, bounds, k=5):
    rng = np.random.default_rng(3)
    n1 = problem.n_joints + 1
    gamma = rng.dirichlet(np.ones(n1), k) * (1 - n1 * 0.02) + 0.02
    return np.hstack([gamma, rng.uniform(*bounds, (k, problem.n_factors))])


def test_the_pareto_problem_pickles_and_evaluates_the_same(problem):
    bounds = (-1.0, 1.0)
    problem = make_problem(problem.beam, problem.target, 2,
                           problem.options.replace(deflection_norm="displacement"))
    pp = ParetoProblem(problem, bounds)
    copy = pickle.loads(pickle.dumps(pp))
    X = _rows(problem, bounds)
    F = pp.evaluate(X, return_as_dictionary=True)["F"]
    assert np.array_equal(copy.evaluate(X, return_as_dictionary=True)["F"], F)
    assert np.array_equal(F, pareto_objectives_batch(problem, X))
    assert np.array_equal(copy.xl, pp.xl) and np.array_equal(copy.xu, pp.xu)


def test_the_injected_runner_evaluates_and_is_left_out_of_the_pickle(problem):
    bounds = (-1.0, 1.0)
    calls = []

    def runner(X):
        calls.append(X.shape[0])
        return pareto_objectives_batch(problem, X)

    pp = ParetoProblem(problem, bounds, runner=runner)
    X = _rows(problem, bounds)
    F = pp.evaluate(X, return_as_dictionary=True)["F"]
    assert calls == [X.shape[0]]
    copy = pickle.loads(pickle.dumps(pp))  # a local function: only picklable when left out
    assert copy.runner is None
    assert np.array_equal(copy.evaluate(X, return_as_dictionary=True)["F"], F)


def test_the_length_repair_pickles():
    X = np.array([[0.5, 0.5, 0.5, 0.01, 3.0], [0.2, 0.3, 0.1, 0.4, -1.0]])
    repair = LengthRepair(4, min_fraction=0.03)
    copy = pickle.loads(pickle.dumps(repair))
    assert np.array_equal(copy._do(None, X), repair._do(None, X))
    assert np.all(copy._do(None, X)[:, :4] >= 0.03 - 1e-15)


def test_a_fit_pool_pins_blas_in_its_workers_not_in_the_caller(monkeypatch):
    for var in BLAS_THREAD_VARS:
        monkeypatch.delenv(var, raising=False)
    with pool_scope(fit_pool(1)) as ex:
        seen = [ex.submit(os.getenv, var).result() for var in BLAS_THREAD_VARS]
    assert seen == ["1"] * len(BLAS_THREAD_VARS)
    assert not any(var in os.environ for var in BLAS_THREAD_VARS)
