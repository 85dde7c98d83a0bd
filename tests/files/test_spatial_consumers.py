"""Every consumer of a spatial chain's exports reads our M(q) and K: Pinocchio's URDF parser,
MuJoCo from the MJCF and from the URDF, pybullet and yourdfpy from the URDF, for the axes xy,
yz and xyz of a 3-joint chain of the tapered planform, at the straight pose and two random
non-small ones; the MJCF damping is the stiffness form on every spring."""

import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin
import pytest
import scipy.linalg as sla
from consumers import (
    consumer_joint_names,
    mujoco_from_spatial_urdf,
    mujoco_mass_matrices,
    pybullet_mass_and_damping,
    yourdfpy_mass_and_damping,
)
from paths import BEAMS
from tolerances import EPS

from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.files.export import export_model, mjcf_text, read_export_record
from prbdm_pin.model.chain_names import joint_names
from prbdm_pin.model.prbdm_model import build_model

mujoco = pytest.importorskip("mujoco")

BEAM = load_beam(BEAMS / "tapered.json")
LENGTHS = np.array([0.12, 0.18, 0.16, 0.14])  # m, summing to the beam's 0.6 m
XI = 0.02

# The mass matrices agree to 1e-9 of max |M|. Conditioning: every consumer builds M from the
# same numbers (the files write each in full, repr), by its own algorithm (CRBA, composite
# inertias, sums of link Jacobian terms). A diagonal entry is a sum of nonnegative link terms
# (some 10 of them, with 3 rotations each), so it is good to some 10 EPS relative; an
# off-diagonal one is bounded by its diagonals (M is positive semidefinite), so its error is a
# few 10 EPS of max |M|: measured at most 1.3e-15 over every consumer, axes and pose. 1e-9 is
# the consumer tests' common bound, far above that and far below what a wrong axis, joint order
# or lever arm gives (an O(1) part of max |M|).
M_RTOL = 1e-9


@pytest.fixture(scope="module", params=["xy", "yz", "xyz"])
def chain(request):
    axes = request.param
    return build_model(BEAM, LENGTHS, spatial_stiffness(BEAM, LENGTHS, axes), axes=axes)


def _poses(model):
    # a seed per axes, so each chain's two poses are drawn once; sd 0.3 rad: up to ~50 degrees
    rng = np.random.default_rng(len(model.axes.value))
    return [np.zeros(model.n_springs), *rng.normal(0.0, 0.3, (2, model.n_springs))]


def _assert_same_M(Ms, model, poses, who):
    for q, M in zip(poses, Ms, strict=True):
        ref = model.mass_matrix(q)
        err = np.abs(M - ref).max() / np.abs(ref).max()
        assert err <= M_RTOL, f"{who}: |M - M_ours| = {err:.2e} of max |M| at q = {q}"


def _urdf_springs(text):
    """The URDF's <springStiffness> per joint, read with ElementTree (not with our reader)."""
    root = ET.fromstring(text)
    return {g.get("reference"): float(g.find("springStiffness").text)
            for g in root.iter("gazebo")}


