"""The elastica's large-deflection tip gradients against central finite differences of
``elastica_static`` and against the elastica's load scaling."""


import numpy as np
import pytest
from elastica_differences import REL, TOL, check, fd_design, fd_force
from paths import BEAMS
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError
from prbdm_pin.member.geometry import Beam
from prbdm_pin.truth.elastica import elastica_static


def _steel():
    return pp.load_beam(BEAMS / "tapered.json").material


def _tapered() -> Beam:
    """Four vertices, tapering by kinks; a combined tip load (F_x and F_z)."""
    return Beam(np.array([0.0, 0.2, 0.45, 0.6]), np.array([0.05, 0.04, 0.03, 0.02]), 0.005,
                _steel(), np.array([-100.0, 0.0, -300.0]), "tapered-kinked", "")


def _stepped() -> Beam:
    """A width step at x = 0.5 m between kinked spans."""
    return Beam(np.array([0.0, 0.25, 0.5, 0.5, 0.8, 1.0]),
                np.array([0.02, 0.019, 0.017, 0.01, 0.009, 0.008]), 0.005, _steel(),
                np.array([0.0, 0.0, -150.0]), "stepped-kinked", "")


def test_uniform_strip_against_differences_and_the_classical_tip():
    beam = pp.load_beam(BEAMS / "uniform-narrow.json")  # P L^2 / EI = 1
    names = ("thickness", "half_width[0]", "half_width[1]", "E", "rho", "nu")
    g = pp.elastica_gradient(beam, names, tol=TOL)
    # the classical elastica at P L^2 / EI = 1 (Bisshopp & Drucker)
    L = beam.length_m
    assert g.tip_position_m[0] == pytest.approx(L * (1 - 0.056433), abs=2e-6 * L)
    assert g.tip_position_m[2] == pytest.approx(-0.301721 * L, abs=2e-6 * L)
    ref = fd_design(beam, names[:3])
    check(g.d_tip_position_m[:, :3], ref)
    # rho and nu do not enter the plain elastica
    assert np.all(g.d_tip_position_m[:, 4:] == 0.0)
    assert np.all(g.d_tip_position_m[1] == 0.0)


def test_thickness_and_modulus_follow_from_the_load_scaling():
    """The tip depends on F / EI only and EI is proportional to E t^3: d r / d t =
    -(3 / t) F . d r / d F and d r / d E = -(1 / E) F . d r / d F, with d r / d F from finite
    differences in the load (an independent check of the design gradient and of the analytic
    load gradient)."""
    beam = pp.load_beam(BEAMS / "uniform-narrow.json")
    g = pp.elastica_gradient(beam, ("thickness", "E"), tol=TOL)
    dF = fd_force(beam)
    check(g.d_tip_d_force_m_per_N[[0, 2]], dF[[0, 2]])
    F = beam.tip_force_N[[0, 2]]
    along = dF @ F
    t, E = beam.thickness_m, beam.material.E_Pa
    scale = np.abs(along).max()
    assert np.abs(g.d_tip_position_m[:, 0] + 3.0 / t * along).max() < REL * 3.0 / t * scale
    assert np.abs(g.d_tip_position_m[:, 1] + along / E).max() < REL * scale / E


def test_tapered_combined_load_against_differences():
    beam = _tapered()
    names = ("half_width[1]", "half_width[3]", "x[1]", "x[2]")
    g = pp.elastica_gradient(beam, names, tol=TOL)
    check(g.d_tip_position_m, fd_design(beam, names))
    check(g.d_tip_d_force_m_per_N, fd_force(beam))


def test_stepped_against_differences_with_a_moved_step():
    beam = _stepped()
    names = ("x[3]", "half_width[2]", "half_width[3]", "x[4]")  # x[3] moves the step
    g = pp.elastica_gradient(beam, names, tol=TOL)
    check(g.d_tip_position_m, fd_design(beam, names))


def test_fixed_ei_scale_against_differences():
    beam = pp.load_beam(BEAMS / "stepped-narrow.json")
    names = ("x[1]", "half_width[0]")
    g = pp.elastica_gradient(beam, names, ei_scale=0.9, tol=TOL)
    # exact by construction: elastica_static is the same primal solve; slack 5000 EPS L
    # (the test's 1e-12 m on this 1 m beam)
    assert np.allclose(g.tip_position_m,
                       elastica_static(beam, tol=TOL, ei_scale=0.9).tip_position_m,
                       rtol=0.0, atol=5000 * EPS * beam.length_m)
    check(g.d_tip_position_m, fd_design(beam, names, ei_scale=0.9))


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        (dict(design=("depth",)), "depth"),
        (dict(design=("x[0]",)), "x[0]"),
        (dict(design=("thickness",), tol=0.0), "tol"),
        (dict(design=("thickness",), tol=True), "tol"),
        (dict(design=("thickness",), ei_scale=-1.0), "ei_scale"),
        (dict(design=("thickness",), tip_force_N=[0.0, 5.0, -1.0]), "tip_force_N[1]"),
        (dict(design=("thickness",), tip_force_N=[0.0, np.nan]), "tip_force_N"),
        (dict(design=("thickness",), anticlastic="yes"), "anticlastic"),
    ],
)
def test_bad_input_is_named(kwargs, field):
    beam = pp.load_beam(BEAMS / "uniform-narrow.json")
    with pytest.raises(BeamInputError, match=field.replace("[", r"\[").replace("]", r"\]")):
        pp.elastica_gradient(beam, **kwargs)


