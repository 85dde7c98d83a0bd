"""The common plant's compiled short path (prbdm_pin.plant.plant_layout, .plant_kernel).

Compared with the general path (Pinocchio's CRBA and Jacobians, LAPACK's eigensolver and
Cholesky solve, step by step; reached by switching the short path off) and, on one joint,
with the closed form of a damped oscillator.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.chain.eigen import COND_LIMIT
from prbdm_pin.errors import BeamInputError, InputTypeError
from prbdm_pin.plant.plant_layout import plant_layout

BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)


def _names(kind: str, n: int) -> tuple[tuple[str, ...], tuple[str, ...]]:
    if kind == "default":
        return ("tip_force_z",), ("tip_z",)
    j = n - 1  # the last joint: every index a chain of n joints has
    return (("tip_force_x", f"joint_torque[{j}]", "tip_force_z", "tip_force_y"),
            ("tip_x", "tip_z_rate", "q[0]", f"q_rate[{j}]", f"spring_torque[{j}]", "tip_y",
             "tip_z"))


def _model(n: int):
    lengths = np.r_[0.1, np.full(n, 0.9 / n)]
    return pp.build_model(BEAM, lengths, np.linspace(900.0, 400.0, n))


def _general(*args, **kwargs):
    """linearize with the short path switched off: the Pinocchio/LAPACK steps."""
    return pp.linearize(*args, compiled=False, **kwargs)


def _cond(a: np.ndarray) -> float:
    return float(np.linalg.cond(a))


@pytest.mark.parametrize("n", [1, 2, 5])
@pytest.mark.parametrize("names", ["default", "mixed"])
@pytest.mark.parametrize("load", [None, (300.0, 0.0, -400.0)])
def test_the_short_path_equals_the_general_path(n, names, load):
    model = _model(n)
    inputs, outputs = _names(names, n)
    xi = np.linspace(0.01, 0.05, n)  # one ratio per mode: the modes' order matters
    fast = pp.linearize(model, inputs, outputs, load_N=load, damping_ratio=xi)
    ref = _general(model, inputs, outputs, load_N=load, damping_ratio=xi)
    assert plant_layout(model, inputs, outputs) is not None  # the short path answered
    for f in ("state_names", "input_names", "output_names", "input_units", "output_units",
              "hub", "n_free", "spin_rad_s", "gyroscopic_Nms_per_rad"):
        assert getattr(fast, f) == getattr(ref, f), f
    fields = ("q_eq", "u_eq", "y_eq", "mass_kg_m2", "stiffness_Nm_per_rad", "input_map",
              "output_map_position", "output_map_rate", "C", "D", "output_map_acceleration",
              "output_map_input")
    for f in fields:
        assert not getattr(fast, f).flags.writeable, f
        if load is None:
            # the same Pinocchio calls and the same products in the same order: equal to
            # the bit
            np.testing.assert_array_equal(getattr(fast, f), getattr(ref, f), err_msg=f)
    if load is not None:
        # the equilibrium by two descents (compiled and numpy) summing in other orders:
        # each converged to a residual of 1e-10 of the torques and polished by its last
        # quadratic step, so both lie within EPS cond(H) of the root (times n for the sums)
        H = ref.stiffness_Nm_per_rad
        dq = 10 * n * EPS * _cond(H) * max(np.abs(ref.q_eq).max(), 1.0)
        np.testing.assert_allclose(fast.q_eq, ref.q_eq, rtol=0.0, atol=dq)
        for f in fields[1:]:
            a, b = getattr(fast, f), getattr(ref, f)
            # a pose-dependent entry is a sum of lengths times sines and cosines of the link
            # angles: each of the n angles moves it by at most its scale per rad
            scale = max(np.abs(b).max(), 1.0)
            np.testing.assert_allclose(a, b, rtol=0.0, atol=10 * n * dq * scale, err_msg=f)
    M, K = ref.mass_kg_m2, ref.stiffness_Nm_per_rad
    s = 1.0 / np.sqrt(model.stiffness_Nm_per_rad)
    # the damping's modes: each solver's eigenvectors are good to EPS cond(S M S) (the gap
    # of the scaled spectrum relative to its largest eigenvalue), times n for the sums
    tol_c = 10 * n * EPS * _cond(M * s[:, None] * s[None, :])
    Cd, Cd_ref = fast.damping_Nms_per_rad, ref.damping_Nms_per_rad
    assert np.linalg.norm(Cd - Cd_ref) <= tol_c * np.linalg.norm(Cd_ref)
    # M^-1 [K, C_d, B_q] by two Cholesky solves: good to EPS cond(M) relative, times n for
    # the sums, plus the damping's own difference carried through M^-1
    tol = 10 * n * EPS * _cond(M) + tol_c * _cond(M)
    X_ref = np.linalg.solve(M, np.hstack([K, Cd_ref, ref.input_map]))
    for a, b, x in ((fast.A, ref.A, X_ref[:, :2 * n]), (fast.B, ref.B, X_ref[:, 2 * n:])):
        assert np.linalg.norm(a - b) <= tol * max(np.linalg.norm(b), np.linalg.norm(x))


def test_one_joint_is_a_damped_oscillator():
    model = _model(1)
    xi, k = 0.03, float(model.stiffness_Nm_per_rad[0])
    lin = pp.linearize(model, damping_ratio=xi)
    inertia = float(pin.crba(model.pin_model, model.pin_model.createData(), np.zeros(1))[0, 0])
    w = np.sqrt(k / inertia)
    expected = np.array([[0.0, 1.0], [-w * w, -2.0 * xi * w]])
    # a few roundings of k / I and sqrt: relative to the largest entry
    np.testing.assert_allclose(lin.A, expected, rtol=0.0, atol=20 * EPS * w * w)
    # the tip's height moves with the joint by the lever arm from the joint to the tip (0.9 m)
    np.testing.assert_allclose(lin.C, [[-0.9, 0.0]], rtol=20 * EPS)  # a few roundings
    np.testing.assert_allclose(lin.B[:, 0], [0.0, -0.9 / inertia], rtol=20 * EPS)


def test_a_list_of_names_takes_the_short_path_and_names_it_does_not_cover_do_not():
    model = _model(3)
    a = pp.linearize(model, ["tip_force_z"], ["tip_z", "q[2]"])
    assert plant_layout(model, ["tip_force_z"], ["tip_z", "q[2]"]) is \
        plant_layout(model, ("tip_force_z",), ("tip_z", "q[2]"))  # one layout, cached
    b = pp.linearize(model, ("tip_force_z",), ("tip_z", "q[2]"))
    np.testing.assert_array_equal(a.A, b.A)  # the same call's arithmetic: equal to the bit
    assert plant_layout(model, ("tip_force_z",), ("strain@0.5",)) is None
    assert plant_layout(model, ("tip_moment_y",), ("tip_z",)) is None
    assert plant_layout(model, ("tip_force_z",), ("q[9]",)) is None  # refused: general path


@pytest.mark.parametrize("kwargs, field", [
    ({"load_N": [0.0, 1.0]}, "load_N"),
    ({"damping_ratio": 1.5}, "damping_ratio"),
    ({"damping_ratio": [0.02, 0.02]}, "damping_ratio"),
    ({"outputs": ("q[9]",)}, "outputs[0]"),
    ({"inputs": "tip_force_z"}, "inputs"),
])
def test_bad_input_names_the_argument(kwargs, field):
    with pytest.raises(BeamInputError, match=field.replace("[", r"\[")):
        pp.linearize(_model(3), **kwargs)


def test_the_kernel_refuses_a_mass_matrix_that_is_not_positive_definite():
    from prbdm_pin.plant.plant_kernel import assemble_plant

    n, m, p = 2, 1, 1
    k = np.array([100.0, 50.0])
    z = np.zeros

    def run(M):
        out = (z((2 * n, 2 * n)), z((2 * n, m)), z((p, 2 * n)), z((n, n)), z((n, n)),
               z((n, m)), z(p), z(m))
        return assemble_plant(M, k, np.full(n, 0.02), np.ones(n + 1), np.ones((3, n)), z(3),
                              z(n), z(3), z((m, 3)), z((n, m)), z((p, 3)), z((p, n)),
                              z((p, 3)), z((p, n)), z((m, 3)), COND_LIMIT, 1e-300, *out)

    assert run(np.array([[1.0, 0.2], [0.2, 1.0]]))
    assert not run(np.array([[1.0, 2.0], [2.0, 1.0]]))  # eigenvalues 3 and -1
    assert not run(np.array([[1.0, np.nan], [np.nan, 1.0]]))


def test_compiled_must_be_a_bool():
    with pytest.raises(InputTypeError, match="compiled = 1"):
        pp.linearize(_model(2), compiled=1)
