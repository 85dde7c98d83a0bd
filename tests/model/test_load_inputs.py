"""The input columns of the follower tip moments, distributed forces and base accelerations.

References, none from the package's maps: central differences of the tip rotation (the follower
moment's virtual work, omega in the tip frame), of the virtual work of the distributed load
integrated by Gauss-Legendre quadrature over material points of the links (positions from
Pinocchio's frame placements), of the total centre of mass (Pinocchio's ``centerOfMass``, the
base acceleration's inertial load -m a); and Pinocchio's generalized gravity for a uniform
strip's self weight.
"""

import numpy as np
import pinocchio as pin
import pytest
from cantilever_loads import strip_properties
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.errors import BeamInputError, InputTypeError
from prbdm_pin.model.chain_names import node_links
from prbdm_pin.model.inputs import input_map

H = 1e-5  # central-difference step, rad: truncation H^2 ~ 1e-10, rounding EPS / H ~ 2e-11
CD_TOL = 1e-8  # relative, of the largest entry: above both by two orders


def _model(beam, axes="y", hub=None):
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * beam.length_m
    return pp.build_model(beam, lengths, spatial_stiffness(beam, lengths, axes), axes=axes,
                          hub=hub)


def _pose(model, seed=1):
    return 0.4 * np.random.default_rng(seed).standard_normal(model.pin_model.nv)


def _central(f, q):
    cols = []
    for j in range(q.size):
        e = np.zeros(q.size)
        e[j] = H
        cols.append((f(q + e) - f(q - e)) / (2 * H))
    return np.array(cols).T  # (len f, nv)


@pytest.mark.parametrize("axes", ["y", "xyz"])
def test_follower_moments_do_the_virtual_work_of_the_tip_frame_rotation(tapered, axes):
    model = _model(tapered, axes)
    q = _pose(model)
    data = model.new_data()

    def rotation(qq):
        pin.framesForwardKinematics(model.pin_model, data, qq)
        return data.oMf[model.tip_frame_id].rotation.copy()

    R = rotation(q)
    # omega in the tip frame per joint rate: the axial vector of R^T dR/dq_j
    ref = np.empty((3, q.size))
    for j in range(q.size):
        e = np.zeros(q.size)
        e[j] = H
        W = R.T @ (rotation(q + e) - rotation(q - e)) / (2 * H)
        ref[:, j] = [W[2, 1], W[0, 2], W[1, 0]]
    B = input_map(model, q, ["tip_moment_follower_x", "tip_moment_follower_y",
                             "tip_moment_follower_z"])
    assert np.abs(B - ref.T).max() <= CD_TOL * np.abs(ref).max()
    if axes == "y":
        # a planar chain keeps every axis along y: the follower y moment is the dead one
        # (both are 1 on every joint, exactly)
        assert np.array_equal(B[:, 1], input_map(model, q, ["tip_moment_y"])[:, 0])


def _quadrature_work(model, q, load, axis, data):
    """Virtual work of the unit distributed load at pose q: sum over links of
    int w(x) e_axis . p(x) dx by 8-point Gauss-Legendre on each link's part of the span."""
    pin.framesForwardKinematics(model.pin_model, data, q)
    ends = np.cumsum(model.lengths_m)
    starts = ends - model.lengths_m
    a, b = (0.0, ends[-1]) if load is None else (load.x_start_m, load.x_end_m)
    wa, wb = (1.0, 1.0) if load is None else (load.start_weight, load.end_weight)
    t, wq = np.polynomial.legendre.leggauss(8)
    names = ["link_0"] + [node_links(j, model.axes)[-1] for j in range(1, model.n_joints + 1)]
    work = 0.0
    for name, s0, s1 in zip(names, starts, ends, strict=True):
        u, v = max(s0, a), min(s1, b)
        if v <= u:
            continue
        M = data.oMf[model.pin_model.getFrameId(name)]
        x = 0.5 * (u + v) + 0.5 * (v - u) * t
        intensity = wa + (wb - wa) * (x - a) / (b - a)
        pts = M.translation[:, None] + M.rotation[:, :1] * (x - s0)
        work += 0.5 * (v - u) * np.sum(wq * intensity * pts[axis])
    return work


