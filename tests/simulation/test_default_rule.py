"""The stated integrator rule (``simulation.default_rule``): the stiffness ratio it reads against
scipy's generalized eigensolver (the clamped chain) and the hub's closed-form rigid mode
elimination (``hub_frequencies``), and its choice in each of its three branches."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from kernel_models import hub, planar
from tolerances import EPS, REFERENCE_RTOL, eig_rtol

import prbdm_pin as pp
from prbdm_pin.model.hub import hub_frequencies
from prbdm_pin.simulation.default_rule import (
    STIFFNESS_RATIO_MAX,
    compiled_steps,
    default_integrator,
    stiffness_ratio,
)
from prbdm_pin.simulation.system import assemble_system, force_function, mass_matrix


def _system(m, tip_force=None, inputs=None, xi=0.0):
    n = m.pin_model.nv
    force, constant = force_function(tip_force)
    return assemble_system(m, np.zeros(n), damping_ratios=np.full(n, xi), damping="modal",
                           schedule=None, tip_force_N=force, constant_force=constant,
                           damping_pose=None, inputs=inputs)


@pytest.mark.parametrize("n", [1, 3, 5, 8])
def test_the_stiffness_ratio_is_the_pencils(narrow, n):
    m = planar(narrow, n)
    w2 = scipy.linalg.eigh(m.stiffness_matrix(), m.mass_matrix(), eigvals_only=True)
    ref = float(np.sqrt(w2[-1] / w2[0]))
    # two solves of one pencil, one ill-conditioned at an end of the spectrum
    assert abs(stiffness_ratio(_system(m), np.zeros(n)) - ref) <= eig_rtol(np.sqrt(w2)) * ref


def test_the_hubs_rigid_mode_is_left_out(narrow):
    m = hub(narrow, "y")
    sy = _system(m)
    # the beam's three springs; the hub's coordinate has none
    w = hub_frequencies(mass_matrix(sy.pin_model, sy.data, np.zeros(4)), m.stiffness_Nm_per_rad)
    ref = float(w[-1] / w[1])
    assert abs(stiffness_ratio(sy, np.zeros(4)) - ref) <= eig_rtol(w[1:]) * ref


def test_the_rule_picks_by_scene(narrow):
    small, large = planar(narrow, 3), planar(narrow, 8)
    z3, z8 = np.zeros(6), np.zeros(16)
    assert stiffness_ratio(_system(small), z3[:3]) <= STIFFNESS_RATIO_MAX
    assert stiffness_ratio(_system(large), z8[:8]) > STIFFNESS_RATIO_MAX
    step = [0.0, 0.0, -0.5]
    # from rest: by the stiffness ratio
    assert isinstance(default_integrator(_system(small, step), z3), pp.Compiled)
    assert isinstance(default_integrator(_system(large, step), z8), pp.Exponential)
    # a release: compiled whatever the ratio
    release = np.concatenate([np.full(8, 0.1), np.zeros(8)])
    assert isinstance(default_integrator(_system(large), release), pp.Compiled)
    # what the kernel cannot serve: the exponential integrator
    assert isinstance(default_integrator(_system(small, lambda t: step), z3), pp.Exponential)


def _stiff(m, xi, form, tip_force=None):
    n = m.pin_model.nv
    force, constant = force_function(tip_force)
    return assemble_system(m, np.zeros(n), damping_ratios=np.full(n, xi), damping=form,
                           schedule=None, tip_force_N=force, constant_force=constant,
                           damping_pose=np.zeros(n), inputs=None)


@pytest.mark.parametrize("n", [2, 5])
def test_undamped_compiled_steps_are_omega_max_t(narrow, n):
    """Undamped, the estimate is omega_max T (h omega_max = 1), omega_max from scipy's eigh."""
    m = planar(narrow, n)
    w = np.sqrt(scipy.linalg.eigh(m.stiffness_matrix(), m.mass_matrix(), eigvals_only=True))
    est = compiled_steps(_system(m), np.zeros(n), 0.5)
    # the first-order system's eigenvalues +-i omega against the pencil's: two solves of one
    # spectrum, each off by the spread's roundings
    assert abs(est - 0.5 * w[-1]) <= eig_rtol(w) * 0.5 * w[-1]


