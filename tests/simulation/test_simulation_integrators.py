"""The integrators as values under one loop: ``simulate(integrator=Gauss(...))`` and the older
``method="gauss"`` spelling build the same object and the same run; every field is validated by
name; the options record the same keys as before; the loop's cap and grid hold for every
scheme; the scipy solvers stepped one step at a time reproduce ``solve_ivp`` to the bit."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from scipy.integrate import solve_ivp

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError
from prbdm_pin.options.integrators import integrator_for
from prbdm_pin.options.simulation import SimulationOptions

BEAM = "examples/beams/uniform-narrow.json"


@pytest.fixture(scope="module")
def model():
    beam = pp.load_beam(BEAM)
    lengths = np.array([1, 2, 2, 1]) / 6.0
    return pp.build_model(beam, lengths, pp.finite_segment_stiffness(beam, lengths))


@pytest.mark.parametrize("spelling, integrator", [
    ({}, pp.Auto()),  # the default: the rule picks per problem; rtol is not its tolerance
    ({"method": "auto", "rtol": 1e-6}, pp.Auto()),
    ({"method": "exponential", "dt_s": 1e-3, "refresh_rad": 0.0, "rtol": 1e-6},
     pp.Exponential(dt_s=1e-3, refresh_rad=0.0)),
    ({"method": "gauss", "steps_per_period": 20, "rtol": 1e-6}, pp.Gauss(steps_per_period=20)),
    ({"method": "trapezoidal", "dt_s": 2e-4}, pp.Trapezoidal(dt_s=2e-4)),
    ({"method": "Radau", "rtol": 1e-7, "atol": 1e-10, "dt_s": 1e-3},
     pp.ScipyIVP("Radau", rtol=1e-7, atol=1e-10)),
])
def test_a_method_name_spells_the_integrator(spelling, integrator):
    """The fields an integrator does not have are ignored, as the options always did."""
    assert SimulationOptions(**spelling).integrator == integrator
    assert integrator_for(**{"method": "auto", **spelling}) == integrator


@pytest.mark.parametrize("spelling, integrator", [
    ({"method": "exponential"}, pp.Exponential()),
    ({"method": "gauss", "dt_s": 2e-3}, pp.Gauss(dt_s=2e-3)),
    ({"method": "trapezoidal"}, pp.Trapezoidal()),
    ({"method": "BDF", "rtol": 1e-6}, pp.ScipyIVP("BDF", rtol=1e-6)),
])
def test_both_spellings_give_the_same_run(model, spelling, integrator):
    kw = {"q0": np.full(3, 0.02), "damping_ratio": 0.02, "output_dt_s": 2e-3}
    old = pp.simulate(model, 0.02, **kw, **spelling)
    new = pp.simulate(model, 0.02, **kw, integrator=integrator)
    assert np.array_equal(old.q_rad, new.q_rad) and np.array_equal(old.v_rad_s, new.v_rad_s)
    assert old.steps == new.steps and old.rhs_evaluations == new.rhs_evaluations
    assert new.integrator == integrator and new.method == integrator.method


@pytest.mark.parametrize("make, field", [
    (lambda: pp.Exponential(dt_s=0.0), "dt_s = 0.0"),
    (lambda: pp.Exponential(steps_per_period=0.5), "steps_per_period = 0.5"),
    (lambda: pp.Exponential(refresh_rad=-1.0), "refresh_rad = -1.0"),
    (lambda: pp.Exponential(step_rtol=0.0), "step_rtol = 0.0"),
    (lambda: pp.Exponential(reject_factor=0.5), "reject_factor = 0.5"),
    (lambda: pp.Exponential(reject_factor=float("nan")), "reject_factor = nan"),
    (lambda: pp.Exponential(max_halvings=-1), "max_halvings = -1"),
    (lambda: pp.Exponential(max_halvings=1.5), "max_halvings = 1.5"),
    (lambda: pp.Exponential(divergence_tol=0.0), "divergence_tol = 0.0"),
    (lambda: pp.Exponential(min_step_ratio=2.0), "min_step_ratio = 2.0"),
    (lambda: pp.Gauss(dt_s=float("inf")), "dt_s = inf"),
    (lambda: pp.Gauss(max_halvings=True), "max_halvings = True"),
    (lambda: pp.Trapezoidal(steps_per_period=0.0), "steps_per_period = 0.0"),
    (lambda: pp.ScipyIVP("euler"), "method = 'euler'"),
    (lambda: pp.ScipyIVP(rtol=-1e-9), "rtol = -1e-09"),
    (lambda: pp.ScipyIVP(atol=0.0), "atol = 0.0"),
    (lambda: pp.Gauss().replace(rtol=1e-6), "rtol = 1e-06: not a field of Gauss"),
    (lambda: SimulationOptions(integrator="gauss"), "integrator = 'gauss'"),
    (lambda: SimulationOptions(method="DOP853", integrator=pp.Gauss()),
     "method = 'DOP853': differs from integrator"),
    (lambda: SimulationOptions(dt_s=1e-3, integrator=pp.Gauss(dt_s=2e-3)),
     "dt_s = 0.001: differs from integrator"),
])
def test_a_bad_integrator_field_is_named(make, field):
    with pytest.raises(BeamInputError, match=field):
        make()


def test_the_options_record_the_same_keys():
    """The record of a run spelled either way is the one written before integrators were
    objects; a step-control field set apart from its default is added."""
    keys = ["kind", "method", "dt_s", "output_dt_s", "rtol", "atol", "max_steps",
            "steps_per_period", "refresh_rad", "damping_ratio", "damping"]
    spelled = SimulationOptions(method="gauss", dt_s=1e-3)
    given = SimulationOptions(integrator=pp.Gauss(dt_s=1e-3))
    assert list(spelled.to_dict()) == keys and spelled.to_dict() == given.to_dict()
    assert given.method == "gauss" and given.dt_s == 1e-3
    tuned = SimulationOptions(integrator=pp.Exponential(max_halvings=2, step_rtol=1e-4))
    assert tuned.to_dict() == {**SimulationOptions(method="exponential").to_dict(),
                               "step_rtol": 1e-4,
                               "max_halvings": 2}


def test_replace_rebuilds_the_integrator_from_its_spelling():
    o = SimulationOptions(integrator=pp.Gauss(dt_s=1e-3, max_halvings=0))
    # a change of the step keeps the scheme's other fields; a change of scheme starts afresh
    assert o.replace(dt_s=2e-3).integrator == pp.Gauss(dt_s=2e-3, max_halvings=0)
    assert o.replace(output_dt_s=0.01).integrator == o.integrator
    ivp = o.replace(method="DOP853", rtol=1e-10)
    assert ivp.integrator == pp.ScipyIVP("DOP853", rtol=1e-10) and ivp.dt_s == 1e-3
    back = ivp.replace(integrator=pp.Trapezoidal())
    assert back.method == "trapezoidal" and back.dt_s is None and back.rtol == 1e-9
    with pytest.raises(BeamInputError, match="dt_s = -0.001"):
        o.replace(dt_s=-1e-3)


def test_every_scheme_ends_on_the_duration(model):
    """The trapezoidal rule's equal steps used to run past the end; the last is shortened."""
    for method in ("exponential", "gauss", "trapezoidal", "RK45"):
        tr = pp.simulate(model, 0.0123, q0=np.full(3, 0.02), method=method)
        assert tr.t_s[-1] == 0.0123 and np.all(np.diff(tr.t_s) > 0)