def test_the_urdf_gives_every_consumer_our_M_and_K(chain, tmp_path):
    path = export_model(chain, tmp_path / "chain.urdf", "urdf", XI)
    text = path.read_text()
    names = joint_names(chain.n_joints, chain.axes)
    poses = _poses(chain)
    # K: the springs as written, read back exactly (repr round trip: exact by construction;
    # slack 5 EPS)
    springs = _urdf_springs(text)
    np.testing.assert_allclose([springs[j] for j in names], chain.stiffness_Nm_per_rad,
                               rtol=5 * EPS, atol=0.0)
    # Pinocchio's own URDF parser, coordinates in our order
    pm = pin.buildModelFromXML(text)
    assert list(pm.names)[1:] == names
    data = pm.createData()
    Ms = [pin.crba(pm, data, q) for q in poses]
    _assert_same_M([np.triu(M) + np.triu(M, 1).T for M in Ms], chain, poses, "pinocchio")
    # pybullet and yourdfpy: their coordinates are the revolute joints in our order (pybullet's
    # joint indices also hold the fixed clamp and tip joints, which carry no coordinate)
    bullet_names, yourdfpy_names = consumer_joint_names(path)
    assert bullet_names == names and yourdfpy_names == names
    Ms_b, damping_b, masses = pybullet_mass_and_damping(path, poses)
    _assert_same_M(Ms_b, chain, poses, "pybullet")
    assert all(masses[link] == 0.0 for link in masses if link.count("_") == 2)  # link_j_a
    Ms_y, damping_y = yourdfpy_mass_and_damping(path, poses)
    _assert_same_M(Ms_y, chain, poses, "yourdfpy")
    # the joint damping: the stiffness form beta k on every spring, written in full (exact by
    # construction; slack 5 EPS)
    rec = read_export_record(text)
    beta_k = rec.damping_beta_s * chain.stiffness_Nm_per_rad
    for got in (damping_b, damping_y, np.array(pm.damping)):
        np.testing.assert_allclose(got, beta_k, rtol=5 * EPS, atol=0.0)
    # MuJoCo from the URDF, its massless node links fused (consumers.mujoco_from_spatial_urdf
    # says why they must be): our M; MuJoCo's URDF import reads no springs (a Gazebo tag)
    m = mujoco_from_spatial_urdf(text, chain.axes.joint_order, chain.n_joints, path.parent)
    assert [m.joint(i).name for i in range(m.njnt)] == names
    assert m.nbody == chain.n_joints + 1  # world (link 0 fused into it) and one body per link
    _assert_same_M(mujoco_mass_matrices(m, poses), chain, poses, "mujoco (urdf)")
    np.testing.assert_array_equal(m.jnt_stiffness, 0.0)


def test_the_mjcf_gives_mujoco_our_M_K_and_damping(chain):
    text = mjcf_text(chain, XI)
    m = mujoco.MjModel.from_xml_string(text)
    names = joint_names(chain.n_joints, chain.axes)
    assert [m.joint(i).name for i in range(m.njnt)] == names
    assert m.nbody == chain.n_joints + 2  # world, link_0 ... link_n: no intermediate bodies
    poses = _poses(chain)
    _assert_same_M(mujoco_mass_matrices(m, poses), chain, poses, "mujoco (mjcf)")
    # K and C as written (repr round trip: exact by construction; slack 5 EPS)
    np.testing.assert_allclose(m.jnt_stiffness, chain.stiffness_Nm_per_rad, rtol=5 * EPS,
                               atol=0.0)
    np.testing.assert_array_equal(m.qpos_spring, 0.0)
    rec = read_export_record(text)
    np.testing.assert_allclose(m.dof_damping, rec.damping_beta_s * m.jnt_stiffness,
                               rtol=5 * EPS, atol=0.0)
    # MuJoCo's own (M, K, C): mode 1 gets the asked ratio, mode k xi omega_k / omega_1, as the
    # record says; the spread of the spectrum (omega_max / omega_1 up to 154) costs
    # n EPS (omega_max / omega_1)^2 ~ 5e-11 relative on the lowest mode's eigenvalue (tolerances.
    # eig_rtol's figure), and the ratios and frequencies follow: 1e-6 is far above it
    M = mujoco_mass_matrices(m, [np.zeros(m.nv)])[0]
    w2, phi = sla.eigh(np.diag(m.jnt_stiffness), M)
    omega = np.sqrt(w2)
    ratios = np.einsum("ik,i,ik->k", phi, m.dof_damping, phi) / (2 * omega)
    np.testing.assert_allclose(ratios, XI * omega / omega[0], rtol=1e-6)
    np.testing.assert_allclose(ratios, rec.modal_damping_ratios, rtol=1e-6)
    np.testing.assert_allclose(rec.natural_frequencies_rad_s, omega, rtol=1e-6)
    assert rec.joint_damping_Nms_per_rad.shape == (chain.n_springs,)