@pytest.mark.parametrize("form", ["none", "modal", "stiffness"])
def test_compiled_steps_estimate_what_the_compiled_run_takes(narrow, form):
    """The cost model against the compiled DOP853's own step control on a 3R step load, 1 s."""
    m = planar(narrow, 3)
    xi = 0.0 if form == "none" else 0.02
    damping = "modal" if form == "none" else form
    est = compiled_steps(_stiff(m, xi, damping), np.zeros(3), 1.0)
    run = pp.simulate(m, 1.0, tip_force=[0.0, 0.0, -0.5], damping_ratio=xi, damping=damping,
                      damping_pose=np.zeros(3), integrator=pp.Compiled(rtol=1e-6),
                      output_dt_s=1e-2)
    # the model's constants are fitted on the steps of 1R-8R runs (default_rule's docstring,
    # docs/benchmarks/bench_compiled.md): the estimate is within 23 % of the steps taken on
    # every measured case (here 1 %, 5 % and 23 %: the model's fit, not rounding)
    assert abs(est - run.steps) <= 0.25 * run.steps, (est, run.steps)


def test_damping_and_tolerance_move_the_pick(narrow):
    m8 = planar(narrow, 8)
    z = np.zeros(16)
    step = [0.0, 0.0, -0.5]
    release = np.concatenate([np.full(8, 0.1), np.zeros(8)])
    # from rest, 2 % modal: the compiled steps (1,703 measured) beat 25 omega_1 T (1,330)
    assert isinstance(default_integrator(_stiff(m8, 0.02, "modal", step), z), pp.Exponential)
    # an overdamped release (stiffness form): the exponential integrator follows it
    assert isinstance(default_integrator(_stiff(m8, 0.02, "stiffness"), release),
                      pp.Exponential)
    # a lightly damped release: compiled (the exponential one misses 0.01 %)
    assert default_integrator(_stiff(m8, 0.02, "modal"), release) == pp.Compiled(rtol=1e-6)
    # asked tighter than the exponential integrator's measured error: compiled at tol / 100
    for sy, y0, tol in ((_system(m8, step), z, 1e-7),
                        (_stiff(m8, 0.02, "stiffness"), release, 1e-5)):
        picked = default_integrator(sy, y0, auto=pp.Auto(tolerance=tol))
        assert isinstance(picked, pp.Compiled)
        # tol / 100: one rounding of the division
        assert abs(picked.rtol - tol * 1e-2) <= 2 * EPS * tol * 1e-2
    # a spinning hub the kernel cannot serve: scipy's DOP853, not the exponential integrator
    sy = _system(hub(narrow, "y"), lambda t: np.zeros(3))
    spin = np.concatenate([np.zeros(4), [5.0, 0.0, 0.0, 0.0]])
    assert default_integrator(sy, spin, spinning=True) == pp.ScipyIVP("DOP853", rtol=1e-6)


@pytest.mark.parametrize(("n", "form", "picked"), [(5, "stiffness", "compiled"),
                                                   (8, "stiffness", "exponential"),
                                                   (3, "modal", "compiled")])
def test_the_default_reaches_its_tolerance(narrow, n, form, picked):
    """simulate's default (Auto) on releases within 0.01 % of the peak of scipy's DOP853."""
    m = planar(narrow, n)
    kw = {"q0": np.full(n, 0.1), "damping_ratio": 0.02, "damping": form,
          "damping_pose": np.zeros(n), "output_dt_s": 1e-3}
    run = pp.simulate(m, 0.1, **kw)
    assert run.method == picked and run.integrator == pp.simulate(
        m, 0.1, integrator=run.integrator, **kw).integrator
    assert not isinstance(run.integrator, pp.Auto)
    ref = pp.simulate(m, 0.1, integrator=pp.ScipyIVP("DOP853", rtol=REFERENCE_RTOL * 10), **kw)
    peak = np.abs(ref.tip_position_m - ref.tip_position_m[0]).max()
    # Auto's tolerance, 1e-4 of the peak (the 0.01 %)
    assert np.abs(run.tip_position_m - ref.tip_position_m).max() <= 1e-4 * peak


