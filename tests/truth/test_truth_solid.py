"""3D solid truth against Euler-Bernoulli, the cantilever-plate table and the elastica table."""


import numpy as np
import pytest
import scipy.sparse.linalg
from paths import BEAMS
from reference import BETA_L as REF_BETA_L
from reference import ELASTICA, SQUARE_PLATE

from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.member.geometry import Beam
from prbdm_pin.member.material import Material
from prbdm_pin.truth import compute_truth, solid_fe, solid_nonlinear
from prbdm_pin.truth.modes import label_modes
from prbdm_pin.truth.solid import default_solid_level, solid_modal, solid_static

# Cantilever eigenvalues beta_n L (e.g. Blevins, Formulas for Natural Frequency and Mode Shape).
BETA_L = REF_BETA_L[:5]
# Converged Kirchhoff cantilever plate, nu = 0.3: omega a^2 sqrt(rho h / D), first five modes
# (tests/reference.py).
PLATE = SQUARE_PLATE


def _euler_bernoulli(beam: Beam) -> np.ndarray:
    rhoA = beam.material.rho_kg_m3 * 2 * beam.half_width_m[0] * beam.thickness_m
    return BETA_L**2 * np.sqrt(beam.root_EI_Nm2 / (rhoA * beam.length_m**4))


def test_default_level_is_two_and_a_half_thicknesses(narrow):
    assert default_solid_level(narrow) == 2  # L / (10 * 2^2) = 25 mm = 2.5 t


def _timoshenko(beam: Beam, kappa: float = 5 / 6) -> np.ndarray:
    """Clamped-free Timoshenko-beam frequencies (rad/s) near the first five Euler-Bernoulli ones:
    roots of the free-end conditions of the exact transfer matrix expm(A L) of
    kGA (w'' - psi') + rho A w^2 w = 0, EI psi'' + kGA (w' - psi) + rho I w^2 psi = 0."""
    from scipy.linalg import expm
    from scipy.optimize import brentq

    m, b, t, L = beam.material, 2 * beam.half_width_m[0], beam.thickness_m, beam.length_m
    EI, kGA = m.E_Pa * b * t**3 / 12, kappa * m.G_Pa * b * t
    rA, rI = m.rho_kg_m3 * b * t, m.rho_kg_m3 * b * t**3 / 12

    def free_end(w: float) -> float:
        Z = np.array([[0, 1, 0, 0], [-rA * w**2 / kGA, 0, 0, 1], [0, 0, 0, 1],
                      [0, -kGA / EI, kGA / EI - rI * w**2 / EI, 0]])
        T = expm(Z * L)  # clamped root: w = psi = 0, so the unknowns are w'(0) and psi'(0)
        B = np.array([T[3], T[1] - T[2]])[:, [1, 3]]  # free tip: psi' = 0, w' - psi = 0
        return np.linalg.det(B) / np.abs(B).max() ** 2

    out = []
    for e in _euler_bernoulli(beam):
        grid = np.linspace(0.9 * e, 1.001 * e, 400)
        v = np.sign([free_end(g) for g in grid])
        k = np.flatnonzero(v[:-1] != v[1:])[-1]
        out.append(brentq(free_end, grid[k], grid[k + 1], xtol=1e-12))
    return np.array(out)


