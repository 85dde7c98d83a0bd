"""Design gradients of the truth against finite differences of the full truth on a fixed topology,
and against the closed-form scalings in thickness, E and rho."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from paths import BEAMS
from skfem import MeshTri

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError, TruthError
from prbdm_pin.truth.beam import beam_modes, beam_stations
from prbdm_pin.truth.beam_static import beam_static
from prbdm_pin.truth.derivative_rules import check_gaps
from prbdm_pin.truth.mesh import planform_tri_mesh
from prbdm_pin.truth.morph import morph_plane, morph_x
from prbdm_pin.truth.plate import plate_modes
from prbdm_pin.truth.plate_derivatives import plate_sensitivity
from prbdm_pin.truth.plate_static import plate_static

# finite differences of the truth: sixth-order central stencil, step FD_REL x the variable's
# scale (``Design.scales``). The truth's own rounding sets the step from below: moving the nodes
# by one ulp changes a frequency or the tip by 1e-10 (tapered) to 1e-7 (reference panel, plate),
# and the stencil divides that by the step; its truncation sets the step from above (5e-4 at
# 0.1). The rounding comes from the plate mesh's grading towards the corners (elements down to
# 1/16 of the local size; 4e-10 on the reference panel's mesh without it) and, for the 1D beam,
# from its stiffness matrix's conditioning.
FD_REL = 3e-2
TOL = 1e-5
# Where the truth's rounding is 1e-8 or more (the stepped plate, the reference panel) the
# finite differences themselves scatter: between steps of 1e-2 and 3e-2 of the scale the
# same entries moved by up to 1.5e-4 (stepped plate, ungraded mesh), 9e-4 (reference panel,
# 1D beam) and 4e-5 (reference panel, ungraded plate) while the gradients they are compared with
# change by less than 1e-6 when their own step changes tenfold; this bound is the scatter of the
# reference, not of the gradient.
TOL_NOISY = 1e-3


def _beam(name: str) -> pp.Beam:
    return pp.load_beam(BEAMS / f"{name}.json")


def _fixed_topology_truth(beam: pp.Beam, model: str, index: np.ndarray, mesh=None):
    """The full truth of designs of ``beam`` on ``beam``'s own mesh, moved with the planform."""
    if model == "plate":
        mesh = planform_tri_mesh(beam, 0) if mesh is None else mesh

        def truth(b):
            moved = MeshTri(morph_plane(beam, b, mesh.p), mesh.t)
            pm = plate_modes(b, 0, int(index.max()) + 3, "argyris", mesh=moved)
            return np.r_[pm.omega_rad_s[index], plate_static(b, 0, mesh=moved)
                         .tip_displacement_m[2]]
    else:
        xs = beam_stations(beam, 200)

        def truth(b):
            x = morph_x(beam, b, xs)
            lam = beam_modes(b, int(index.max()) + 3, 200, x)[6]
            return np.r_[np.sqrt(lam[index]), beam_static(b, stations_m=x).tip_displacement_m[2]]
    return truth


def _fd_check(name: str, model: str, variables: tuple[str, ...], tol: float = TOL,
              corner_passes: int | None = None) -> None:
    beam = _beam(name)
    design = pp.Design(beam, variables)
    if corner_passes is None:
        g = pp.truth_gradient(beam, design, model=model, modes=3)
        mesh = None
    else:  # the plate on a mesh with less grading towards the corners than the truth's own
        mesh = planform_tri_mesh(beam, 0, corner_passes=corner_passes)
        r = plate_sensitivity(design, 0, 3, "paper", 25, True, mesh=mesh)
        g = SimpleNamespace(**r)
    truth = _fixed_topology_truth(beam, model, g.mode_index, mesh)
    value = np.r_[g.omega_rad_s, g.tip_z_m]
    errs = {}
    p0 = design.values
    for j, name_j in enumerate(design.names):
        h = FD_REL * design.scales[j]
        f = {}
        for k in (-3, -2, -1, 1, 2, 3):
            p = p0.copy()
            p[j] += k * h
            f[k] = truth(design.beam_at(p))
        fd = (45 * (f[1] - f[-1]) - 9 * (f[2] - f[-2]) + (f[3] - f[-3])) / (60 * h)
        got = np.r_[g.d_omega_rad_s[:, j], g.d_tip_z_m[j]]
        # relative to the derivative, or to value / scale where the derivative is nearly zero
        # (a relative sensitivity below 1e-2, whose own relative error is rounding)
        ref = np.maximum(np.abs(fd), 1e-2 * np.abs(value) / design.scales[j])
        errs[name_j] = np.abs(got - fd) / ref
    assert all(np.all(e <= tol) for e in errs.values()), (name, model, errs)


