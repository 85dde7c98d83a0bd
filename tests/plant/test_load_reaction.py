"""The root reaction and the root strain under the loads of prbdm_pin.model.loads: what the
member passes on to its support at rest (the linear plant's static gain), against the loads'
resultants about the root computed by hand (uniform and partial-span distributed forces, a
follower moment, a base acceleration: the member's inertia -m a at its centre of mass)."""

import numpy as np
import pytest
from paths import ROOT
from tolerances import REFERENCE_ATOL, REFERENCE_RTOL

import prbdm_pin as pp
from prbdm_pin.files.beam_file import load_beam

BEAM = load_beam(ROOT / "examples/beams/uniform-narrow.json")  # L = 1 m, uniform
LENGTHS = np.array([0.15, 0.3, 0.3, 0.25])
SPRINGS = np.array([900.0, 700.0, 400.0])
INPUTS = ("base_accel_z", "distributed_force_z", "distributed_force_z[0]",
          "tip_moment_follower_y", "base_accel_x")
OUTPUTS = ("root_force_x", "root_force_z", "root_moment_y", "strain@0")


@pytest.mark.parametrize("hub", [None, pp.Hub(50.0, 0.0)])
def test_static_reaction_is_the_loads_resultant(hub):
    model = pp.build_model(BEAM, LENGTHS, SPRINGS, hub=hub)
    span = pp.DistributedLoad(0.3, 0.7)
    ins = INPUTS + (("hub_torque",) if hub else ())
    lin = pp.linearize(model, inputs=ins, outputs=OUTPUTS, loads=(span,), damping_ratio=0.05)
    L, m = BEAM.length_m, BEAM.mass_kg
    # at rest (a held hub: its torque balances the loads' moment about the axis, so the member
    # passes on to its support exactly what it carries)
    if hub is None:
        G = lin.D - lin.C @ np.linalg.solve(lin.A, lin.B)
    else:  # the hub is a free rigid body: hold it with its torque and read the flexible part
        G = _held_hub_gain(lin)
    # columns: base a_z: the member's inertia -m a at L/2: force -m, moment (L/2 e_x) x (-m e_z)
    # = +m L/2 about y; uniform q: force L, moment int x e_x x e_z = -L^2/2 about y; q over
    # [0.3, 0.7]: force 0.4, moment -(0.7^2 - 0.3^2)/2 = -0.2; a follower moment about the tip's
    # y: passed on whole; base a_x: force -m along x, no moment
    ref = np.array([[0.0, 0.0, 0.0, 0.0, -m],
                    [-m, L, 0.4, 0.0, 0.0],
                    [m * L / 2, -L**2 / 2, -0.2, 1.0, 0.0]])
    # a linear static solve of condition ~1e3 (springs over inertia scales): 1e-9 of the gains
    scale = np.abs(ref).max()
    np.testing.assert_allclose(G[:3, :5], ref, atol=1e-9 * scale)
    # the root strain reads the root moment: -M t / (2 E I) in microstrain
    EI = BEAM.material.E_Pa * BEAM.area_moment_at(0.0)
    np.testing.assert_allclose(G[3, :5], -ref[2] * BEAM.thickness_m / (2 * EI) * 1e6,
                               atol=1e-9 * scale * BEAM.thickness_m / EI * 1e6)


def _held_hub_gain(lin):
    """Static outputs with the hub held at angle 0 by its torque (the hub row of the statics
    is the torque's, so the flexible joints solve K_f dq_f = B_f u): at rest the acceleration
    path is idle, y = C_q dq + D_u u (the hub torque is internal to the support)."""
    K, Bq = lin.stiffness_Nm_per_rad, lin.input_map
    dq = np.zeros_like(Bq)
    dq[1:] = np.linalg.solve(K[1:, 1:], Bq[1:])
    return lin.output_map_position @ dq + lin.output_map_input


@pytest.mark.parametrize("name", ["base_accel_z", "distributed_force_z[0]",
                                  "tip_moment_follower_y"])
def test_simulated_reaction_follows_the_linear_plant_at_small_amplitude(name):
    """A small step of each load: simulate's recorded reaction and root strain (from the
    samples' accelerations and the loads' resultants) against the linear plant's exact step
    response (matrix exponential); the difference is second order in the amplitude."""
    from scipy.linalg import expm

    model = pp.build_model(BEAM, LENGTHS, SPRINGS)
    span = pp.DistributedLoad(0.3, 0.7)
    outs = ("root_force_z", "root_moment_y", "strain@0.4")
    lin = pp.linearize(model, inputs=(name,), outputs=outs, loads=(span,), damping_ratio=0.05)
    u = 1e-3
    t = np.linspace(0.0, 0.05, 26)
    # the run's integrator tolerances (not a comparison bound): its error stays far below the
    # O(u^2) difference the test bounds at 1e-5 of the peak
    run = pp.simulate(model, 0.05, inputs=(name,), u=np.array([u]), outputs=outs,
                      loads=(span,), output_dt_s=t[1], damping_ratio=0.05, method="DOP853",
                      rtol=10 * REFERENCE_RTOL, atol=REFERENCE_ATOL)
    n = lin.A.shape[0]
    aug = np.zeros((n + 1, n + 1))
    aug[:n, :n], aug[:n, n] = lin.A, lin.B[:, 0] * u
    x = np.array([expm(aug * ti)[:n, n] for ti in t])
    y = x @ lin.C.T + lin.D[:, 0] * u
    peak = np.abs(y).max(axis=0)
    # second order in the amplitude: the deflection ~1e-6 rad turns the lever arms by ~1e-6
    # of the reaction's scale; the integrator's rtol 1e-11 adds nothing visible
    assert np.all(np.abs(run.output_values - y) <= 1e-5 * peak)
    assert np.all(peak > 0.0)