def test_the_options_default_is_auto():
    assert pp.SimulationOptions().method == "auto"
    assert pp.SimulationOptions().integrator == pp.Auto()
    assert pp.SimulationOptions(method="auto").replace(method="exponential").integrator == \
        pp.Exponential()


def test_a_batch_under_the_default_records_the_pick(narrow):
    """Designs looped through simulate under Auto: each resolves the rule; the batch records
    the integrator they ran, and design b is simulate's run of it with that integrator."""
    m = planar(narrow, 2)
    models = [m, m.with_stiffness(1.5 * m.stiffness_Nm_per_rad)]
    runs = pp.simulate_batch(models, 0.05, q0=np.full(2, 0.01),
                             options=pp.SimulationOptions(output_dt_s=1e-3))
    assert runs.method == "compiled" and isinstance(runs.integrator, pp.Compiled)
    for b, model in enumerate(models):
        one = pp.simulate(model, 0.05, q0=np.full(2, 0.01), output_dt_s=1e-3,
                          integrator=runs.integrator)
        # the same run twice: exact
        np.testing.assert_array_equal(runs.q_rad[b], one.q_rad)


def test_an_exponential_pick_takes_the_spelled_step(narrow):
    """Under Auto, dt_s / steps_per_period / refresh_rad spelled beside it reach the
    exponential integrator the rule picks (a time-varying force), as with the old default."""
    m = planar(narrow, 2)

    def force(t):
        return np.array([0.0, 0.0, -0.5 * np.sin(60.0 * t)])

    kw = {"tip_force": force, "output_dt_s": 1e-3, "steps_per_period": 20.0,
          "refresh_rad": 0.0}
    run = pp.simulate(m, 0.05, **kw)
    assert run.integrator == pp.Exponential(steps_per_period=20.0, refresh_rad=0.0)
    named = pp.simulate(m, 0.05, method="exponential", **kw)
    # the same integrator and step: the same run, exactly
    np.testing.assert_array_equal(run.q_rad, named.q_rad)
    assert run.steps == named.steps


@pytest.mark.parametrize(("force_N", "picked"), [(-2500.0, "compiled"), (-2.5, "exponential")])
def test_an_undamped_step_load_is_judged_by_its_static_angle(force_N, picked):
    """From rest, undamped, on the stiff 5R (omega_max / omega_1 > 25): a small load stays with
    the exponential integrator, a large one (0.098 rad of static joint angle, past
    LINEAR_ANGLE_RAD, where the exponential integrator's own step control left 0.19 % of the
    peak) goes to the compiled scheme; both within Auto's 1e-4 of the peak of DOP853."""
    from prbdm_pin.bench.run import finite_segment_chain

    m = finite_segment_chain(pp.load_beam("examples/beams/reference-random.json"), 5)
    kw = {"tip_force": [0.0, 0.0, force_N], "damping_ratio": 0.0, "output_dt_s": 1e-3}
    run = pp.simulate(m, 0.2, **kw)
    assert run.method == picked
    ref = pp.simulate(m, 0.2, integrator=pp.ScipyIVP("DOP853", rtol=REFERENCE_RTOL * 10), **kw)
    peak = np.abs(ref.tip_position_m - ref.tip_position_m[0]).max()
    # Auto's tolerance, 1e-4 of the peak (the 0.01 %)
    assert np.abs(run.tip_position_m - ref.tip_position_m).max() <= 1e-4 * peak