@pytest.mark.parametrize("model", ["plate", "beam"])
def test_tapered_against_finite_differences(model):
    _fd_check("tapered", model, ("half_width[0]", "half_width[1]", "nu", "thickness"))


@pytest.mark.parametrize("model", ["plate", "beam"])
def test_stepped_against_finite_differences(model):
    _fd_check("stepped-narrow", model, ("half_width[0]", "half_width[1]", "half_width[2]",
                                        "half_width[3]", "x[2]"),
              TOL if model == "beam" else TOL_NOISY)


def test_stepped_plate_ungraded_mesh_against_finite_differences():
    # the same panel on a mesh without corner grading (rounding 4e-9 instead of 9e-8)
    _fd_check("stepped-narrow", "plate", ("half_width[0]", "half_width[1]", "half_width[2]",
                                         "half_width[3]", "x[2]", "nu"), TOL_NOISY,
              corner_passes=0)


def test_reference_beam_against_finite_differences():
    _fd_check("reference-random", "beam", ("half_width[0]", "half_width[6]", "x[3]", "x[9]"),
              TOL_NOISY)


@pytest.mark.slow
def test_reference_plate_against_finite_differences():
    # on the truth's graded mesh (rounding 1e-7) the finite differences scatter by 5e-4 and
    # more: the panel's own mesh without the corner grading (rounding 4e-10)
    _fd_check("reference-random", "plate", ("half_width[0]", "half_width[6]", "x[3]", "x[9]"),
              TOL_NOISY, corner_passes=0)


@pytest.mark.parametrize("name", ["reference-random", "tapered", "stepped-narrow"])
@pytest.mark.parametrize("model", ["plate", "beam"])
def test_closed_form_scalings(name, model):
    # K ~ E t^3, M ~ rho t: omega ~ t sqrt(E / rho), the linear tip ~ 1 / (E t^3), no rho
    beam = _beam(name)
    g = pp.truth_gradient(beam, ("thickness", "E", "rho"), model=model, modes=3)
    np.testing.assert_allclose(g.relative_d_omega, np.tile([1.0, 0.5, -0.5], (3, 1)),
                               rtol=0, atol=1e-10)
    np.testing.assert_allclose(g.relative_d_tip_z, [-3.0, -1.0, 0.0], rtol=0, atol=1e-10)


def test_nu_does_not_move_the_1d_beam():
    g = pp.truth_gradient(_beam("tapered"), ("nu",), model="beam", modes=2)
    assert np.all(g.d_omega_rad_s == 0.0) and g.d_tip_z_m[0] == 0.0


@pytest.mark.parametrize("model", ["plate", "beam"])
def test_values_are_the_truths(model):
    beam = _beam("tapered")
    g = pp.truth_gradient(beam, ("thickness",), model=model, modes=3)
    r = pp.compute_truth(beam, model=model, modes=3, error_tol_pct=None)
    np.testing.assert_allclose(g.omega_rad_s, r.omega_rad_s, rtol=1e-9)
    np.testing.assert_array_equal(g.mode_index, r.mode_index)
    np.testing.assert_allclose(g.tip_z_m, r.static_linear.tip_displacement_m[2], rtol=1e-9)


def test_bad_designs_refused():
    beam = _beam("stepped-narrow")
    with pytest.raises(BeamInputError, match="x\\[0\\]"):
        pp.truth_gradient(beam, ("x[0]",))
    with pytest.raises(BeamInputError, match="tip station"):
        pp.truth_gradient(beam, ("x[3]",))
    with pytest.raises(BeamInputError, match="'width'"):
        pp.truth_gradient(beam, ("width",))
    with pytest.raises(BeamInputError, match="model"):
        pp.truth_gradient(beam, ("thickness",), model="solid")
    with pytest.raises(BeamInputError, match="modes"):
        pp.truth_gradient(beam, ("thickness",), modes=0)


def test_repeated_eigenvalue_refused():
    lam = np.array([1.0, 4.0, 4.0 * (1 + 1e-9), 9.0])
    check_gaps("b", lam, np.array([0, 3]))
    with pytest.raises(TruthError, match="repeated"):
        check_gaps("b", lam, np.array([0, 1]))
