"""Statics of the spatial chain under a dead tip force and moment.

Against the isotropic rod's helix under an end moment (closed form), the explicit equilibrium of
a pure moment (forward substitution), the planar solver, the linear solution and finite
differences of the residual.
"""

import numpy as np
import pinocchio as pin
import pytest
from tolerances import EPS

from prbdm_pin.chain.spatial_statics import spatial_static_deflection
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.chain.spatial_tangent import residual_and_tangent
from prbdm_pin.chain.statics import static_deflection_planar
from prbdm_pin.errors import BeamInputError
from prbdm_pin.member.geometry import Beam
from prbdm_pin.member.section import torsion_constant_m4
from prbdm_pin.model.prbdm_model import build_model

L, T_M = 1.0, 0.01
# a square section: E I_y = E I_z, the isotropic rod
SQUARE = Beam(np.array([0.0, L]), np.array([T_M / 2, T_M / 2]), T_M, name="square-rod")
EI = SQUARE.material.E_Pa * T_M**4 / 12.0
GJ = SQUARE.material.G_Pa * float(torsion_constant_m4(T_M, T_M))
RTOL = 1e-10  # the solvers' convergence test: ||K q - J^T w|| <= RTOL max(||K q||, ||J^T w||)
E_X = np.array([1.0, 0.0, 0.0])


def chain(n, axes="xyz"):
    """n equal segments with half segments at the ends, finite-segment springs of every axis."""
    h = L / n
    lengths = np.concatenate([[h / 2], np.full(n - 1, h), [h / 2]])
    k = spatial_stiffness(SQUARE, lengths, axes, min_fraction=0.0)
    return build_model(SQUARE, lengths, k, min_fraction=0.0, axes=axes)


