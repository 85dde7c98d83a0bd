"""Input checks at the CLI: --min-link on fit, pareto and batch (exit 2 naming the option), a
beam without tip_force (no load: eigen fits only). The truth is an independent file (Euler-
Bernoulli frequencies and the elastica tip of uniform-narrow.json) or the 1D beam truth."""

from __future__ import annotations

import json

import numpy as np
import pytest
from tolerances import EPS

from prbdm_pin.batch import BeamTask, FitSettings, evaluate_beam
from prbdm_pin.cli import main
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.fitting import fit
from prbdm_pin.fitting.target import FitTarget
from prbdm_pin.options.objects import FitOptions

BEAM = "examples/beams/uniform-narrow.json"


@pytest.fixture(scope="module")
def truth_file(strip_truth):
    return strip_truth[0]


def _one_line_exit_2(capsys, argv, *needles):
    rc = main(argv)
    err = capsys.readouterr().err.strip()
    assert rc == 2, err
    assert len(err.splitlines()) == 1, err
    for n in needles:
        assert n in err, err
    return err


@pytest.mark.parametrize("extra, needles", [
    (["--joints", "60"], ["--min-link = 0.02", "61 links", "(0, 0.01639)"]),
    (["--joints", "2", "--min-link", "0"], ["--min-link = 0", "(0, 0.3333)"]),
    (["--joints", "2", "--min-link", "0.34"], ["--min-link = 0.34", "do not fit"]),
    (["--joints", "2", "--min-link", "nan"], ["--min-link = nan"]),
])
def test_fit_and_pareto_refuse_a_bad_min_link(capsys, tmp_path, truth_file, extra, needles):
    for cmd in ("fit", "pareto"):
        _one_line_exit_2(capsys, [cmd, BEAM, *extra, "--truth", str(truth_file),
                                  "--out", str(tmp_path / cmd), "-q"], *needles)
        assert not (tmp_path / cmd / "fit.json").exists()


def test_batch_refuses_a_bad_min_link(capsys, tmp_path):
    _one_line_exit_2(capsys, ["batch", "--beams", "1", "--joints", "60", "--truth-model", "beam",
                              "--out", str(tmp_path / "b"), "-q"], "--min-link = 0.02",
                     "(0, 0.01639)")
    with pytest.raises(BeamInputError, match=r"min_fraction = 0\.5"):
        FitSettings(joints=1, options=FitOptions(min_fraction=0.5))


def test_min_link_reaches_the_fit(tmp_path, truth_file):
    # the free 2R optimum has a link below 0.3 L; --min-link 0.3 confines all to [0.3, 0.4] L
    lengths = {}
    for f in (None, 0.3):
        out = tmp_path / f"f{f}"
        argv = ["fit", BEAM, "--joints", "2", "--stiffness", "joint", "--starts", "4",
                "--truth", str(truth_file), "--out", str(out), "-q"]
        assert main(argv + ([] if f is None else ["--min-link", str(f)])) == 0
        record = json.loads((out / "fit.json").read_text())
        lengths[f] = np.array(record["lengths_m"])
        assert record["min_fraction"] == (0.02 if f is None else f)  # fit.json says which bound
    assert lengths[None].min() < 0.29
    assert lengths[0.3].min() >= 0.3 - 1e-12 and lengths[0.3].max() <= 0.4 + 1e-12


def test_min_link_reaches_the_pareto_front(tmp_path, truth_file):
    import csv

    out = tmp_path / "pareto"
    assert main(["pareto", BEAM, "--joints", "2", "--stiffness", "joint", "--pop", "8",
                 "--generations", "2", "--min-link", "0.3", "--truth", str(truth_file),
                 "--out", str(out), "-q"]) == 0
    rows = list(csv.DictReader((out / "pareto.csv").open()))
    cols = [k for k in rows[0] if k.startswith("L") and k.endswith("_m")]  # L0_m, L1_m, ...
    g = np.array([[float(r[k]) for k in cols] for r in rows])
    assert cols and g.min() >= 0.3 - 1e-9, (cols, g.min())
    knee = np.array(json.loads((out / "fit.json").read_text())["lengths_m"])
    assert knee.min() >= 0.3 - 1e-12


def test_min_link_reaches_the_batch_fit(tmp_path):
    beam = load_beam(BEAM)
    gammas = {}
    for f in (0.02, 0.3):
        s = FitSettings(joints=2, options=FitOptions(stiffness="joint", starts=3, min_fraction=f),
                        truth_model="beam", cache_dir=str(tmp_path))
        rec = evaluate_beam(BeamTask(0, 0, s, "narrow", beam))
        assert rec["status"] == "ok", rec.get("error")
        gammas[f] = np.array(rec["gamma"])
    assert gammas[0.02].min() < 0.29
    assert gammas[0.3].min() >= 0.3 - 1e-12


