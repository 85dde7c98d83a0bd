"""The "compiled" integrator (scipy's DOP853 run inside the numba chain kernel) against scipy's
own DOP853 on Pinocchio's dynamics (``ScipyIVP("DOP853")``): a tight reference (rtol 1e-11)
for the accuracy of step loads and releases of 1R-8R chains, damped and undamped, on a hub, a
spatial chain and a free bus; the same controller's step counts at equal tolerances; the
energy of an undamped release; and the scenes it refuses by name."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from kernel_models import bus, hub, planar, spatial

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError
from prbdm_pin.simulation import StiffnessSchedule, mechanical_energy
from prbdm_pin.simulation.base_motion import BaseMotion

REF_RTOL = 1e-11  # the reference DOP853's tolerance (the brief's reference setting)
RTOL = 1e-8  # the compiled run's
DURATION_S = 0.1  # 5.5 periods of the 1R's mode 1, 1-2 of the 8R's
# DOP853 keeps each step's local error under rtol; an oscillation's phase error then adds up
# over its periods, so the global error grows with the number of periods of the fastest mode
# the motion carries (omega_max T / 2 pi; 110 on the xy chain's twist, where scipy's own
# DOP853 is 300-600 rtol off its rtol-1e-12 run over 0.2 s). GROWTH allows the constant of
# that growth, and both runs' errors add.
GROWTH = 10.0


def _periods(m) -> float:
    """Periods of the fastest linear mode at the straight pose over the run, at least 1."""
    w2 = scipy.linalg.eigh(m.stiffness_matrix(), m.mass_matrix(), eigvals_only=True)
    return max(1.0, float(np.sqrt(w2.max())) * DURATION_S / (2 * np.pi))


def _case(beam, name):
    kind, load = name.split()
    if kind.endswith("R"):
        m = planar(beam, int(kind[:-1]))
    elif kind.startswith("hub"):
        m = hub(beam, kind[-1])
    elif kind == "bus":
        m = bus(beam)
    else:
        m = spatial(beam, kind)
    n, flex = m.pin_model.nv, np.array(m.stiffness_matrix().diagonal() > 0.0)
    if load == "step":
        return m, {"tip_force": [0.0, 0.3 if kind in ("xyz", "xy") else 0.0, -0.5]}
    if load == "spin":  # released bent on a spinning hub: centrifugal and Coriolis terms
        q0 = np.zeros(n)
        q0[1:] = 0.05
        return m, {"spin_rad_s": 20.0, "q0": q0}
    q0 = np.zeros(n)
    q0[-flex.sum():] = 0.1  # 0.1 rad on every sprung joint
    kw = {"q0": q0}
    if kind == "hub-z":
        kw["gravity_m_s2"] = [0.0, 0.0, -9.81]  # the weight bends the flapping beam
    return m, kw


CASES = [f"{n}R {load}" for n in (1, 3, 5, 8) for load in ("step", "release")] + [
    "hub-y release", "hub-z release", "hub-z spin", "xyz step", "xy release", "bus release"]


@pytest.mark.parametrize("zeta", [0.0, 0.02])
@pytest.mark.parametrize("name", CASES)
def test_compiled_follows_scipys_dop853_within_the_tolerances(narrow, name, zeta):
    m, kw = _case(narrow, name)
    common = {"damping_ratio": zeta, "output_dt_s": 1e-3, **kw}
    ref = pp.simulate(m, DURATION_S, integrator=pp.ScipyIVP("DOP853", rtol=REF_RTOL), **common)
    run = pp.simulate(m, DURATION_S, integrator=pp.Compiled(rtol=RTOL), **common)
    assert run.method == "compiled" and np.array_equal(run.t_s, ref.t_s)
    bound = GROWTH * _periods(m) * (RTOL + REF_RTOL)
    peak = np.abs(ref.q_rad).max()
    assert np.abs(run.q_rad - ref.q_rad).max() <= bound * peak
    tip = np.abs(ref.tip_displacement_m).max()
    assert np.abs(run.tip_displacement_m - ref.tip_displacement_m).max() <= bound * tip


@pytest.mark.parametrize("name", ["1R release", "5R step", "8R release", "hub-y release",
                                  "xyz step", "bus release"])
@pytest.mark.parametrize("zeta", [0.0, 0.02])
def test_the_step_count_is_scipys_at_equal_tolerances(narrow, name, zeta):
    """The same controller takes the same steps; an error norm within a rounding of 1 can flip
    one accept/reject decision (the two evaluate the dynamics in another order) and the paths
    then part by a few steps: 1e-2 of the count, and 3 steps."""
    m, kw = _case(narrow, name)
    common = {"damping_ratio": zeta, "output_dt_s": 1e-3, **kw}
    ref = pp.simulate(m, DURATION_S, integrator=pp.ScipyIVP("DOP853", rtol=1e-7), **common)
    run = pp.simulate(m, DURATION_S, integrator=pp.Compiled(rtol=1e-7), **common)
    assert abs(run.steps - ref.steps) <= 1e-2 * ref.steps + 3
    # 12 evaluations per trial step, 2 to start, 3 per sampled step's interpolant: never more
    # than scipy's, which builds every step's interpolant
    assert run.rhs_evaluations <= ref.rhs_evaluations + 12 * abs(run.steps - ref.steps) + 36


def test_an_undamped_release_keeps_its_energy(narrow):
    """The energy's drift against scipy's DOP853 on Pinocchio at the same tolerance (the same
    controller: a wrong Coriolis or gravity term in the kernel would drift where it does not),
    and in absolute terms within the tolerance over the run's steps."""
    m = planar(narrow, 3)
    rtol, q0 = 1e-10, np.full(3, 0.1)
    kw = {"q0": q0, "damping_ratio": 0.0, "output_dt_s": 1e-3}
    runs = [pp.simulate(m, 0.5, integrator=integ, **kw)
            for integ in (pp.Compiled(rtol=rtol), pp.ScipyIVP("DOP853", rtol=rtol))]
    drift = []
    for run in runs:
        E = mechanical_energy(m, run.q_rad, run.v_rad_s)
        drift.append(np.abs(E / E[0] - 1.0).max())
    # the two runs' roundings steer a few steps apart: their drifts agree within a factor 2
    assert drift[0] <= 2 * drift[1]
    # each step's local error is under rtol of the state, and energy is quadratic in it
    assert drift[0] <= 2 * rtol * runs[0].steps


