"""One design's planar chain in one compiled call (chain/planar_chain_fast.py).

With its frequencies and equilibria (planar_chain_evaluation_parts): against scipy's
generalized eigensolver on Pinocchio's mass matrix, and the numpy descent with Pinocchio's tip.

Its mass matrices against Pinocchio's CRBA on the model built from the same lengths, its
springs against QUADPACK's integral of the compliance, its points against Pinocchio's joint
placements (its sections are checked against quadrature in test_planform_kernel.py); a member
under a thickness law is left to the numpy path (None).
"""

import numpy as np
import pinocchio as pin
import pytest
from paths import BEAMS
from scipy.integrate import quad
from scipy.linalg import eigh
from tolerances import EPS, eig_rtol

from prbdm_pin.chain.layout import sample_lengths
from prbdm_pin.chain.pin_dynamics import mass_matrices
from prbdm_pin.chain.planar_chain_fast import planar_chain_evaluation_parts, planar_chain_parts
from prbdm_pin.chain.planar_statics_kernel import load_stiffness_into
from prbdm_pin.chain.statics import static_deflection_planar
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.member.geometry import Beam
from prbdm_pin.model.prbdm_model import build_model


@pytest.mark.parametrize("name", ["reference-random", "stepped-narrow"])
@pytest.mark.parametrize("n", [1, 3, 6])
def test_the_chain_matches_pinocchio_and_quadrature(name, n):
    rng = np.random.default_rng(n)
    beam = load_beam(BEAMS / f"{name}.json")
    for lengths in sample_lengths(rng, beam.length_m, n + 1, 2):
        Q = rng.uniform(-1.5, 1.5, (3, n))
        _, K0, M, (_, joints, _) = planar_chain_parts(beam, lengths, Q)
        model = build_model(beam, lengths, K0)
        ref = mass_matrices(model.pin_model, model.new_data(), Q)
        # two sums of n + 1 links' m r^2 + I (CRBA's spatial algebra against lever arms): a
        # few tens of roundings of the largest entry
        assert np.max(np.abs(M - ref)) <= 50 * n * EPS * np.max(np.abs(ref))
        data = model.new_data()
        for p, q in enumerate(Q):
            pin.forwardKinematics(model.pin_model, data, q)
            # joint j + 1's placement (x, z; the chain's z flipped): sums of j + 1 link
            # vectors, a few roundings of the member's length
            for j in range(n):
                x, _, z = data.oMi[j + 1].translation
                np.testing.assert_allclose(joints[0, p, :, j], [x, -z], rtol=0,
                                           atol=10 * n * EPS * beam.length_m)
        c = np.cumsum(lengths) - 0.5 * lengths
        c[0], c[-1] = 0.0, beam.length_m
        EI_w = beam.material.E_Pa * 2 * beam.thickness_m**3 / 12  # E I(x) = EI_w w(x)
        for j in range(n):
            pts = [x for x in beam.x_m if c[j] < x < c[j + 1]] or None
            # QUADPACK's request, 450 EPS (1e-13), and as much again for the compiled sums
            integral = quad(lambda x: 1.0 / float(beam.half_width_at(x)), c[j], c[j + 1],
                            points=pts, epsabs=0, epsrel=450 * EPS, limit=200)[0]
            assert K0[j] == pytest.approx(EI_w / integral, rel=900 * EPS)


def test_a_thickness_law_is_left_to_the_numpy_path():
    beam = Beam(x_m=[0.0, 1.0], half_width_m=[0.02, 0.02], thickness_m=[0.01, 0.005])
    assert planar_chain_parts(beam, np.array([0.2, 0.5, 0.3]), np.zeros((1, 2))) is None


def test_the_evaluation_matches_scipy_the_numpy_descent_and_pinocchios_tip():
    beam = load_beam(BEAMS / "reference-random.json")
    rng = np.random.default_rng(5)
    n = 5
    lengths = next(iter(sample_lengths(rng, beam.length_m, n + 1, 1)))
    Q = np.full((1, n), 0.02)
    factors = rng.uniform(0.5, 2.0, n)
    forces = np.array([[0.0, -40.0], [25.0, 60.0]])  # N: x and z of two load cases
    starts = np.zeros((2, n))
    _, K0, K, M, _, w, solved = planar_chain_evaluation_parts(beam, lengths, Q, factors,
                                                               forces, starts)
    model = build_model(beam, lengths, K)
    Mp = mass_matrices(model.pin_model, model.new_data(), Q)[0]
    ref = np.sqrt(eigh(np.diag(K), Mp, eigvals_only=True))
    # two eigensolves of one pencil: within the spectrum's spread of each other
    np.testing.assert_allclose(w[0], ref, rtol=eig_rtol(ref), atol=0)
    np.testing.assert_allclose(K, factors * K0, rtol=EPS, atol=0)  # one rounding
    for (fx, fz), (q, tip) in zip(forces, solved, strict=True):
        F = np.array([fx, 0.0, fz])
        q_ref = static_deflection_planar(lengths, K, F)
        # each descent stops once |K q - J^T F| <= 1e-10 |K q| (its request), so within
        # that over H's smallest eigenvalue of the root; two of them, twice that
        T = np.empty((n, n))
        load_stiffness_into(lengths, q, fx, fz, *(np.empty(n) for _ in range(4)), T)
        lam = np.linalg.eigvalsh(np.diag(K) - T)[0]
        tol = 2 * 1e-10 * np.linalg.norm(K * q) / lam
        np.testing.assert_allclose(q, q_ref, rtol=0, atol=tol)
        data = model.new_data()
        pin.framesForwardKinematics(model.pin_model, data, q)
        # sums of n + 1 link vectors: a few roundings of the member's length
        np.testing.assert_allclose(tip, data.oMf[model.tip_frame_id].translation, rtol=0,
                                   atol=10 * (n + 1) * EPS * beam.length_m)


def test_what_the_evaluation_leaves_to_the_checked_paths():
    beam = load_beam(BEAMS / "reference-random.json")
    lengths = np.full(4, beam.length_m / 4)
    K0 = planar_chain_parts(beam, lengths, np.zeros((1, 3)))[1]
    # a column past its buckling load from the straight pose (a saddle), and no in-plane load
    forces = np.array([[-4.0 * K0.max() / beam.length_m, 0.0], [0.0, 0.0]])
    got = planar_chain_evaluation_parts(beam, lengths, np.zeros((1, 3)), np.ones(3), forces,
                                        np.zeros((2, 3)))
    assert got[6] == [None, None]
    # two poses: the fits' batched LAPACK path answers them
    assert planar_chain_evaluation_parts(beam, lengths, np.zeros((2, 3)), np.ones(3), forces,
                                         np.zeros((2, 3))) is None