def test_narrow_bending_modes_just_above_timoshenko(narrow):
    m = solid_modal(narrow, n_modes=12)
    bending = np.array([lab == "bending" for lab in label_modes(m)])
    assert np.all(m.symmetric[bending]) and np.all(m.mpf_z_fraction[bending][:5] > 1e-3)
    # Shear and rotary inertia lower the higher modes (Timoshenko: -0.008 % ... -0.38 % of
    # Euler-Bernoulli for modes 1-5); the clamp blocks the root's Poisson contraction and adds
    # 0.2-0.5 % (measured 0.25, 0.26, 0.29, 0.33, 0.40 %, unchanged at level 4).
    rel = m.omega_rad_s[bending][:5] / _timoshenko(narrow) - 1
    assert np.all((rel > 0.002) & (rel < 0.005)), rel
    # Cantilever effective-mass fractions of modes 1-3 (Blevins): 0.6131, 0.1883, 0.0647.
    assert m.mpf_z_fraction[bending][:3] == pytest.approx([0.6131, 0.1883, 0.0647], abs=2e-3)
    # The centreline shape of mode 1 is the Euler-Bernoulli shape.
    x = m.centerline_x_m
    b = BETA_L[0]
    sigma = (np.cosh(b) + np.cos(b)) / (np.sinh(b) + np.sin(b))
    ref = np.cosh(b * x) - np.cos(b * x) - sigma * (np.sinh(b * x) - np.sin(b * x))
    u = m.centerline_uz[0]
    assert (u @ ref) ** 2 / ((u @ u) * (ref @ ref)) > 0.9999
    assert m.mac_beam[0] > 0.9999


def test_narrow_in_plane_modes_labelled_and_never_selected(narrow):
    m = solid_modal(narrow, n_modes=12)
    labels = label_modes(m)
    in_plane = np.flatnonzero(np.array(labels) == "in-plane")
    # the first in-plane bending mode: Euler-Bernoulli about z, depth 2 w instead of t
    ratio = 2 * narrow.half_width_m[0] / narrow.thickness_m
    ref = ratio * _euler_bernoulli(narrow)[0]
    assert m.omega_rad_s[in_plane[0]] == pytest.approx(ref, rel=1e-2)
    assert np.all(m.z_energy_fraction[in_plane] < 1e-6)
    for selection in ("paper", "shape"):
        r = compute_truth(narrow, model="solid", modes=5, selection=selection, static=False)
        assert [r.labels[i] for i in r.mode_index] == ["bending"] * 5
        assert not set(r.mode_index) & set(in_plane)


def test_linear_tip_deflection(narrow):
    s = solid_static(narrow)
    ref = narrow.tip_force_N[2] * narrow.length_m**3 / (3 * narrow.root_EI_Nm2)
    assert s.tip_displacement_m[2] == pytest.approx(ref, rel=5e-3)
    assert abs(s.tip_displacement_m[0]) < 1e-9 and abs(s.tip_displacement_m[1]) < 1e-9


def test_linear_tip_deflection_without_poisson_is_timoshenko(narrow):
    # nu = 0: no clamp constraint; Euler-Bernoulli plus shear P L / (k G A), k = 5/6.
    mat = Material("nu0", 205e9, 7850.0, 0.0)
    beam = Beam(narrow.x_m, narrow.half_width_m, narrow.thickness_m, mat, narrow.tip_force_N)
    P, L, A = beam.tip_force_N[2], beam.length_m, 2 * beam.half_width_m[0] * beam.thickness_m
    ref = P * L**3 / (3 * beam.root_EI_Nm2) + P * L / (5 / 6 * mat.G_Pa * A)
    assert solid_static(beam).tip_displacement_m[2] == pytest.approx(ref, rel=2e-4)


def test_tip_deflection_converged_across_levels(narrow):
    ref = narrow.tip_force_N[2] * narrow.length_m**3 / (3 * narrow.root_EI_Nm2)
    w = np.array([solid_static(narrow, level).tip_displacement_m[2] for level in (0, 2, 4)])
    # The strip's mesh is set by its half-width (the local feature size), so every level is
    # converged: measured -0.3765, -0.3754, -0.3793 % (the clamp stiffens the root; 5.3k to 74.6k
    # DOFs; the old mapped mesh needed level 5, 190k DOFs, for -0.377 %)
    assert np.all(np.abs(w / ref - 1) < 5e-3)
    assert np.ptp(w) < 1e-4 * abs(ref)


