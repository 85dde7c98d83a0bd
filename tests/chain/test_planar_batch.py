"""The batched planar closed forms (prbdm_pin.chain.planar_batch and its compiled kernel)
against Pinocchio on each design: M(q) against CRBA, the accelerations against ABA with the
tip force through Pinocchio's frame Jacobian, every design at its own random state."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from tolerances import EPS

from prbdm_pin.chain.planar_batch import batch_mass, design_links, planar_links, stack_links
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.files.urdf_file import load_urdf
from prbdm_pin.member.geometry import Beam
from prbdm_pin.model.prbdm_model import build_model

BEAM = Beam(x_m=[0.0, 1.0], half_width_m=[0.03, 0.02], thickness_m=[0.012, 0.006])


def _designs(n: int, count: int, seed: int):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        w = rng.uniform(0.5, 1.5, n + 1)
        lengths = w / w.sum()
        out.append(build_model(BEAM, lengths, rng.uniform(500.0, 5000.0, n)))
    return out


@pytest.mark.parametrize("n", [1, 3, 5, 8])
def test_batched_mass_matrices_match_crba_per_design(n):
    models = _designs(n, 4, seed=n)
    links = design_links(models)
    Q = np.random.default_rng(10 + n).uniform(-1.0, 1.0, (4, n))
    M = batch_mass(links, Q)
    for b, m in enumerate(models):
        ref = pin.crba(m.pin_model, m.new_data(), Q[b])
        # each entry is a sum of at most n squared lever arms (R^T R): n roundings of the
        # largest entry, times 10 for the products and the inertia tail
        assert np.abs(M[b] - ref).max() <= 10 * n * EPS * np.abs(ref).max()


@pytest.mark.parametrize("n", [1, 2, 5, 8])
def test_compiled_accelerations_match_aba_with_the_tip_force(n):
    from prbdm_pin.chain.planar_batch_kernel import batch_state_rates

    models = _designs(n, 5, seed=20 + n)
    links = design_links(models)
    rng = np.random.default_rng(30 + n)
    Q, V = rng.uniform(-1.0, 1.0, (5, n)), rng.uniform(-20.0, 20.0, (5, n))
    tau, F = rng.normal(size=(5, n)) * 10.0, rng.normal(size=(5, 3)) * 50.0
    k = rng.uniform(100.0, 1000.0, (5, n))
    C = rng.normal(size=(5, n, n))
    C = C @ C.swapaxes(1, 2)  # any matrix: the kernel applies it as it is
    rates = batch_state_rates(links, np.hstack((Q, V)), k, C, tau, F)
    assert np.array_equal(rates[:, :n], V)
    a = rates[:, n:]
    for b, m in enumerate(models):
        d = m.new_data()
        J = pin.computeFrameJacobian(m.pin_model, d, Q[b], m.tip_frame_id,
                                     pin.LOCAL_WORLD_ALIGNED)[:3]
        ref = pin.aba(m.pin_model, d, Q[b], V[b],
                      tau[b] - k[b] * Q[b] - C[b] @ V[b] + J.T @ F[b])
        cond = np.linalg.cond(pin.crba(m.pin_model, d, Q[b]))
        # a solve of M: the right-hand side's roundings (n terms each) times cond(M), x10
        assert np.abs(a[b] - ref).max() <= 10 * n * cond * EPS * np.abs(ref).max()


def test_the_batched_kernel_reads_no_force_damping_or_torque_as_zero():
    from prbdm_pin.chain.planar_batch_kernel import batch_state_rates

    models = _designs(3, 2, seed=3)
    links = design_links(models)
    Q, V = np.full((2, 3), 0.2), np.full((2, 3), -1.0)
    k = np.full((2, 3), 300.0)
    for b, m in enumerate(models):
        ref = pin.aba(m.pin_model, m.new_data(), Q[b], V[b], -k[b] * Q[b])
        a = batch_state_rates(links, np.hstack((Q, V)), k, None, None, None)[b, 3:]
        cond = np.linalg.cond(pin.crba(m.pin_model, m.new_data(), Q[b]))
        assert np.abs(a - ref).max() <= 30 * cond * EPS * np.abs(ref).max()  # as above, n = 3


def test_chains_the_closed_form_does_not_describe_are_reported_as_none():
    lengths = [0.2, 0.5, 0.3]
    flat = Beam(x_m=[0.0, 1.0], half_width_m=[0.03, 0.02], thickness_m=0.01)
    spatial = build_model(flat, lengths, spatial_stiffness(flat, lengths, "xy"), axes="xy")
    assert planar_links(spatial.pin_model, spatial.tip_frame_id) is None
    plain = build_model(BEAM, lengths, [2500.0, 1200.0])
    lengths_m, mass, off, iyy = planar_links(plain.pin_model, plain.tip_frame_id)
    assert lengths_m.tolist() == lengths  # placements read back exactly
    # the links' masses are the sections' (exact copies through the Pinocchio model)
    assert mass.tolist() == plain.sections.mass_kg[1:].tolist()


def test_the_sections_reading_is_the_pinocchio_models_own(tmp_path):
    models = _designs(4, 2, seed=9)
    models.append(load_urdf(models[0].write_urdf(tmp_path / "m.urdf")))
    links = design_links(models)
    pin_read = stack_links([planar_links(m.pin_model, m.tip_frame_id) for m in models])
    for name in ("lengths_m", "mass_kg", "com_offset_m", "inertia_yy_kg_m2"):
        a, b = getattr(links, name), getattr(pin_read, name)
        # the offset is a difference of positions along x (one rounding of ~1 m); the rest
        # are copies, or one rounding of the URDF's printed digits
        assert np.abs(a - b).max() <= 2 * EPS * max(1.0, np.abs(b).max()), name