@pytest.mark.parametrize("axes, hub", [("y", None), ("xyz", None), ("y", (2.0, 0.1))])
def test_a_distributed_load_does_the_virtual_work_of_the_load_along_the_links(tapered, axes,
                                                                            hub):
    model = _model(tapered, axes, None if hub is None else pp.Hub(*hub))
    q = _pose(model, 2)
    L = tapered.length_m
    # the span cuts links 0 and 2 inside; a linear profile
    load = pp.DistributedLoad(0.1 * L, 0.65 * L, start_weight=0.5, end_weight=2.0)
    # a profile through zero: a link's part with (nearly) no resultant but a couple
    flip = pp.DistributedLoad(0.2 * L, 0.5 * L, start_weight=-1.0, end_weight=1.0)  # link 1
    names = ["distributed_force_x", "distributed_force_y", "distributed_force_z",
             "distributed_force_z[0]", "distributed_force_y[0]", "distributed_force_z[1]"]
    B = input_map(model, q, names, loads=(load, flip))
    data = model.new_data()
    scale = np.abs(B).max()  # of all columns: a y load on the planar chain has a zero column
    cases = [(0, None), (1, None), (2, None), (2, load), (1, load), (2, flip)]
    for c, (axis, ld) in enumerate(cases):
        ref = _central(lambda qq, ax=axis, lo=ld: np.array([_quadrature_work(model, qq, lo, ax,
                                                                             data)]), q)[0]
        assert np.abs(B[:, c] - ref).max() <= CD_TOL * scale, c


@pytest.mark.parametrize("axes", ["y", "xyz"])
def test_a_uniform_strip_s_weight_as_a_distributed_load_is_its_generalized_gravity(narrow,
                                                                                   axes):
    model = _model(narrow, axes)
    q = _pose(model, 3)
    _, _, rhoA = strip_properties(narrow)
    g = np.array([0.5, -2.0, -9.81])
    B = input_map(model, q, ["distributed_force_x", "distributed_force_y",
                             "distributed_force_z"])
    pm = pin.Model(model.pin_model)
    pm.gravity = pin.Motion(np.r_[g, 0.0, 0.0, 0.0])
    ref = -pin.computeGeneralizedGravity(pm, pm.createData(), q)  # the weight's force
    # a sum of 4 links' terms each of a few roundings (link masses from the sections'
    # quadrature, the same centroids): 100 EPS of the largest
    assert np.abs(B @ (rhoA * g) - ref).max() <= 100 * EPS * np.abs(ref).max()


@pytest.mark.parametrize("axes, hub", [("y", None), ("xyz", None), ("y", (2.0, 0.1))])
def test_a_base_acceleration_is_the_inertial_load_of_the_whole_mass(tapered, axes, hub):
    model = _model(tapered, axes, None if hub is None else pp.Hub(*hub))
    q = _pose(model, 4)
    data = model.new_data()

    def first_moment(qq):  # sum m_i c_i of the moving links, kg m
        c = pin.centerOfMass(model.pin_model, data, qq)
        return data.mass[0] * c  # the mass it divided by (the joints' subtrees)

    # -m a on every link: generalized force -sum m_i dc_i/dq . a
    ref = -_central(first_moment, q)  # (3, nv)
    B = input_map(model, q, ["base_accel_x", "base_accel_y", "base_accel_z"])
    assert np.abs(B - ref.T).max() <= CD_TOL * np.abs(ref).max()


def test_bad_loads_are_refused_by_name(tapered):
    model = _model(tapered)
    L = tapered.length_m
    with pytest.raises(BeamInputError, match=r"inputs\[0\] = 'distributed_force_z\[1\]'"):
        input_map(model, np.zeros(3), ["distributed_force_z[1]"],
                  loads=(pp.DistributedLoad(0.0, 0.5 * L),))
    with pytest.raises(BeamInputError, match=r"loads\[0\] x_end_m = .*: must lie on the beam"):
        pp.linearize(model, inputs=["distributed_force_z[0]"],
                     loads=(pp.DistributedLoad(0.1, 2.0 * L),))
    with pytest.raises(InputTypeError, match=r"loads\[0\] = .*DistributedLoad"):
        pp.linearize(model, inputs=["distributed_force_z[0]"], loads=((0.1, 0.5),))
    with pytest.raises(InputTypeError, match="loads = "):
        pp.simulate(model, 0.01, inputs=["distributed_force_z"], loads="0.1:0.5")
    with pytest.raises(BeamInputError, match="DistributedLoad x_start_m = 0.5: must be < "):
        pp.DistributedLoad(0.5, 0.2)
    with pytest.raises(BeamInputError, match="unknown; must be one of .*base_accel_z"):
        pp.linearize(model, inputs=["base_accel_w"])