def test_tangent_matches_linear_stiffness_and_finite_differences(narrow):
    d = solid_fe.discretise(narrow, 0)
    kin = solid_nonlinear.Kinematics(d)
    f0, K0 = kin.evaluate(np.zeros(d.n_vec))
    KL = solid_fe.assemble(narrow, d)[0]  # batched element matrices into a scalar pattern
    assert abs(K0 - KL).max() < 1e-12 * abs(KL).max()
    assert np.abs(f0).max() == 0.0
    rng = np.random.default_rng(1)
    u = 1e-2 * rng.standard_normal(d.n_vec)
    v = rng.standard_normal(d.n_vec)
    _, K = kin.evaluate(u)
    eps = 1e-7
    fp, _ = kin.evaluate(u + eps * v, tangent=False)
    fm, _ = kin.evaluate(u - eps * v, tangent=False)
    assert np.linalg.norm((fp - fm) / (2 * eps) - K @ v) < 1e-6 * np.linalg.norm(K @ v)


def test_free_dof_pattern_and_preconditioned_corrections(narrow):
    d = solid_fe.discretise(narrow, 0)
    kin = solid_nonlinear.Kinematics(d)
    rng = np.random.default_rng(2)
    u = 1e-2 * rng.standard_normal(d.n_vec)
    _, Kfull = kin.evaluate(u)
    _, Kfree = kin.evaluate(u, which="free")
    ref = Kfull[d.free][:, d.free]  # scipy's slicing of the full COO-free assembly
    assert abs(Kfree - ref).max() <= 1e-14 * abs(ref).max()
    # CG preconditioned by the factor of a nearby tangent reaches the direct solution
    solver = solid_nonlinear.TangentSolver(rtol=1e-10, max_cg=50)
    r = rng.standard_normal(d.free.size)
    _, K0 = kin.evaluate(0.99 * u, which="free")
    solver.solve(K0, r)
    du = solver.solve(Kfree, r)
    assert solver.factorisations == 1 and solver.cg_iterations > 0
    exact = scipy.sparse.linalg.spsolve(Kfree.tocsc(), r)
    assert np.linalg.norm(du - exact) < 1e-6 * np.linalg.norm(exact)


def test_assembly_matches_scikit_fem_forms(narrow):
    from skfem import BilinearForm, asm

    d = solid_fe.discretise(narrow, 0)
    K, M = solid_fe.assemble(narrow, d)

    def gradient(k, m):
        return BilinearForm(lambda u, v, w: v.grad[k] * u.grad[m])

    A = {(k, m): asm(gradient(k, m), d.basis) for k in range(3) for m in range(3)}
    trace = A[0, 0] + A[1, 1] + A[2, 2]
    Ms = narrow.material.rho_kg_m3 * asm(BilinearForm(lambda u, v, w: u * v), d.basis)
    for i in range(3):
        for j in range(3):
            ref = d.lam * A[i, j] + d.mu * A[j, i] + (d.mu * trace if i == j else 0 * trace)
            assert abs(K[i::3, j::3] - ref).max() < 1e-12 * abs(K).max()
            assert abs(M[i::3, j::3] - (Ms if i == j else 0 * Ms)).max() < 1e-12 * abs(Ms).max()


def _orders(beam: Beam, level):
    d = solid_fe.discretise(beam, level)
    assert np.array_equal(np.sort(d.order), np.arange(d.free.size))
    K = solid_fe.assemble(beam, d)[0][d.free][:, d.free]
    col, mmd = solid_fe.SpdFactor(K, d.order), solid_fe.SpdFactor(K)
    f = solid_fe.tip_load(beam, d, beam.tip_force_N)[d.free]
    a, b = col.solve(f), mmd.solve(f)
    # normwise backward error (Rigal-Gaches): both are backward stable
    norm_k = scipy.sparse.linalg.norm(K, np.inf)
    for x in (a, b):
        eta = np.linalg.norm(K @ x - f, np.inf) / (norm_k * np.abs(x).max() + np.abs(f).max())
        assert eta < 1e-14, eta
    # forward errors of both are limited by the conditioning of the thin solid
    assert np.linalg.norm(a - b) < 1e-7 * np.linalg.norm(b)
    return [f.lu.L.nnz + f.lu.U.nnz for f in (col, mmd)]


