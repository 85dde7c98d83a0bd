"""A truth one can judge: per-mode error estimates checked against finer meshes and a converged
plate table, the gap to 1D beam theory checked against closed-form Euler-Bernoulli frequencies,
the refusal of a coarse truth, and the beam fingerprint that keeps a truth with its beam."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from paths import BEAMS
from reference import BETA_L as REF_BETA_L
from reference import SQUARE_PLATE

from prbdm_pin.cli import main
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.truth import CoarseTruthError, compute_modal, compute_truth
from prbdm_pin.truth.modes import mac_matrix

# converged Kirchhoff cantilever square plate, nu = 0.3, omega a^2 sqrt(rho h / D): modes 1
# (first bending), 3 (second bending) and 4 (chordwise), the symmetric ones (reference table)
SQUARE_TABLE = SQUARE_PLATE[[0, 2, 3]]
BETA_L = REF_BETA_L[:5]


def _true_error_pct(beam, truth, level: int) -> np.ndarray:
    """Error of the truth's selected frequencies against the same modes on a finer nested mesh
    (matched by MAC at the coarse nodes), %."""
    fine = compute_modal(beam, truth.modal.model.replace("plate-argyris", "plate"), level, 25)
    n0 = truth.modal.node_uz.shape[1]
    j = mac_matrix(truth.modal.node_uz[truth.mode_index], fine.node_uz[:, :n0]).argmax(axis=1)
    return 100.0 * np.abs(truth.omega_rad_s / fine.omega_rad_s[j] - 1.0)


def test_square_plate_estimate_bounds_the_error_against_the_converged_table():
    beam = load_beam(BEAMS / "square-plate.json")
    mat = beam.material
    D = mat.E_Pa * beam.thickness_m**3 / (12 * (1 - mat.nu**2))
    scale = beam.length_m**2 * math.sqrt(mat.rho_kg_m3 * beam.thickness_m / D)
    # Argyris selects the chordwise mode 4 as its third of five; coarse Morley misses it
    for model, level, modes, n in (("plate", 0, 5, 3), ("plate-morley", 1, 2, 2)):
        r = compute_truth(beam, model=model, modes=modes, mesh_level=level, static=False,
                          error_tol_pct=None)
        err = 100.0 * np.abs(r.omega_rad_s[:n] * scale / SQUARE_TABLE[:n] - 1.0)
        # the table's 5 digits are good to 0.0015 %, below the estimate's 0.01 % floor
        assert np.all(err <= r.error_estimate_pct[:n]), (model, err, r.error_estimate_pct)
        assert r.error_estimate_level == level + 1
    # sharp for Argyris: the estimate sits at its floor, not at the Morley bracket's percent
    assert np.all(compute_truth(beam, modes=3, static=False).error_estimate_pct <= 0.01)


def test_square_plate_estimate_bounds_the_error_against_level_2():
    beam = load_beam(BEAMS / "square-plate.json")
    r = compute_truth(beam, modes=5, static=False)
    assert np.all(_true_error_pct(beam, r, 2) <= r.error_estimate_pct)


@pytest.mark.slow
def test_reference_beam_estimate_bounds_the_error_against_level_2():
    """Level 2 of the reference panel: 180k DOFs, about a minute of CPU time."""
    beam = load_beam(BEAMS / "reference-random.json")
    r = compute_truth(beam, modes=5, static=False)
    true = _true_error_pct(beam, r, 2)
    assert np.all(true <= r.error_estimate_pct), (true, r.error_estimate_pct)


def test_coarse_truth_is_refused_unless_accepted(tmp_path, capsys):
    """Morley at level 0 on the tapered panel is 12 % low on mode 5 (Argyris level 2: 4185.05
    rad/s); its estimate says so and the truth is refused, in the API and the CLI."""
    beam = load_beam(BEAMS / "tapered-linear.json")
    with pytest.raises(CoarseTruthError, match="raise the mesh level"):
        compute_truth(beam, model="plate-morley", mesh_level=0, static=False)
    r = compute_truth(beam, model="plate-morley", mesh_level=0, static=False,
                      error_tol_pct=None)
    true = 100 * abs(r.omega_rad_s[-1] / 4185.05413 - 1)
    assert 10 < true <= r.error_estimate_pct[-1]
    out = tmp_path / "t"
    argv = ["truth", str(BEAMS / "tapered-linear.json"), "--model", "plate-morley", "--mesh",
            "0", "--no-static", "--out", str(out), "-q"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--mesh 1" in err
    assert not (out / "truth.json").exists()
    assert main(argv + ["--accept-coarse"]) == 0
    d = json.loads((out / "truth.json").read_text())
    assert d["error_estimate_pct"][-1] == pytest.approx(r.error_estimate_pct[-1])


def test_cached_truth_carries_its_estimate_and_is_judged_on_load(tmp_path, monkeypatch):
    beam = load_beam(BEAMS / "uniform-narrow.json")
    first = compute_truth(beam, modes=3, static=False, cache_dir=tmp_path)
    from prbdm_pin.truth import plate

    def no_solve(*a, **k):
        raise AssertionError("a cached truth was recomputed")

    monkeypatch.setattr(plate, "plate_modes", no_solve)
    hit = compute_truth(beam, modes=3, static=False, cache_dir=tmp_path)
    assert np.array_equal(hit.error_estimate_pct, first.error_estimate_pct)
    with pytest.raises(CoarseTruthError):
        compute_truth(beam, modes=3, static=False, cache_dir=tmp_path, error_tol_pct=1e-3)


def test_gap_to_beam_theory_and_its_cause():
    """uniform-narrow: the plate sits 0.3-0.45 % above closed-form Euler-Bernoulli (the clamped
    Poisson effect); the square plate's and the reference panel's gaps are plate action or modes
    without a 1D counterpart."""
    beam = load_beam(BEAMS / "uniform-narrow.json")
    r = compute_truth(beam, modes=5, static=False)
    b, t, L = 0.05, 0.01, 1.0
    w_eb = BETA_L**2 * math.sqrt(205e9 * b * t**3 / 12 / (7850.0 * b * t * L**4))
    assert r.beam_gap_pct == pytest.approx(100 * (w_eb / r.omega_rad_s - 1), abs=2e-3)
    assert np.all((-0.5 < r.beam_gap_pct) & (r.beam_gap_pct < -0.25))
    assert all("clamped Poisson" in c for c in r.beam_gap_cause)
    square = compute_truth(load_beam(BEAMS / "square-plate.json"), modes=5, static=False)
    assert square.beam_gap_cause[0].startswith("plate action")
    assert square.beam_gap_pct[0] < -3.0
    assert "chordwise" in square.beam_gap_cause[2]


def test_truth_json_records_estimate_gap_and_fingerprint(tmp_path, capsys):
    out = tmp_path / "t"
    assert main(["truth", str(BEAMS / "uniform-narrow.json"), "--modes", "3",
                 "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "clamped Poisson effect" in text and "error est." in text
    d = json.loads((out / "truth.json").read_text())
    beam = load_beam(BEAMS / "uniform-narrow.json")
    assert d["beam_fingerprint"] == beam.fingerprint()
    assert len(d["error_estimate_pct"]) == len(d["beam_gap_pct"]) == 3
    assert d["large_deflection"] == "calibrated-elastica"
    # the small-load theory gap is the ratio of two independent linear solves
    from prbdm_pin.truth.beam_static import beam_static
    from prbdm_pin.truth.plate_static import plate_static

    ratio = beam_static(beam).tip_displacement_m[2] / plate_static(beam).tip_displacement_m[2]
    assert d["static_theory_gap_pct"] == pytest.approx(100 * (ratio - 1), rel=1e-9)


@pytest.fixture(scope="module")
def narrow_truth(tmp_path_factory):
    out = tmp_path_factory.mktemp("truth")
    assert main(["truth", str(BEAMS / "uniform-narrow.json"), "--model", "beam", "--modes", "2",
                 "--out", str(out), "-q"]) == 0
    return out / "truth.json"


@pytest.mark.parametrize("command", ["fit", "pareto"])
def test_truth_of_another_beam_is_refused(narrow_truth, tmp_path, capsys, command):
    other = load_beam(BEAMS / "tapered-linear.json")
    extra = ["--starts", "2"] if command == "fit" else ["--pop", "8", "--generations", "2"]
    rc = main([command, str(BEAMS / "tapered-linear.json"), "--joints", "2", "--stiffness",
               "joint", *extra, "--truth", str(narrow_truth), "--out", str(tmp_path / "x"), "-q"])
    assert rc == 2
    err = capsys.readouterr().err
    mine = json.loads(narrow_truth.read_text())["beam_fingerprint"]
    assert mine in err and other.fingerprint() in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x" / "fit.json").exists()


def test_truth_of_the_same_beam_is_used(narrow_truth, tmp_path):
    rc = main(["fit", str(BEAMS / "uniform-narrow.json"), "--joints", "2", "--stiffness",
               "joint", "--starts", "2", "--truth", str(narrow_truth), "--out",
               str(tmp_path / "x"), "-q"])
    assert rc == 0
    d = json.loads((tmp_path / "x" / "fit.json").read_text())
    truth = json.loads(narrow_truth.read_text())
    assert d["omega_truth_rad_s"] == pytest.approx(truth["omega_rad_s"][:2])


def test_truth_request_carries_the_tolerance():
    from prbdm_pin.errors import BeamInputError
    from prbdm_pin.truth import TruthRequest

    req = TruthRequest(error_tol_pct=None)
    assert TruthRequest.from_dict(req.to_dict()) == req
    assert TruthRequest.from_dict({"model": "plate"}).error_tol_pct == 0.5
    with pytest.raises(BeamInputError, match="error_tol_pct"):
        TruthRequest.from_dict({"error_tol_pct": "0.5"})
    with pytest.raises(BeamInputError, match="error_tol_pct"):
        compute_truth(load_beam(BEAMS / "uniform-narrow.json"), error_tol_pct=0.0)


def test_the_estimate_is_skipped_where_the_next_level_is_too_large(monkeypatch):
    """A plate truth whose next mesh level would exceed the DOF cap gets no estimate (and no
    refusal), and says why; the cap is lowered here so that a small strip triggers it."""
    beam = load_beam(BEAMS / "uniform-narrow.json")
    monkeypatch.setenv("PRBDM_MAX_ESTIMATE_DOFS", "100")
    r = compute_truth(beam, modes=2, static=False)
    assert r.error_estimate_pct is None
    assert any("next mesh level" in w and "DOFs" in w for w in r.warnings)
    monkeypatch.undo()
    r = compute_truth(beam, modes=2, static=False)
    assert r.error_estimate_pct is not None and np.all(r.error_estimate_pct >= 0.01)
