"""The truth plant's tip moment and line load (plant.truth_loads): the all-mode clamped truth's
static gains against the Euler-Bernoulli cantilever's closed forms, and a fine PRBDM chain on a
hub and on a bus against the truth on the same support (rigid-body gains, the line load as the
clamp's acceleration)."""

import numpy as np
import pytest
from tolerances import EPS, hermite_basis_cond

import prbdm_pin as pp
from prbdm_pin.plant.truth_loads import with_truth_loads
from prbdm_pin.truth.beam import beam_stations
from prbdm_pin.truth.plant import clamped_model


@pytest.fixture(scope="module")
def all_modes(narrow, truth_of):
    return truth_of(narrow, model="beam", modes=400, static=False, error_tol_pct=None)


def test_all_mode_static_gains_are_the_cantilever_s(narrow, all_modes):
    L, EI = narrow.length_m, narrow.root_EI_Nm2
    plant = with_truth_loads(clamped_model(all_modes, narrow, [(0.0, L)]), narrow,
                             ("tip_moment_y", "distributed_force_z"), "strain[0]")
    assert plant.input_names == ("tip_force_z", "base_accel_z", "tip_moment_y",
                                 "distributed_force_z")
    G = -plant.C[0] @ np.linalg.solve(plant.A, plant.B)
    # a moment about +y at the tip turns it down: w(L) = -M L^2 / (2 EI); a line load q up:
    # q L^4 / (8 EI); rtol as the clamped plant's static test (the Hermite basis' condition)
    c = hermite_basis_cond(beam_stations(narrow))
    np.testing.assert_allclose(G[2:], [-L**2 / (2 * EI), L**4 / (8 * EI)], rtol=2 * EPS * c)


@pytest.fixture(scope="module")
def fine(narrow):
    L, n = narrow.length_m, 20
    lengths = np.r_[0.5, np.ones(n - 1), 0.5] * L / n
    return lengths, pp.finite_segment_stiffness(narrow, lengths)


@pytest.mark.parametrize("support", ["hub", "bus"])
def test_a_fine_chain_on_a_support_against_the_truth_s_loads(narrow, fine, truth_of, tmp_path,
                                                              support):
    lengths, k = fine
    if support == "hub":
        model = pp.build_model(narrow, lengths, k, hub=pp.Hub(20.0, 0.05))
        ins = ["tip_moment_y", "distributed_force_z", "base_accel_z", "hub_torque"]
        out = "hub_angle"
    else:
        model = pp.build_model(narrow, lengths, k,
                               support=pp.FreeBus(2.0, [0.08, 0.08, 0.08], root_m=(0.1, 0, 0)))
        ins = ["tip_moment_y", "distributed_force_z"]
        out = "bus_attitude_y"
    lin = pp.linearize(model, inputs=ins, outputs=["tip_z", out], damping_ratio=0.02)
    request = pp.TruthRequest(model="beam", modes=24)
    cmp = pp.compare_truth_plant(lin, model, request, (), 0.02,
                                 cache_dir=tmp_path).comparison
    # the rigid turn under each load: the same total inertia and the same moment of the load
    # about the axis on both sides (the links' own inertia through the thickness, 1e-4 of the
    # strip's, is the chain's alone: measured 9e-4 % and 3.7e-3 %)
    for name in ins:
        assert abs(cmp.pair(name, out).rigid_gain_error_pct) <= 0.01
    # the 20-link chain's discretisation: the flexible FRFs within a few % (measured 1-5 %)
    for name in ins:
        assert cmp.pair(name, "tip_z").frf_error_pct <= 6.0
    if support == "hub":  # on a uniform strip the line load is the clamp's acceleration
        a, b = cmp.pair("distributed_force_z", "tip_z"), cmp.pair("base_accel_z", "tip_z")
        assert a.frf_error_pct == pytest.approx(b.frf_error_pct, rel=1e-6)


def test_a_tapered_member_has_no_line_load_on_the_truth_side(tapered, truth_of):
    truth = truth_of(tapered, model="beam", modes=4, static=False, error_tol_pct=None)
    plant = with_truth_loads(clamped_model(truth, tapered), tapered,
                             ("distributed_force_z",), None)
    # the width varies: int phi dx is not the modes' translation over a constant, so no column
    assert plant.input_names == ("tip_force_z", "base_accel_z")