def test_column_order_is_a_permutation_that_solves_the_same(narrow):
    fill = _orders(narrow, 0)
    # measured 4.46 M vs 4.81 M entries for SuperLU's minimum degree on the vector matrix
    assert fill[0] < 0.95 * fill[1], fill


@pytest.mark.slow
def test_column_order_less_fill_on_the_reference_panel():
    fill = _orders(load_beam(BEAMS / "reference-random.json"), 0)
    # measured 45.5 M vs 53.2 M entries (factorisation 2.6 s vs 4.1 s); at the default level
    # (168k DOFs) SuperLU's own order runs out of memory
    assert fill[0] < 0.9 * fill[1], fill


def _plate_lambda(beam: Beam, omega: np.ndarray) -> np.ndarray:
    mat, h = beam.material, beam.thickness_m
    D = mat.E_Pa * h**3 / (12 * (1 - mat.nu**2))
    return omega * beam.length_m**2 * np.sqrt(mat.rho_kg_m3 * h / D)


def test_square_plate_coarse():
    beam = load_beam(BEAMS / "square-plate.json")
    m = solid_modal(beam, level=1, n_modes=5)
    assert _plate_lambda(beam, m.omega_rad_s) == pytest.approx(PLATE, rel=1e-2)
    assert m.symmetric.tolist() == [True, False, True, True, False]
    assert np.all(m.mpf_z_fraction[[1, 4]] < 1e-12)
    # the cantilever plate's mode types (Leissa), as the plate model labels them
    assert label_modes(m) == ("bending", "torsion", "bending", "chordwise", "torsion")
    assert np.all(m.mac_beam[[0, 2]] > 0.85) and m.beam_mode_index[0] == 0


@pytest.mark.slow
def test_square_plate_default_level():
    beam = load_beam(BEAMS / "square-plate.json")
    m = solid_modal(beam, n_modes=5)
    assert _plate_lambda(beam, m.omega_rad_s) == pytest.approx(PLATE, rel=1e-2)


# Elastica table ((L - x)/L, y/L): Mattiasson (1981) Table 1
# (tests/reference.py).
@pytest.mark.parametrize(
    "alpha2, retreat, deflection",
    [
        (1.0, *ELASTICA[1.0]),
        pytest.param(2.0, *ELASTICA[2.0], marks=pytest.mark.slow),
    ],
)
def test_large_deflection_matches_elastica_table(narrow, alpha2, retreat, deflection):
    P = alpha2 * narrow.root_EI_Nm2 / narrow.length_m**2
    s = solid_static(narrow, tip_force_N=np.array([0.0, 0.0, -P]), nonlinear=True)
    ref = np.array([-retreat, 0.0, -deflection]) * narrow.length_m
    err = np.linalg.norm(s.tip_displacement_m - ref) / np.linalg.norm(ref)
    assert err < 5e-3, err
    assert s.nonlinear


def test_small_load_nonlinear_equals_linear(narrow):
    F = 1e-3 * narrow.tip_force_N
    lin = solid_static(narrow, level=1, tip_force_N=F)
    nl = solid_static(narrow, level=1, tip_force_N=F, nonlinear=True)
    assert nl.tip_displacement_m[2] == pytest.approx(lin.tip_displacement_m[2], rel=1e-5)


def test_bad_input(narrow):
    with pytest.raises(BeamInputError, match="level"):
        solid_modal(narrow, level=-1)
    with pytest.raises(BeamInputError, match="n_modes"):
        solid_modal(narrow, n_modes=0)
    with pytest.raises(BeamInputError, match="tip_force_N"):
        solid_static(narrow, tip_force_N=np.array([1.0]))