def test_beam_without_tip_force_is_unloaded_and_refused_by_deflection_fits(
        capsys, tmp_path, truth_file):
    d = json.loads(open(BEAM).read())
    del d["tip_force"]
    path = tmp_path / "unloaded.json"
    path.write_text(json.dumps(d))
    beam = load_beam(path)
    np.testing.assert_array_equal(beam.tip_force_N, [0.0, 0.0, 0.0])
    for cmd, objective in (("fit", ["--objective", "deflection"]),
                           ("fit", ["--objective", "combined"]), ("pareto", [])):
        _one_line_exit_2(capsys, [cmd, str(path), "--joints", "2", *objective, "--truth",
                                  str(truth_file), "--out", str(tmp_path / "o"), "-q"],
                         "tip_force = [0, 0, 0] N")
    # the library refuses too (a fit to nothing: the unloaded model tip equals the truth's)
    target = FitTarget(np.array([1.0, 6.0]), beam.tip_force_N, [1.0, 0, 0], [0.0, 0, 0])
    with pytest.raises(BeamInputError, match=r"tip_force = \[0, 0, 0\] N"):
        fit(beam, target, 2, objective="deflection", starts=1, progress=False)
    # an eigen fit needs no load
    assert main(["fit", str(path), "--joints", "2", "--stiffness", "joint", "--starts", "2",
                 "--truth", str(truth_file), "--out", str(tmp_path / "e"), "-q"]) == 0


def test_help_states_the_tip_force_default(capsys):
    with pytest.raises(SystemExit):
        main(["fit", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert 'without "tip_force" has no load (0 N)' in out
    assert "--min-link FRACTION" in out


def test_outputs_of_a_fit_with_links_below_the_default_bound(tmp_path, truth_file):
    # a --min-link 0.005 fit may return a link below 0.02 L: fit.json, the URDF and the
    # planform plot are written for it, and the URDF carries that link's exact mass
    import dataclasses

    from prbdm_pin.commands.fit import write_fit_outputs
    from prbdm_pin.files.urdf_file import load_urdf

    out = tmp_path / "fit"
    assert main(["fit", BEAM, "--joints", "2", "--stiffness", "joint", "--starts", "2",
                 "--min-link", "0.005", "--truth", str(truth_file), "--out", str(out),
                 "-q"]) == 0
    from prbdm_pin.files.fit_file import load_fit

    beam = load_beam(BEAM)
    res = dataclasses.replace(load_fit(out / "fit.json"),
                              lengths_m=np.array([0.01, 0.5, 0.49]))
    write_fit_outputs(res, beam, tmp_path / "short")
    model = load_urdf(tmp_path / "short" / "model.urdf")
    m0 = 7850.0 * 0.01 * 0.05 * 0.01  # rho L_0 b t
    # a product of four numbers on each side, the URDF's written in full (repr): a few
    # roundings (exact here); kept: the test's 1e-12
    assert model.sections.mass_kg[0] == pytest.approx(m0, rel=5000 * EPS)
    assert (tmp_path / "short" / "planform.png").stat().st_size > 1000


def test_a_design_below_the_default_bound_is_evaluated():
    # a fit with min_fraction 0.005 evaluates designs with a link of 0.01 L: the finite-segment
    # springs and the model of that design, not a refusal at Eq. 15's default 0.02 L
    from prbdm_pin.fitting.evaluate import evaluate
    from prbdm_pin.fitting.problem import make_problem

    beam = load_beam(BEAM)
    target = FitTarget(np.array([10.0, 60.0]), beam.tip_force_N)
    problem = make_problem(beam, target, 2, FitOptions(stiffness="joint", min_fraction=0.005,
                                                       eigen_norm="paper"))
    lengths = np.array([0.01, 0.5, 0.49])
    ev = evaluate(problem, lengths, np.ones(2), deflection=False)
    EI = 205e9 * 0.05 * 0.01**3 / 12
    # joint 0 spans [0, 0.26] (clamp to link 1's mid-span), joint 1 [0.26, 1]: K = EI / span
    # EI over a span of summed half-lengths: a few roundings (1 EPS measured); kept: the
    # test's 1e-12
    np.testing.assert_allclose(ev.stiffness_Nm_per_rad[0], [EI / 0.26, EI / 0.74],
                               rtol=5000 * EPS)


@pytest.mark.slow
def test_a_long_chain_fits_with_a_smaller_min_link(tmp_path, truth_file):
    # 50 links of at least 0.02 L do not fit; with --min-link 0.015 the 49R fit runs end to end
    # and its URDF has the Euler-Bernoulli frequencies of the truth file
    from prbdm_pin.files.urdf_file import load_urdf

    out = tmp_path / "long"
    assert main(["fit", BEAM, "--joints", "49", "--min-link", "0.015", "--frequencies", "3",
                 "--stiffness", "joint", "--starts", "1", "--truth", str(truth_file),
                 "--out", str(out), "-q"]) == 0
    d = json.loads((out / "fit.json").read_text())
    lengths = np.array(d["lengths_m"])
    assert lengths.size == 50 and lengths.min() >= 0.015 - 1e-12
    omega = load_urdf(out / "model.urdf").natural_frequencies()[:3]
    np.testing.assert_allclose(omega, d["omega_truth_rad_s"], rtol=1e-2)
