"""The spring parametrisations as objects: the option turns into its object, which pickles with
the problem and answers for one design as for a stack."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from paths import BEAMS

from prbdm_pin.chain.stiffness import pose_sweep
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.fitting.evaluate import batch_losses, evaluate
from prbdm_pin.fitting.joint_springs import JointSprings
from prbdm_pin.fitting.paper_springs import PaperSprings
from prbdm_pin.fitting.parametrisation import parametrisation
from prbdm_pin.fitting.problem import make_problem
from prbdm_pin.fitting.target import FitTarget
from prbdm_pin.options.choices import XI_RAD, Objective, StiffnessKind
from prbdm_pin.options.objects import FitOptions, ParetoOptions

BEAM = load_beam(BEAMS / "tapered.json")


def _target() -> FitTarget:
    L = BEAM.length_m
    tip = np.array([0.97 * L, 0.0, -0.2 * L])
    return FitTarget([12.0, 80.0, 230.0], BEAM.tip_force_N, tip, tip - [L, 0.0, 0.0])


@pytest.mark.parametrize("kind,cls", [("paper", PaperSprings), (StiffnessKind.JOINT,
                                                                 JointSprings)])
def test_the_choice_turns_into_its_object_named_as_the_files_write_it(kind, cls):
    p = parametrisation(kind)
    assert isinstance(p, cls)
    assert p.name == str(kind) and type(p.name) is str


def test_an_unknown_parametrisation_is_refused_by_name():
    with pytest.raises(BeamInputError, match="stiffness = 'spring'"):
        parametrisation("spring")


SWEEP = pose_sweep(3, XI_RAD, 0.05).shape[0]  # poses of a 3R sweep in steps of 0.05 rad


@pytest.mark.parametrize("options,poses,factors", [
    (FitOptions(stiffness="paper", eps_rad=0.05), SWEEP, SWEEP),
    (FitOptions(stiffness="joint"), 1, 3),
    (FitOptions(stiffness="joint", joint_sweep=True, eps_rad=0.05), SWEEP, 3),
    # a Pareto fit compares a joint model at the straight pose
    (ParetoOptions(stiffness="joint", eps_rad=0.05), 1, 3),
])
def test_the_problem_holds_its_options_and_parametrisation(options, poses, factors):
    problem = make_problem(BEAM, _target(), 3, options)
    assert problem.options is options
    assert problem.parametrisation.name == options.stiffness.value
    assert (problem.n_poses, problem.n_factors) == (poses, factors)
    copy = pickle.loads(pickle.dumps(problem))
    assert copy.parametrisation.name == problem.parametrisation.name
    assert np.array_equal(copy.poses_rad, problem.poses_rad)


@pytest.mark.parametrize("stiffness", ["paper", "joint"])
def test_one_design_and_a_stack_get_the_same_springs_and_losses(stiffness):
    problem = make_problem(BEAM, _target(), 3, FitOptions(stiffness=stiffness, eps_rad=0.3))
    P = problem.parametrisation
    rng = np.random.default_rng(1)
    L = np.array([[0.2, 0.3, 0.3, 0.2], [0.1, 0.4, 0.3, 0.2]]) * BEAM.length_m
    f = np.exp(rng.uniform(-0.3, 0.3, (2, problem.n_factors)))
    K0 = np.array([P.build(problem, row)[1] for row in L])
    K = P.pose_springs(K0, f, problem.n_poses)
    assert K.shape == (2, problem.n_poses, 3)
    for b in range(2):
        assert np.array_equal(K[b], P.pose_springs(K0[b], f[b], problem.n_poses))
    assert P.static_rows(K).shape == (2 * P.n_static_rows(problem.n_poses), 3)
    batch = batch_losses(problem, L, f)
    for b in range(2):
        ev = evaluate(problem, L[b], f[b])
        np.testing.assert_allclose(batch.eigen_errors[b], ev.eigen_errors, rtol=1e-9)
        np.testing.assert_allclose(batch.position_errors[b], ev.position_errors, rtol=1e-7)


def test_an_objective_says_which_terms_it_has():
    assert [(o.has_eigen_term, o.has_deflection_term) for o in Objective] == [
        (True, False), (False, True), (True, True)]
