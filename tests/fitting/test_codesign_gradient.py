"""Co-design through truth -> fit -> PRBDM: the chained gradient against central differences of
the whole chain, against the truth's own frequency gradient, and the example script's optimum
against the truth and against a derivative-free optimiser."""

from __future__ import annotations

import importlib.util
import json
import sys

import numpy as np
import pytest
from paths import ROOT
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError
from prbdm_pin.fitting.codesign import codesign_point, panel_mass
from prbdm_pin.fitting.design_derivatives import fit_design_gradient


def _script():
    spec = importlib.util.spec_from_file_location("codesign_gradient",
                                                  ROOT / "scripts" / "codesign_gradient.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules["codesign_gradient"] = mod  # its dataclasses look their module up
    spec.loader.exec_module(mod)
    return mod


CG = _script()
PROBLEM = CG.CodesignProblem(CG.planform(pp.load_beam(CG.BEAM), CG.VERTICES))
# a design inside the box away from the start and from every bound: thickness, half-widths
P = np.array([0.0055, 0.052, 0.041, 0.022, 0.012])
# central differences of the whole chain (truth solve, unique fit and model at p +- h), step
# 1e-3 x Design.scales. The differences themselves scatter: between steps 3e-4, 1e-3 and 3e-3
# they moved by up to 1.1e-5 (omega_1) and 1.8e-5 (tip) of each output's largest derivative,
# the fit's convergence tolerance seen through the step; the chained gradient's distance to
# them is the same size (measured 1.1e-5 and 2.5e-6 at this step)
FD_STEP_REL = 1e-3
FD_TOL = 1e-4


def test_chained_gradient_equals_central_differences_of_the_chain():
    d = PROBLEM.design
    c = codesign_point(d, P)
    grad = np.vstack([c.d_omega_rad_s, c.d_tip_deflection_m, c.d_mass_kg])
    fd = np.empty_like(grad)
    for j in range(d.size):
        e = np.zeros(d.size)
        e[j] = FD_STEP_REL * d.scales[j]
        a = codesign_point(d, P + e, gradient=False)
        b = codesign_point(d, P - e, gradient=False)
        fd[:, j] = np.r_[a.omega_rad_s - b.omega_rad_s, a.tip_deflection_m - b.tip_deflection_m,
                         a.mass_kg - b.mass_kg] / (2.0 * e[j])
    err = np.max(np.abs(grad - fd), axis=1) / np.max(np.abs(fd), axis=1)
    assert np.all(err[:-1] < FD_TOL), err
    # the mass is linear in each half-width and in the thickness: differences are exact
    assert err[-1] < 1e-10
    # every output moves: the check is not on zeros (the tip half-width softens the tip least)
    assert np.all(np.abs(grad[:-1]) > 1e-3 * np.max(np.abs(grad[:-1]), axis=1)[:, None])


def test_model_frequency_gradient_is_the_truths():
    # the unique fit matches the truth's frequencies at every design, so the model's chained
    # frequency gradient (IFT of the fit + model sensitivities + sections at fixed parameters)
    # must be the truth's analytic one; measured 6e-10 of each mode's largest entry (the
    # nested central differences of G_z inside the chain; G_p and the model's direct term are
    # analytic)
    d = PROBLEM.design
    c = codesign_point(d, P)
    g = pp.truth_gradient(d.beam_at(P), d, model="beam", modes=3, static=False)
    assert np.allclose(c.omega_rad_s, g.omega_rad_s, rtol=1e-9, atol=0.0)
    err = (np.max(np.abs(c.d_omega_rad_s - g.d_omega_rad_s), axis=1)
           / np.max(np.abs(g.d_omega_rad_s), axis=1))
    assert np.all(err < 1e-8), err


def test_panel_mass_gradient_at_a_width_step():
    beam = pp.load_beam(ROOT / "examples" / "beams" / "stepped-narrow.json")
    d = pp.Design(beam, ("x[1]", "half_width[0]", "half_width[2]", "thickness", "rho"))
    p = d.values
    m, dm = panel_mass(d, p)
    # the mass is linear in each variable alone: a difference over a finite step is exact
    for j in range(d.size):
        e = np.zeros(d.size)
        e[j] = 0.1 * d.scales[j]
        fd = (d.beam_at(p + e).mass_kg - d.beam_at(p - e).mass_kg) / (2.0 * e[j])
        # both masses are exact to a few EPS m, so their difference over 2 e[j] to ~EPS m / e[j]
        # (3e-15 relative measured); kept: the test's 1e-12 (relative and of m)
        assert dm[j] == pytest.approx(fd, rel=5000 * EPS, abs=5000 * EPS * m)
    # and by hand: the step at x = 0.4 m moves from the wide (0.02 m) to the narrow (0.01 m)
    # side, rho t (2 (0.02 - 0.01)) per metre
    # three factors on each side (exact here); kept: the test's 1e-12
    assert dm[0] == pytest.approx(beam.material.rho_kg_m3 * beam.thickness_m * 0.02,
                                  rel=5000 * EPS)


def test_fit_design_gradient_refuses_fits_it_cannot_differentiate():
    d = PROBLEM.design
    beam = d.beam_at(P)
    g = pp.truth_gradient(beam, d, model="beam", modes=3, static=False)
    target = pp.FitTarget(g.omega_rad_s, beam.tip_force_N)
    multi = pp.fit(beam, target, 3, stiffness="joint", starts=2, progress=False)
    with pytest.raises(BeamInputError, match="unique = 'nearest'"):
        fit_design_gradient(multi, d, P, g)
    uniq = pp.fit(beam, target, 3, stiffness="joint", unique="nearest", progress=False)
    other = pp.truth_gradient(beam, ("thickness",), model="beam", modes=3, static=False)
    with pytest.raises(BeamInputError, match="truth.names"):
        fit_design_gradient(uniq, d, P, other)
    elsewhere = pp.truth_gradient(d.beam_at(P * 1.01), d, model="beam", modes=3, static=False)
    with pytest.raises(BeamInputError, match="not the truth's"):
        fit_design_gradient(uniq, d, P * 1.01, elsewhere)
    with pytest.raises(BeamInputError, match="truth_model"):
        codesign_point(d, P, truth_model="solid")


# The PRBDM's large-deflection tip is not fitted (an eigen fit): its error against the truth's
# elastica is a model error. Measured on 20 random designs of the box: -1.15 % to +1.13 %; at the
# optimum +1.54 % (narrow tip). Twice the largest:
TIP_ERROR_BOUND = 0.03


def test_slsqp_optimum_holds_on_the_truth():
    ev, res, _ = CG.run_slsqp(PROBLEM)
    assert res.success, res.message
    c = ev.point(res.x)
    g = CG.constraints_of(PROBLEM, c)
    # feasible on the model, and both constraints active (the thickness and the tip
    # half-width on their bounds, three half-widths free)
    assert np.all(g > -CG.FEAS_TOL) and np.all(np.abs(g) < CG.FEAS_TOL), g
    assert c.values[0] == pytest.approx(PROBLEM.thickness_range_m[1], rel=1e-9)
    assert c.values[-1] == pytest.approx(PROBLEM.half_width_range_m[0], rel=1e-9)
    assert len(ev.history) < 40  # measured 21 truth evaluations
    chk = CG.truth_check(PROBLEM, c.values, "beam")
    # frequencies: the fit matches the truth exactly, so the truth holds the floor as the
    # model does (to the feasibility tolerance)
    assert chk.omega_1_rad_s >= PROBLEM.omega_min_rad_s * (1.0 - CG.FEAS_TOL)
    # tip: within the PRBDM's tip error of the limit
    assert abs(c.tip_deflection_m / chk.delta_m - 1.0) < TIP_ERROR_BOUND
    assert chk.delta_m <= PROBLEM.delta_max_m * (1.0 + CG.FEAS_TOL + TIP_ERROR_BOUND)


@pytest.mark.slow
def test_derivative_free_optimiser_finds_the_same_optimum():
    # COBYLA on the same model, without gradients (measured: 142 truth evaluations)
    ev_s, res_s, _ = CG.run_slsqp(PROBLEM)
    ev_c, res_c, _ = CG.run_cobyla(PROBLEM)
    a, b = ev_s.point(res_s.x), ev_c.point(res_c.x)
    assert a.mass_kg == pytest.approx(b.mass_kg, rel=1e-5)
    assert np.allclose(a.values, b.values, rtol=1e-3)
    assert len(ev_c.history) > 2 * len(ev_s.history)


def test_script_writes_table_figure_and_history(tmp_path, capsys):
    out = tmp_path / "cd"
    assert CG.main(["--out", str(out), "--maxiter", "4", "--cobyla-maxiter", "12"]) == 0
    printed = capsys.readouterr().out
    text = (out / "codesign_gradient.md").read_text()
    assert printed.strip() in text
    assert (out / "convergence.png").stat().st_size > 10_000
    hist = json.loads((out / "history.json").read_text())
    assert set(hist) == {"SLSQP (chained gradients)", "COBYLA (derivative-free)"}
    # each run's count of truth evaluations in the table is its history's
    for name, h in hist.items():
        row = next(line for line in text.splitlines() if line.startswith(f"| {name} |"))
        assert row.split("|")[2].strip().startswith(f"{len(h['history'])} ")
    assert len(hist["COBYLA (derivative-free)"]["history"]) == 12
    # the rows give each optimiser's last design with the 1D beam truth and the plate there
    assert sum(line.startswith("| | ") for line in text.splitlines()) == 2