def test_bad_beam_is_named():
    with pytest.raises(BeamInputError, match="beam"):
        pp.elastica_gradient("uniform-narrow.json", ("thickness",))


# The calibrated scale u_1D / u_plate is a ratio of two re-solved linear finite-element tips whose
# rounding (see tests/truth/test_truth_gradient.py: 4e-6 for the tapered 1D beam) the differences
# divide by the step: between steps of 1e-2 and 3e-2 of the scale the reference itself moves by
# up to 2e-5 (half_width[1]), and at 1e-1 the thickness's truncation shows (3e-4). Measured at
# 3e-2: at most 3.5e-6 relative; the bound is the reference's scatter, not the gradient's.
REL_PLATE = 1e-5


def _fd_calibrated(beam, names, rel=3e-2):
    """Central differences (sixth order) of the calibrated elastica of ``compute_truth``:
    EI scaled by u_1D / u_plate of the linear tips, the plate on the beam's mesh moved with the
    planform (fixed topology) and the 1D beam on its moved stations."""
    from skfem import MeshTri

    from prbdm_pin.truth.beam import beam_stations
    from prbdm_pin.truth.beam_static import beam_static
    from prbdm_pin.truth.mesh import planform_tri_mesh
    from prbdm_pin.truth.morph import morph_plane, morph_x
    from prbdm_pin.truth.plate_static import plate_static
    from prbdm_pin.truth.settings import DEFAULT_PLATE_LEVEL

    mesh = planform_tri_mesh(beam, DEFAULT_PLATE_LEVEL)
    xs = beam_stations(beam, 200)

    def tip(b):
        moved = MeshTri(morph_plane(beam, b, mesh.p), mesh.t)
        u_pl = plate_static(b, DEFAULT_PLATE_LEVEL, mesh=moved).tip_displacement_m[2]
        u_1d = beam_static(b, stations_m=morph_x(beam, b, xs)).tip_displacement_m[2]
        return elastica_static(b, tol=TOL, ei_scale=u_1d / u_pl).tip_position_m

    d = pp.Design(beam, names)
    p0, scales = d.values, d.scales
    sixth = ((1, 45.0), (-1, -45.0), (2, -9.0), (-2, 9.0), (3, 1.0), (-3, -1.0))
    out = np.zeros((3, d.size))
    for j in range(d.size):
        h = rel * scales[j]
        e = np.zeros(d.size)
        e[j] = h
        out[:, j] = sum(c * tip(d.beam_at(p0 + k * e)) for k, c in sixth) / (60.0 * h)
    return out


def test_plate_calibrated_scale_against_differences():
    beam = pp.load_beam(BEAMS / "tapered.json")
    names = ("nu", "thickness", "half_width[0]", "half_width[1]")
    g = pp.elastica_gradient(beam, names, ei_scale="plate", tol=TOL)
    assert g.ei_scale_source == "plate"
    # the scale is independent of t (both tips scale as 1 / t^3); nu moves only the plate
    assert g.d_ei_scale[1] == pytest.approx(0.0, abs=1e-9 * g.ei_scale / beam.thickness_m)
    ref = _fd_calibrated(beam, names)
    err = np.abs(g.d_tip_position_m - ref).max(axis=0) / np.abs(ref).max(axis=0)
    assert err.max() < REL_PLATE, err
    # nu enters through the plate's scale only: without it the elastica ignores nu
    fixed = pp.elastica_gradient(beam, names, ei_scale=g.ei_scale, tol=TOL)
    assert np.all(fixed.d_tip_position_m[:, 0] == 0.0)
    assert np.abs(g.d_tip_position_m[:, 0]).max() > 0.0


def test_plate_scale_is_the_calibrated_truths():
    """``ei_scale="plate"`` is the large-deflection tip of the truth's calibrated elastica."""
    from prbdm_pin.truth.tip_response import tip_response

    beam = pp.load_beam(BEAMS / "stepped-narrow.json")
    g = pp.elastica_gradient(beam, ("x[1]",), ei_scale="plate")
    _, calibrated, gap = tip_response(beam, "plate", 0, "calibrated-elastica")
    assert g.ei_scale == pytest.approx(1.0 + gap / 100.0, rel=1e-7)
    # the two scales' plate solves round differently (1e-8): the tips agree to that
    assert np.abs(g.tip_position_m - calibrated.tip_position_m).max() < 1e-7 * beam.length_m


def test_unknown_scale_is_named():
    beam = pp.load_beam(BEAMS / "uniform-narrow.json")
    with pytest.raises(BeamInputError, match="ei_scale"):
        pp.elastica_gradient(beam, ("thickness",), ei_scale="solid")


@pytest.mark.slow
def test_strongly_bent_strip_against_differences():
    """P L^2 / EI = 5, far beyond the linear range: the tip is lowered by about 0.7 L and
    retreats by about 0.4 L."""
    beam = pp.load_beam(BEAMS / "uniform-narrow.json")
    beam = Beam(beam.x_m, beam.half_width_m, beam.thickness_m, beam.material,
                5.0 * beam.tip_force_N, "uniform-narrow-5", "")
    names = ("thickness", "half_width[0]")
    g = pp.elastica_gradient(beam, names, tol=TOL)
    check(g.d_tip_position_m, fd_design(beam, names))
