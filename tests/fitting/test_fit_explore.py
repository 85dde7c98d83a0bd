"""The joint deflection and combined fits: explore every start, refine the best.

Checked against the same multistart with every start run to convergence, against scipy's
trust-region least squares (another algorithm) from the same start, and across worker counts.
"""

import numpy as np
import pytest
from scipy.optimize import least_squares

import prbdm_pin as pp
from prbdm_pin.fitting.explore import run_explored
from prbdm_pin.fitting.joint import JointResiduals
from prbdm_pin.fitting.local import explore_start, joint_box, refine_start
from prbdm_pin.fitting.multistart import draw_starts
from prbdm_pin.fitting.problem import make_problem, unit_from_lengths
from prbdm_pin.fitting.spec import FitSpec

TAPERED = pp.load_beam("examples/beams/tapered.json")


@pytest.fixture(scope="module")
def target():
    """The tapered panel's 1D beam truth: six frequencies and the tip under its load."""
    truth = pp.compute_truth(TAPERED, model="beam", modes=6, error_tol_pct=None)
    return pp.target_from_truth(truth, TAPERED.tip_force_N)


def _spec(target, n=3, max_nfev=400):
    o = pp.FitOptions(objective="combined", stiffness="joint")
    return FitSpec(make_problem(TAPERED, target, n, o), o.objective, max_nfev)


def test_a_start_reaches_the_optimum_scipys_trf_reaches(target):
    """From one start, the explored and refined solve ends at scipy's trf optimum (run to its
    own convergence): the same loss and the same chain."""
    spec = _spec(target, max_nfev=4000)
    _, L0, F0 = draw_starts(spec.problem, 1, 2)[0]  # a start trf takes to the same basin
    ours = refine_start(spec, *explore_start(spec, 0, L0, F0, 64))
    J = JointResiduals(spec)
    n = spec.problem.n_joints
    x0 = np.r_[unit_from_lengths(L0, TAPERED.length_m, spec.problem.min_fraction), np.log(F0)]
    r = least_squares(J.residuals, x0, jac=J.jac, method="trf", x_scale="jac", max_nfev=20000,
                      bounds=joint_box(n),
                      ftol=1e-13, xtol=1e-13, gtol=1e-13)
    assert ours.success
    assert ours.loss_pct == pytest.approx(100 * J.loss(r.x), rel=1e-8)
    lengths, s = J.design(r.x)
    np.testing.assert_allclose(ours.lengths_m, lengths, atol=1e-5 * TAPERED.length_m)


def test_refining_the_best_finds_the_optimum_of_every_start_refined(target):
    """The default (explore 64 evaluations, refine the 3 best) against all 8 starts run to
    convergence: the same best loss."""
    kw = dict(objective="combined", stiffness="joint", starts=8, seed=1, progress=False)
    explored = pp.fit(TAPERED, target, 3, **kw)
    every = pp.fit(TAPERED, target, 3, refine_starts=0, max_nfev=3000, **kw)
    assert explored.success and every.success
    assert explored.combined_loss_pct == pytest.approx(every.combined_loss_pct, rel=1e-7)
    # the explored-only starts report where they stopped, never below the best
    assert np.all(explored.start_losses_pct >= explored.combined_loss_pct * (1 - 1e-12))


def test_explored_starts_are_marked_and_the_refined_ones_ran_on(target):
    spec = _spec(target)
    tasks = draw_starts(spec.problem, 6, 0)
    runs = run_explored(spec, tasks, explore_nfev=20, refine=2, progress=False)
    refined = [r for r in runs if not r.message.startswith("explored only")]
    assert len(runs) == 6 and len(refined) == 2
    assert [r.index for r in runs] == list(range(6))
    # the refined are the two best explored (an explored loss never rises when refined)
    explored = [explore_start(spec, *t, 20)[0].loss_pct for t in tasks]
    assert sorted(r.index for r in refined) == sorted(np.argsort(explored)[:2].tolist())
    assert all(r.nfev > 20 for r in refined)


def test_the_result_does_not_depend_on_the_workers(target):
    kw = dict(objective="combined", stiffness="joint", starts=6, seed=3, progress=False)
    one = pp.fit(TAPERED, target, 3, **kw)
    two = pp.fit(TAPERED, target, 3, workers=2, **kw)
    assert np.array_equal(one.lengths_m, two.lengths_m)
    assert np.array_equal(one.stiffness_Nm_per_rad, two.stiffness_Nm_per_rad)
    assert np.array_equal(one.start_losses_pct, two.start_losses_pct)