def wrench_residual(model, q, w):
    """||K q - J^T w|| / ||J^T w|| with Pinocchio's frame Jacobian."""
    d = model.new_data()
    J = pin.computeFrameJacobian(model.pin_model, d, q, model.tip_frame_id,
                                 pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
    jw = J.T @ w
    return np.linalg.norm(model.stiffness_Nm_per_rad * q - jw) / np.linalg.norm(jw)


def solve_bound(model, q, w):
    """What two solutions that both pass the convergence test may differ by, rad (2-norm).

    ||dq|| <= ||T^-1|| ||dr|| with ||dr|| <= 2 RTOL scale and scale <= ||K q|| (1 + RTOL).
    """
    _, T = residual_and_tangent(model.pin_model, model.new_data(), model.stiffness_Nm_per_rad,
                                model.tip_frame_id, q, w)
    scale = np.linalg.norm(model.stiffness_Nm_per_rad * q)
    return 2.0 * RTOL * scale / np.linalg.svd(T, compute_uv=False)[-1] * (1.0 + 1e-6)


def helix_end(M):
    """End position (m) and rotation of the isotropic Kirchhoff rod clamped along e_x.

    Under a dead end moment M the internal moment is M everywhere, so the tangent precesses
    about M: t' = (M / EI) x t, at the rate kappa = |M| / EI; the material frame turns about M
    at kappa and about t at c = (M . t) (1 / GJ - 1 / EI) (twist less the bending's share), so
    R(s) = Rot(M / |M|, kappa s) Rot(e_x, c s). With t0 = cos(theta) m + sin(theta) u (m the
    moment's direction, u a unit vector normal to it), p(L) = integral of t: a helix about m of
    radius sin(theta) / kappa and pitch 2 pi cos(theta) / kappa.
    """
    mu = np.linalg.norm(M)
    m, kappa = M / mu, mu / EI
    cos_th = float(m @ E_X)
    u = E_X - cos_th * m
    sin_th = np.linalg.norm(u)
    u /= sin_th
    p = cos_th * m * L + sin_th / kappa * (np.sin(kappa * L) * u
                                           + (1.0 - np.cos(kappa * L)) * np.cross(m, u))
    c = mu * cos_th * (1.0 / GJ - 1.0 / EI)
    return p, pin.exp3(m * kappa * L) @ pin.exp3(E_X * c * L)


def forward_substitution(model, M):
    """The pure-moment equilibrium, explicit: k_i q_i = a_i . M, axis a_i set by q_1 ... q_i-1."""
    d = model.new_data()
    q = np.zeros(model.n_springs)
    col = {"x": 0, "y": 1, "z": 2}
    for i, a in enumerate(model.spring_axes):
        pin.forwardKinematics(model.pin_model, d, q)
        q[i] = d.oMi[i + 1].rotation[:, col[a]] @ M / model.stiffness_Nm_per_rad[i]
    return q


def tip_errors(M, ns):
    p_ex, R_ex = helix_end(M)
    out = []
    for n in ns:
        model = chain(n)
        q, p = model.static_deflection(np.zeros(3), tip_moment_Nm=M)
        # a different algorithm for the same equilibrium: the solver's own convergence bound
        q_fs = forward_substitution(model, M)
        assert np.linalg.norm(q - q_fs) <= solve_bound(model, q, np.r_[np.zeros(3), M])
        p2, R = model.tip_pose(q)
        np.testing.assert_array_equal(p, p2)
        out.append((np.linalg.norm(p - p_ex) / L, np.linalg.norm(pin.log3(R_ex.T @ R)), p))
    return out


def test_helix_under_a_bending_and_twisting_end_moment():
    # 50 deg from the rod, 2.5 EI / L: the tangent turns 2.5 rad (143 deg) about M
    a = np.radians(50.0)
    M = 2.5 * EI / L * np.array([np.cos(a), np.sin(a), 0.0])
    (e8, _, _), (e16, r16, p16), (e32, r32, p32), (_, _, p64) = tip_errors(M, (8, 16, 32, 64))
    # first order, observed ratios 1.99, 2.01 (position), 2.08, 2.03 (rotation): a y, z, x node
    # turns by Ry(q_y) Rz(q_z) Rx(q_x), whose second-order term (a twist q_y q_z / 2 the
    # springs do not see) accumulates over n nodes to O(1/n); the bounds allow 10 % about 2
    for ratio in (e8 / e16, e16 / e32, r16 / r32):
        assert 1.8 <= ratio <= 2.2
    # n e_n -> 0.62 (position / L) and 1.38 rad (rotation) observed; 10 % above them
    assert e32 <= 0.68 / 32 and r32 <= 1.52 / 32
    # the limit is the helix: Richardson's 2 p_2n - p_n leaves the O(1/n^2) remainder,
    # observed 3.2e-3 L (n = 16, 32), 8.2e-4 L (32, 64), ratio 3.97: second order, 10 % about
    # 4, and 10 % above the last
    p_ex = helix_end(M)[0]
    e_r = np.linalg.norm(2 * p64 - p32 - p_ex)
    assert 3.6 <= np.linalg.norm(2 * p32 - p16 - p_ex) / e_r <= 4.4
    assert e_r <= 9e-4 * L


def test_bending_moment_normal_to_the_rod_converges_at_second_order():
    # M normal to e_x: no twist, an arc of radius EI / |M| in the plane normal to M; the
    # centreline's error is second order (observed ratios 3.97, 3.99; 10 % about 4)
    M = 2.5 * EI / L * np.array([0.0, 1.0, 1.0]) / np.sqrt(2.0)
    (e8, *_), (e16, *_), (e32, *_) = tip_errors(M, (8, 16, 32))
    for ratio in (e8 / e16, e16 / e32):
        assert 3.6 <= ratio <= 4.4
    assert e32 <= 1.1 * 0.99 / 32**2  # n^2 e_n -> 0.99 observed, 10 % above


@pytest.mark.parametrize("F", [[3.0, 0.0, -5.0], [-2.0, 0.0, -8.0], [-10.0, 0.0, 0.3],
                               [0.0, 0.0, -40.0]])
def test_force_in_the_plane_equals_the_planar_chain(F):
    F = np.array(F) * EI / L**2  # P L^2 / EI up to 40; -10 along x: 4 times the buckling load
    n = 16
    spatial, planar = chain(n), chain(n, "y")
    q, p = spatial.static_deflection(F)
    qp, pp = planar.static_deflection(F)
    # the planar path is the planar solver itself, unchanged
    np.testing.assert_array_equal(qp, static_deflection_planar(planar.lengths_m,
                                                               planar.stiffness_Nm_per_rad, F))
    w = np.r_[F, np.zeros(3)]
    q3 = q.reshape(n, 3)
    embedded = np.zeros((n, 3))
    embedded[:, 0] = qp
    # both pass the convergence test: they differ by at most the solve bound
    assert np.linalg.norm(q - embedded.ravel()) <= solve_bound(spatial, q, w)
    # z and x stay a structural zero up to the rounding of the Newton steps
    assert np.max(np.abs(q3[:, 1:])) <= EPS * np.linalg.cond(
        residual_and_tangent(spatial.pin_model, spatial.new_data(),
                             spatial.stiffness_Nm_per_rad, spatial.tip_frame_id, q, w)[1]
    ) * np.linalg.norm(qp)
    # the tip: the positions of two poses within the solve bound, lever arm at most L
    # (plus the rounding of the tip position itself, a few EPS L)
    assert np.linalg.norm(p - pp) <= L * solve_bound(spatial, q, w) + 4 * EPS * L
    # the general solver on the planar chain: the same equilibrium
    qg = spatial_static_deflection(planar.pin_model, planar.new_data(),
                                   planar.stiffness_Nm_per_rad, planar.tip_frame_id, F)
    assert np.linalg.norm(qg - qp) <= solve_bound(planar, qp, w)


def test_planar_chain_under_an_end_moment():
    # the planar chain's axes stay e_y: k_i q_i = M_y exactly, the x and z parts do nothing
    model = chain(8, "y")
    M = np.array([3.0, 2.0 * EI / L, -5.0])
    q, p = model.static_deflection(np.zeros(3), tip_moment_Nm=M)
    np.testing.assert_allclose(q, M[1] / model.stiffness_Nm_per_rad,
                               rtol=solve_bound(model, q, np.r_[np.zeros(3), M])
                               / np.linalg.norm(q))


@pytest.mark.parametrize("axes", ["xy", "yz", "xyz"])
def test_small_loads_follow_the_linear_solution(axes):
    model = chain(8, axes)
    w = np.array([0.3, -0.5, -1.0, 0.2 * L, -0.4 * L, 0.3 * L]) * EI / L**2
    J0 = pin.computeFrameJacobian(model.pin_model, model.new_data(), np.zeros(model.n_springs),
                                  model.tip_frame_id, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
    errs = []
    for s in (1e-4, 1e-3):
        q, _ = model.static_deflection(s * w[:3], tip_moment_Nm=s * w[3:])
        q_lin = s * (J0.T @ w) / model.stiffness_Nm_per_rad
        errs.append(np.linalg.norm(q - q_lin) / np.linalg.norm(q_lin))
    # the relative error is O(load): a tenfold load, a tenfold error (observed ratios 9.9993 to
    # 10.0001; 20 % allowed for the next order); 1.1e-5 to 2.2e-5 observed at the small load,
    # bounded at 2.5 times that
    assert 8.0 <= errs[1] / errs[0] <= 12.0
    assert errs[0] <= 5e-5


def test_tangent_stiffness_against_central_differences():
    model = chain(6)
    d = model.new_data()
    rng = np.random.default_rng(7)
    q = rng.normal(0.0, 0.3, model.n_springs)
    w = np.array([3.0, -2.0, 5.0, 1.0 * L, -2.0 * L, 0.5 * L]) * EI / L**2

    def res(x):
        return residual_and_tangent(model.pin_model, d, model.stiffness_Nm_per_rad,
                                    model.tip_frame_id, x, w)

    T = res(q)[1]
    assert not np.allclose(T, T.T)  # a dead moment: not symmetric
    errs = []
    for h in (1e-3, 1e-4):
        Tf = np.column_stack([(res(q + h * e)[0] - res(q - h * e)[0]) / (2 * h)
                              for e in np.eye(q.size)])
        errs.append(np.linalg.norm(Tf - T) / np.linalg.norm(T))
    # central differences err by h^2 / 6 r''': ratio 100 between the steps (observed 100.0;
    # 10 % allowed), 9.8e-8 observed at h = 1e-3
    assert 90.0 <= errs[0] / errs[1] <= 110.0
    assert errs[0] <= 1e-6


def test_combined_force_and_moment_reach_an_equilibrium():
    model = chain(16)
    F = np.array([3.0, -4.0, -6.0]) * EI / L**2
    M = np.array([1.0, 2.0, -3.0]) * EI / L
    q, p = model.static_deflection(F, tip_moment_Nm=M)
    # the convergence test of the solver, against Pinocchio's Jacobian
    assert wrench_residual(model, q, np.r_[F, M]) <= RTOL
    np.testing.assert_array_equal(p, model.tip_position(q))


def test_large_moment_by_load_stepping():
    # 10 EI / L: the tangent winds 1.6 turns about M
    model = chain(32)
    M = 10.0 * EI / L * np.array([np.cos(0.87), np.sin(0.87), 0.0])
    q, _ = model.static_deflection(np.zeros(3), tip_moment_Nm=M)
    assert np.linalg.norm(q - forward_substitution(model, M)) <= solve_bound(
        model, q, np.r_[np.zeros(3), M])


def test_column_past_buckling_leaves_the_straight_pose():
    # 4 times the buckling load along the rod: the straight pose is a saddle of V
    model = chain(16)
    F = np.array([-10.0 * EI / L**2, 0.0, 0.0])
    q, p = model.static_deflection(F)
    assert wrench_residual(model, q, np.r_[F, np.zeros(3)]) <= RTOL
    _, T = residual_and_tangent(model.pin_model, model.new_data(), model.stiffness_Nm_per_rad,
                                model.tip_frame_id, q, np.r_[F, np.zeros(3)])
    assert np.linalg.eigvalsh(T).min() > 0.0  # a minimum
    # the isotropic column buckles in any plane through x; the chain leaves along one of its
    # joints' planes (y or z bending, equal springs), where it is the planar chain: its tip
    # (-0.34 L, 0, -0.62 L, behind the clamp) within the solve bound times the lever L
    pp = chain(16, "y").static_deflection(F)[1]
    tol = L * solve_bound(model, q, np.r_[F, np.zeros(3)]) + 4 * EPS * L  # + the tip's rounding
    assert abs(p[0] - pp[0]) <= tol
    assert abs(np.hypot(p[1], p[2]) - abs(pp[2])) <= tol


@pytest.mark.parametrize("bad", [[1.0, 2.0], [0.0, np.nan, 0.0], [np.inf, 0.0, 0.0], "abc",
                                 [[1.0, 2.0, 3.0]]])
@pytest.mark.parametrize("axes", ["y", "xyz"])
def test_bad_tip_moment_is_named(bad, axes):
    model = chain(4, axes)
    with pytest.raises(BeamInputError, match="tip_moment"):
        model.static_deflection(np.zeros(3), tip_moment_Nm=bad)
    with pytest.raises(BeamInputError, match="tip_moment"):
        spatial_static_deflection(model.pin_model, model.new_data(), model.stiffness_Nm_per_rad,
                                  model.tip_frame_id, np.zeros(3), bad)


def test_bad_tip_force_is_named_on_the_spatial_chain():
    model = chain(4)
    with pytest.raises(BeamInputError, match="tip_force"):
        model.static_deflection(np.array([0.0, np.nan, 1.0]))