def test_the_step_cap_holds_for_every_scheme(model):
    """Adaptive steppers are stopped by the loop; fixed steps are refused before the run."""
    kinked = np.array([0.0, 0.0, 0.05])  # the step control shortens the nominal steps
    for method in ("exponential", "RK45"):
        with pytest.raises(BeamInputError, match=f"the {method} integrator took more than "
                                                 "max_steps = 3"):
            pp.simulate(model, 0.05, q0=kinked, method=method, dt_s=0.05 / 3, max_steps=3)
    with pytest.raises(BeamInputError, match="steps exceed max_steps = 3"):
        pp.simulate(model, 0.05, q0=np.full(3, 0.02), method="gauss", max_steps=3)


def test_progress_bar_runs(model, monkeypatch):
    import io
    import sys

    class Terminal(io.StringIO):  # the bar draws on a terminal only (io.progress)
        def isatty(self) -> bool:
            return True

    term = Terminal()
    monkeypatch.setattr(sys, "stderr", term)
    tr = pp.simulate(model, 0.01, q0=np.full(3, 0.02), progress=True)
    assert tr.t_s[-1] == 0.01 and "simulate" in term.getvalue()


@pytest.mark.parametrize("method", ["DOP853", "Radau"])
def test_the_scipy_stepper_is_solve_ivp(model, method):
    """Stepped through OdeSolver.step() under the shared loop, the solver takes solve_ivp's
    steps and samples its dense output as solve_ivp does: the same numbers."""
    q0 = np.array([0.03, -0.02, 0.01])
    pm, data, k = model.pin_model, model.pin_model.createData(), model.stiffness_Nm_per_rad

    def rhs(t, y):
        q, v = y[:3], y[3:]
        return np.concatenate((v, pin.aba(pm, data, q, v, -k * q)))

    def jac(t, y):
        q, v = y[:3], y[3:]
        dq, dv, Minv = pin.computeABADerivatives(pm, data, q, v, -k * q)
        Minv = np.triu(Minv) + np.triu(Minv, 1).T
        return np.vstack((np.hstack((np.zeros((3, 3)), np.eye(3))),
                          np.hstack((dq - Minv * k, dv))))

    kw = {"jac": jac} if method == "Radau" else {}
    y0 = np.concatenate((q0, np.zeros(3)))
    t_out = np.arange(11) * 2e-3
    ref = solve_ivp(rhs, (0.0, 0.02), y0, method=method, rtol=1e-8, atol=1e-8 * 0.03,
                    dense_output=True, **kw)
    steps = pp.simulate(model, 0.02, q0=q0, damping_ratio=0.0, method=method, rtol=1e-8)
    assert np.array_equal(steps.t_s, ref.t) and np.array_equal(steps.q_rad, ref.y[:3].T)
    dense = pp.simulate(model, 0.02, q0=q0, damping_ratio=0.0, method=method, rtol=1e-8,
                        output_dt_s=2e-3)
    assert np.array_equal(dense.q_rad, ref.sol(t_out)[:3].T)
    assert dense.rhs_evaluations == ref.nfev
