"""``prbdm simulate --compare-truth`` end to end on a 3R fit to uniform-narrow.json.

Independent references: the Euler-Bernoulli closed form of the uniform cantilever (the beam
truth's step and FRF errors), the plate's linear static solve and L^3 / (3 E I) with the closed-form
share of the static compliance in modes above the third (the static limit of each truth's FRF).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from reference import BETA_L as REF_BETA_L
from tolerances import EPS

from prbdm_pin.cli import main
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.files.fit_file import load_fit
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.simulation.response import (
    dynamic_accuracy,
    euler_bernoulli_modal_tip,
    truth_modal_tip,
)

BEAM = "examples/beams/uniform-narrow.json"
# roots of cos(x) cosh(x) = -1: the clamped-free beam's first three modes
BETA_L = REF_BETA_L[:3]
# share of the static tip compliance L^3 / (3 E I) carried by modes 4, 5, ...: mode k carries
# 12 / (beta_k L)^4
EB_TAIL_3 = 1.0 - float(np.sum(12.0 / BETA_L**4))
ERRORS = ("step_error", "frf_error", "frf_magnitude_error", "frf_phase_error_rad")


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """A 3R eigen fit against the plate truth, then both comparisons, sharing one cache."""
    d = tmp_path_factory.mktemp("simulate")
    cache = d / "cache"
    assert main(["fit", BEAM, "--joints", "3", "--objective", "eigen", "--stiffness", "joint",
                 "--starts", "2", "--seed", "0", "--cache-dir", str(cache),
                 "--out", str(d / "fit"), "-q"]) == 0
    out = {}
    for truth in ("plate", "beam"):
        assert main(["simulate", str(d / "fit" / "fit.json"), "--duration", "0.05",
                     "--tip-force", "0,0,-10", "--compare-truth", "--truth-model", truth,
                     "--cache-dir", str(cache), "--out", str(d / truth), "-q"]) == 0
        out[truth] = json.loads((d / truth / "truth_comparison.json").read_text())
    beam = load_beam(BEAM)
    fit = load_fit(d / "fit" / "fit.json")
    model = build_model(beam, fit.lengths_m, fit.stiffness_Nm_per_rad)
    return d, cache, beam, model, out


def test_beam_truth_errors_match_the_euler_bernoulli_closed_form(run):
    _, _, beam, model, out = run
    s = out["beam"]
    assert s["truth"]["model"] == "beam" and s["truth"]["superposed_modes"] == 3
    acc = dynamic_accuracy(model, euler_bernoulli_modal_tip(beam, 3), damping_ratio=0.02)
    # the beam truth's frequencies are within 1e-8 and its tip gains within 2e-4 of the closed
    # form (mass-per-length quadrature): the L2 errors move by ~1e-6 (measured 2e-6 at most) ...
    for key in ERRORS[:3]:
        assert s[key] == pytest.approx(getattr(acc, key), abs=2e-5), key
    # ... the rms phase more: the gains place the antiresonances, where the phase swings by
    # about pi over a width ~ 2 xi omega, so a 2e-4 shift there moves it by up to ~1e-2 rad
    # locally (measured 6e-5 rad rms over the band)
    assert s["frf_phase_error_rad"] == pytest.approx(acc.frf_phase_error_rad, abs=5e-4)
    assert s["band_rad_s"][1] == pytest.approx(acc.omega_band_rad_s[-1], rel=1e-6)
    assert 0.01 < s["step_error"] < 0.5  # a 3R eigen fit does not match the tip gains
    # static limit of the 3-mode FRF: L^3 / (3 E I) less the modes above the third
    static_eb = beam.length_m**3 / (3.0 * beam.root_EI_Nm2)
    assert s["truth_frf_static_limit_m_per_N"] / static_eb - 1.0 == pytest.approx(
        -EB_TAIL_3, abs=1e-5)


def test_plate_truth_is_the_cached_fit_truth_and_matches_dynamic_accuracy(run):
    _, cache, beam, model, out = run
    from prbdm_pin.truth import compute_truth

    s = out["plate"]
    assert s["truth"]["model"] == "plate" and s["truth"]["solver"] == "plate-argyris"
    assert s["truth"]["modal_masses"] == "finite-element"
    # one plate entry (shared by `prbdm fit` and `prbdm simulate`) and one beam entry
    assert len(list(cache.glob("truth-*.npz"))) == 2
    truth = compute_truth(beam, modes=3, cache_dir=cache)
    # exact by construction: the cached truth, the same accuracy call and band, written as
    # JSON; slack 5 EPS and 5000 EPS (the test's 1e-15 and 1e-12)
    assert s["truth"]["selected_omega_rad_s"] == pytest.approx(truth.omega_rad_s, rel=5 * EPS)
    acc = dynamic_accuracy(model, truth_modal_tip(truth, beam), damping_ratio=0.02)
    for key in ERRORS:
        assert s[key] == pytest.approx(getattr(acc, key), rel=5000 * EPS), key
    assert s["band_rad_s"][1] == pytest.approx(1.2 * truth.omega_rad_s[2], rel=5000 * EPS)
    # the plate and beam truths differ (plate 0.3 % stiffer in frequency), so do the errors
    assert s["frf_error"] != pytest.approx(out["beam"]["frf_error"], rel=1e-3)


def test_plate_frf_static_limit_is_the_static_solve_less_the_higher_modes(run):
    """H(0) of the superposition against an independent linear solve of the plate: on this
    strip the modes above the third carry the Euler-Bernoulli share of the compliance."""
    _, _, beam, _, out = run
    from prbdm_pin.truth.plate_static import plate_static

    solve = plate_static(beam)
    compliance = float(solve.tip_displacement_m[2] / beam.tip_force_N[2])
    s = out["plate"]
    # exact by construction (the command's solve is this one); slack: the test's 1e-12
    assert s["truth"]["linear_static_compliance_m_per_N"] == pytest.approx(compliance,
                                                                           rel=5000 * EPS)
    assert s["truth_frf_static_limit_m_per_N"] / compliance - 1.0 == pytest.approx(
        -EB_TAIL_3, abs=1e-5)


def test_outputs_are_complete_and_the_cache_is_reused(run, monkeypatch):
    d, cache, _, _, _ = run
    for truth in ("plate", "beam"):
        assert (d / truth / "truth_comparison.png").stat().st_size > 10_000
        assert not [p.name for p in (d / truth).iterdir() if p.name.startswith(".")]

    def no_solve(*args, **kwargs):
        raise AssertionError("the truth was recomputed")

    monkeypatch.setattr("prbdm_pin.truth.compute_modal", no_solve)
    again = d / "again"
    assert main(["simulate", str(d / "fit" / "fit.json"), "--duration", "0.01",
                 "--compare-truth", "--cache-dir", str(cache), "--out", str(again), "-q"]) == 0
    s = json.loads((again / "truth_comparison.json").read_text())
    plate = json.loads((d / "plate" / "truth_comparison.json").read_text())
    assert s["step_error"] == plate["step_error"] and s["truth"]["model"] == "plate"


@pytest.mark.parametrize("extra, match", [
    (["--damping", "1.5"], "--damping"),
    (["--damping", "nan"], "--damping"),
])
def test_bad_damping_for_comparison_is_one_line_exit_2(run, tmp_path, capsys, extra, match):
    d = run[0]
    out = tmp_path / "x"
    assert main(["simulate", str(d / "fit" / "fit.json"), "--duration", "0.01",
                 "--compare-truth", "--out", str(out)] + extra) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and match in err
    assert not out.exists()  # refused before any work


def test_urdf_has_no_beam_to_compare(run, tmp_path, capsys):
    d = run[0]
    out = tmp_path / "x"
    assert main(["simulate", str(d / "fit" / "model.urdf"), "--duration", "0.01",
                 "--compare-truth", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--compare-truth" in err
    assert not out.exists()


def test_unknown_truth_model_is_refused(run, tmp_path):
    d = run[0]
    with pytest.raises(SystemExit) as exc:
        main(["simulate", str(d / "fit" / "fit.json"), "--duration", "0.01", "--compare-truth",
              "--truth-model", "solid", "--out", str(tmp_path / "x")])
    assert exc.value.code == 2


@pytest.fixture(scope="module")
def level1(tmp_path_factory):
    """A 2R eigen fit against the plate truth at mesh level 1 (not the default level 0)."""
    d = tmp_path_factory.mktemp("level1")
    assert main(["fit", BEAM, "--joints", "2", "--objective", "eigen", "--stiffness", "joint",
                 "--starts", "2", "--seed", "0", "--mesh-level", "1", "--cache-dir",
                 str(d / "cache"), "--out", str(d / "fit"), "-q"]) == 0
    return d


def test_comparison_uses_the_truth_the_fit_was_measured_against(level1, monkeypatch):
    from prbdm_pin.truth import TruthRequest, compute_truth

    d = level1
    fit = load_fit(d / "fit" / "fit.json")
    assert fit.truth_request == TruthRequest(model="plate", modes=2, mesh_level=1)

    def no_solve(*args, **kwargs):
        raise AssertionError("the truth was recomputed")

    with monkeypatch.context() as m:
        m.setattr("prbdm_pin.truth.compute_modal", no_solve)
        assert main(["simulate", str(d / "fit" / "fit.json"), "--duration", "0.01",
                     "--compare-truth", "--cache-dir", str(d / "cache"),
                     "--out", str(d / "sim"), "-q"]) == 0
    s = json.loads((d / "sim" / "truth_comparison.json").read_text())
    assert s["truth"]["mesh_level"] == 1 and s["truth"]["request"]["mesh_level"] == 1
    # exact by construction (the fit's recorded truth); slack 5 EPS (the test's 1e-15)
    assert s["truth"]["selected_omega_rad_s"] == pytest.approx(fit.omega_truth_rad_s,
                                                               rel=5 * EPS)
    # the default-level plate is another truth (on this strip level 0 lies ~6e-8 above level 1;
    # identical meshes repeat to ~1e-15), which the comparison did not fall back to
    default = compute_truth(load_beam(BEAM), modes=2, static=False)
    assert np.all(np.abs(default.omega_rad_s / fit.omega_truth_rad_s - 1.0) > 1e-8)


def test_asking_for_another_truth_model_overrides_the_fits(level1):
    d = level1
    assert main(["simulate", str(d / "fit" / "fit.json"), "--duration", "0.01",
                 "--compare-truth", "--truth-model", "beam", "--cache-dir", str(d / "cache"),
                 "--out", str(d / "beam"), "-q"]) == 0
    s = json.loads((d / "beam" / "truth_comparison.json").read_text())
    assert s["truth"]["model"] == "beam" and s["truth"]["request"]["mesh_level"] is None


def test_truth_request_round_trips_and_old_fits_read_without_one(level1, tmp_path):
    from prbdm_pin.errors import BeamInputError
    from prbdm_pin.fitting.results import FitResult

    d = json.loads((level1 / "fit" / "fit.json").read_text())
    assert d["truth_request"] == {"model": "plate", "modes": 2, "mesh_level": 1,
                                  "selection": "paper",
                                  # the default large-deflection truth and error tolerance
                                  # since issue 12
                                  "large_deflection": "calibrated-elastica",
                                  "error_tol_pct": 0.5}
    assert FitResult.from_dict(d).to_dict()["truth_request"] == d["truth_request"]
    old = {k: v for k, v in d.items() if k != "truth_request"}
    assert FitResult.from_dict(old).truth_request is None
    for bad in ({"model": 3}, {"modes": "2"}, {"mesh": 1}, [1, 2]):
        with pytest.raises(BeamInputError, match="truth_request"):
            FitResult.from_dict({**d, "truth_request": bad})
