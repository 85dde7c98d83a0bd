"""The option objects: validated once (every error names the field), carried whole from the API
and the command line into fit.json and read back; the options that the command line lacked
(deflection norm, joint sweep, polish, evaluation cap) reach the fit."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from reference import BETA_L
from tolerances import EPS

from prbdm_pin.cli import main
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.fit_file import load_fit, save_fit
from prbdm_pin.fitting import fit
from prbdm_pin.fitting.target import FitTarget
from prbdm_pin.options.objects import (
    FitOptions,
    ParetoOptions,
    SimulationOptions,
    options_from_dict,
)

NARROW = "examples/beams/uniform-narrow.json"


@pytest.fixture(scope="module")
def target(narrow):
    """Euler-Bernoulli frequencies and the elastica tip at P L^2 / EI = 1 (0.056433 L retreat,
    0.301721 L deflection): independent of the package."""
    b, t, L = 2 * narrow.half_width_m[0], narrow.thickness_m, narrow.length_m
    EI = narrow.material.E_Pa * b * t**3 / 12
    omega = BETA_L**2 * math.sqrt(EI / (narrow.material.rho_kg_m3 * b * t * L**4))
    tip = np.array([L * (1 - 0.056433), 0.0, -0.301721 * L])
    return FitTarget(omega, narrow.tip_force_N, tip, tip - np.array([L, 0.0, 0.0]))


@pytest.mark.parametrize("options", [
    FitOptions(), FitOptions(objective="combined", stiffness="joint", loss_tol_pct=0.1,
                             deflection_norm="displacement", joint_sweep=True, polish=0),
    ParetoOptions(), ParetoOptions(log10_bounds=(-1.0, 2.0), seed_with_fits=False, pop=8),
])
def test_options_survive_json(options):
    d = json.loads(json.dumps(options.to_dict()))
    assert options_from_dict(d) == options
    assert type(options).from_dict(d).to_dict() == options.to_dict()


@pytest.mark.parametrize("cls, change, field", [
    (FitOptions, {"objective": "modal"}, "objective = 'modal'"),
    (FitOptions, {"stiffness": "spring"}, "stiffness = 'spring'"),
    (FitOptions, {"starts": 0}, "starts = 0"),
    (FitOptions, {"starts": 2.5}, "starts = 2.5"),
    (FitOptions, {"seed": True}, "seed = True"),
    (FitOptions, {"xi_rad": math.nan}, "xi_rad = nan"),
    (FitOptions, {"eps_rad": 0.0}, "eps_rad = 0.0"),
    (FitOptions, {"loss_tol_pct": -1.0}, "loss_tol_pct = -1.0"),
    (FitOptions, {"deflection_norm": "tip"}, "deflection_norm = 'tip'"),
    (FitOptions, {"eigen_norm": "l2"}, "eigen_norm = 'l2'"),
    (FitOptions, {"min_fraction": 0.5}, "min_fraction = 0.5"),
    (FitOptions, {"polish": -1}, "polish = -1"),
    (FitOptions, {"max_nfev": 0}, "max_nfev = 0"),
    (FitOptions, {"explore_nfev": 0}, "explore_nfev = 0"),
    (FitOptions, {"refine_starts": -1}, "refine_starts = -1"),
    (FitOptions, {"refine_starts": 1.5}, "refine_starts = 1.5"),
    (FitOptions, {"joint_sweep": "yes"}, "joint_sweep = 'yes'"),
    (FitOptions, {"pop": 10}, "pop = 10: not an option of FitOptions"),
    (ParetoOptions, {"log10_bounds": (1.0, 0.0)}, "log10_bounds"),
    (ParetoOptions, {"log10_bounds": (0.0, math.inf)}, r"log10_bounds\[1\] = inf"),
    (ParetoOptions, {"generations": 0}, "generations = 0"),
    (ParetoOptions, {"seed_starts": 0}, "seed_starts = 0"),
    (SimulationOptions, {"method": "euler"}, "method = 'euler'"),
    (SimulationOptions, {"dt_s": -1e-3}, "dt_s = -0.001"),
    (SimulationOptions, {"damping": "rayleigh"}, "damping = 'rayleigh'"),
    (SimulationOptions, {"damping_ratio": (0.02, -0.1)}, r"damping_ratio\[1\] = -0.1"),
])
def test_a_bad_option_is_named(cls, change, field):
    with pytest.raises(BeamInputError, match=field):
        cls().replace(**change)
    if "not an option" not in field:
        with pytest.raises(BeamInputError, match=field):
            cls(**change)


def test_fit_json_records_the_options_and_reads_them_back(narrow, target, tmp_path):
    o = FitOptions(objective="combined", stiffness="joint", starts=2, seed=3,
                   deflection_norm="displacement", max_nfev=200)
    r = fit(narrow, target, 2, o, progress=False)
    assert r.options == o
    back = load_fit(save_fit(r, tmp_path / "fit.json", narrow))
    assert back.options == o and back.to_dict() == r.to_dict()
    # the recorded norm is the one the combined loss was taken in: the tip error over the truth
    # tip displacement, recomputed here from the recorded tips
    err = np.linalg.norm(r.tip_position_model_m[0] - target.tip_position_m)
    disp = 100 * err / np.linalg.norm(target.tip_displacement_m)
    # a norm and a hypot either side: a few roundings (0.9 EPS measured); kept: the tests'
    # 1e-12
    assert r.displacement_loss_pct == pytest.approx(disp, rel=5000 * EPS)
    assert r.combined_loss_pct == pytest.approx(math.hypot(r.eigen_loss_pct, disp),
                                                rel=5000 * EPS)
    # keyword changes are the same options
    assert fit(narrow, target, 2, progress=False, **{
        k: v for k, v in o.to_dict().items() if k != "kind"}).options == o


def test_a_fit_json_without_options_still_loads(narrow, target, tmp_path):
    r = fit(narrow, target, 1, starts=1, progress=False)
    d = r.to_dict()
    del d["options"]
    (tmp_path / "old.json").write_text(json.dumps(d))
    assert load_fit(tmp_path / "old.json", beam=narrow).options is None


def test_a_fit_json_with_bad_options_is_refused(narrow, target, tmp_path):
    d = fit(narrow, target, 1, starts=1, progress=False).to_dict()
    d["options"]["max_nfev"] = -3
    (tmp_path / "bad.json").write_text(json.dumps(d))
    with pytest.raises(BeamInputError, match=r"options: max_nfev = -3"):
        load_fit(tmp_path / "bad.json", beam=narrow)


def test_the_cli_carries_every_fit_option_into_fit_json(tmp_path, capsys):
    args = ["fit", NARROW, "--joints", "2", "--stiffness", "joint", "--objective", "combined",
            "--truth-model", "beam", "--starts", "2", "--seed", "5", "--joint-sweep",
            "--eps", "0.2", "--deflection-norm", "displacement", "--polish", "1",
            "--max-nfev", "150", "--loss-tol", "0.5", "--eigen-norm", "paper",
            "--explore-nfev", "20", "--refine-starts", "1", "--min-link", "0.05",
            "--cache-dir", str(tmp_path / "cache"),
            "--out", str(tmp_path / "fit"), "-q"]
    assert main(args) == 0
    d = json.loads((tmp_path / "fit" / "fit.json").read_text())
    want = FitOptions(objective="combined", stiffness="joint", starts=2, seed=5,
                      joint_sweep=True, eps_rad=0.2, deflection_norm="displacement", polish=1,
                      max_nfev=150, loss_tol_pct=0.5, eigen_norm="paper", min_fraction=0.05,
                      explore_nfev=20, refine_starts=1)
    assert d["options"] == want.to_dict()
    # the sweep was used (one straight pose without it) and the combined loss is in the
    # displacement norm
    assert len(d["poses_rad"]) > 1
    # the recorded hypot of the recorded two (exact here); kept: the test's 1e-12
    assert d["combined_loss_pct"] == pytest.approx(
        math.hypot(d["eigen_loss_pct"], d["displacement_loss_pct"]), rel=5000 * EPS)