def test_every_step_is_sampled_without_output_dt(narrow):
    m = planar(narrow, 3)
    run = pp.simulate(m, 0.05, q0=np.full(3, 0.1), integrator=pp.Compiled(rtol=1e-8))
    assert run.t_s.size == run.steps + 1 and run.t_s[0] == 0.0 and run.t_s[-1] == 0.05
    assert np.all(np.diff(run.t_s) > 0.0) and np.array_equal(run.q_rad[0], np.full(3, 0.1))
    # the samples are the sampled run's at the same step ends: the dense output at a step's
    # end is the step's own state (up to the interpolant's rounding, 10 EPS of the angles)
    dense = pp.simulate(m, 0.05, q0=np.full(3, 0.1), integrator=pp.Compiled(rtol=1e-8),
                        output_dt_s=0.01)
    assert dense.steps == run.steps
    assert abs(dense.q_rad[-1] - run.q_rad[-1]).max() <= 10 * np.finfo(float).eps * 0.1


def test_the_method_name_spells_the_integrator(narrow):
    m = planar(narrow, 2)
    a = pp.simulate(m, 0.02, q0=[0.01, 0.0], method="compiled", rtol=1e-7)
    assert a.integrator == pp.Compiled(rtol=1e-7) and a.method == "compiled"


def test_what_it_cannot_serve_is_refused_by_name(narrow):
    m = planar(narrow, 2)
    method = {"integrator": pp.Compiled()}
    with pytest.raises(BeamInputError, match="tip_force"):
        pp.simulate(m, 0.01, tip_force=lambda t: [0.0, 0.0, -t], **method)
    sched = StiffnessSchedule(np.array([0.0, 1.0]),
                              np.vstack([m.stiffness_Nm_per_rad, m.stiffness_Nm_per_rad]))
    with pytest.raises(BeamInputError, match="stiffness_schedule"):
        pp.simulate(m, 0.01, stiffness_schedule=sched, **method)
    with pytest.raises(BeamInputError, match="inputs"):
        pp.simulate(m, 0.01, inputs=["tip_force_z"], u=[1.0], **method)
    z = np.zeros(6)
    with pytest.raises(BeamInputError, match="base_motion"):
        pp.simulate(m, 0.01, base_motion=BaseMotion(lambda t: z, lambda t: z, lambda t: z),
                    **method)


@pytest.mark.parametrize("rtol", [1e-15, 0.5, 1e-14, 0.1, float("nan"), -1e-6])
def test_a_tolerance_outside_the_range_is_refused(rtol):
    with pytest.raises(BeamInputError, match="rtol"):
        pp.Compiled(rtol=rtol)
    with pytest.raises(BeamInputError, match="atol"):
        pp.Compiled(atol=-1.0)
