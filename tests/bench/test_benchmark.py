"""`prbdm bench --quick` against independent references (Euler-Bernoulli, brute-force frontier)."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from scipy.optimize import brentq
from tolerances import EPS

from prbdm_pin.bench.report import frontier_mask
from prbdm_pin.cli import main


def _beta_l(k: int) -> float:
    # cos(x) cosh(x) = -1, written without overflow
    return brentq(lambda x: np.cos(x) + 1.0 / np.cosh(x), (k - 0.5) * np.pi - 0.5,
                  (k - 0.5) * np.pi + 0.5, xtol=1e-14)


def _eb_omega(k: int) -> float:
    """uniform-narrow: L = 1 m, 50 mm x 10 mm steel (E 205 GPa, rho 7850)."""
    E, rho, b, t, L = 205e9, 7850.0, 0.05, 0.01, 1.0
    return _beta_l(k) ** 2 * np.sqrt(E * b * t**3 / 12.0 / (rho * b * t * L**4))


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    assert main(["bench", "--quick", "--quiet", "--out", str(out)]) == 0
    return out


def _md_rows(text: str, header_start: str) -> list[list[str]]:
    lines = text.splitlines()
    i = next(j for j, s in enumerate(lines) if s.startswith(header_start))
    rows = []
    for s in lines[i + 2:]:
        if not s.startswith("|"):
            break
        rows.append([c.strip() for c in s.strip("|").split("|")])
    return rows


def test_files_complete(quick):
    names = sorted(p.name for p in quick.iterdir() if p.is_file())
    assert names == ["error_vs_cost.png", "results.json", "results.md"]  # no temp files left
    assert (quick / "error_vs_cost.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    doc = json.loads((quick / "results.json").read_text())
    md = (quick / "results.md").read_text()
    rows = _md_rows(md, "| beam | model |")
    assert len(rows) == len(doc["models"]) == 2 * (2 + 3)  # 2 beams x (2 fits + 3 chains)
    kinds = {(m["beam"], m["kind"], m["joints"]) for m in doc["models"]}
    for beam in ("uniform-narrow", "reference-random"):
        for n in (2, 4):
            assert (beam, "fitted", n) in kinds
        for n in (4, 16, 32):
            assert (beam, "chain", n) in kinds
    for m in doc["models"]:
        assert all(np.isfinite(v) for v in m["tip_errors_pct"])
        assert np.isfinite(m["step_error_pct"]) and np.isfinite(m["frf_error_pct"])
        assert m["sim_cpu_s_per_s"] > 0
    assert len(doc["truths"]) == 2 and "Fitted nR against the smallest chain" in md


def test_chain_matches_euler_bernoulli(quick):
    """Chains on the slender strip: frequencies against beta_k L closed forms.

    The springs' spans tile the beam (K = EI/h at every joint), so the chain converges to
    Euler-Bernoulli at second order: mode 1's error falls about 4x per doubling of N.
    """
    doc = json.loads((quick / "results.json").read_text())
    md = (quick / "results.md").read_text()
    table = {(r[0], r[1]): r for r in _md_rows(md, "| beam | model |")}
    eb = np.array([_eb_omega(k) for k in range(1, 5)])
    chains = sorted((m for m in doc["models"]
                     if m["beam"] == "uniform-narrow" and m["kind"] == "chain"),
                    key=lambda m: m["joints"])
    prev = np.inf
    first = {}
    for m in chains:
        N = m["joints"]
        w = np.array(m["omega_model_rad_s"])
        truth = np.array(m["omega_truth_rad_s"])
        # the plate truth of a narrow strip is Euler-Bernoulli to well under 1 %
        np.testing.assert_allclose(truth, eb[: truth.size], rtol=5e-3)
        err_eb = w / eb[: w.size] - 1.0
        assert np.all(err_eb > 0)  # a chain of rigid links is stiffer than the beam
        assert np.max(err_eb) < prev  # errors fall with N
        prev = np.max(err_eb)
        first[N] = err_eb[0]
        # the table's errors are against the plate truth: the EB comparison shifted by the
        # plate-versus-EB difference (< 0.5 %); printed to 4 significant digits
        printed = [float(v) for v in table[("uniform-narrow", f"chain N={N}")][4].split()]
        np.testing.assert_allclose(printed, 100 * err_eb, atol=0.5 + 1e-9)
        # rtol: 4 significant digits; atol: w / truth - 1 is exact to ~2 EPS absolute, 200 EPS
        # in percent (kept: the test's 1e-12)
        np.testing.assert_allclose(printed, 100 * (w / truth - 1.0), rtol=5.01e-4,
                                   atol=5000 * EPS)
    assert first[16] < 6e-3 and first[16] / first[32] > 3.0


def test_fitted_matches_its_frequencies_and_comparisons(quick):
    doc = json.loads((quick / "results.json").read_text())
    for m in doc["models"]:
        if m["kind"] == "fitted":
            # the joint parametrisation matches n frequencies at the straight pose
            np.testing.assert_allclose(m["omega_model_rad_s"], m["omega_truth_rad_s"], rtol=1e-6)
    md = (quick / "results.md").read_text()
    comp = _md_rows(md, "| beam | n | fitted max err %")
    assert len(comp) == 4
    for r in comp:
        n, chain_n = int(r[1]), int(r[4])
        assert chain_n == 8 * n  # the quick set has chains of exactly 16 and 32 joints
        chain = next(m for m in doc["models"] if m["beam"] == r[0] and m["kind"] == "chain"
                     and m["joints"] == chain_n)
        w, t = np.array(chain["omega_model_rad_s"][:n]), np.array(chain["omega_truth_rad_s"][:n])
        assert float(r[5]) == pytest.approx(100 * np.max(np.abs(w / t - 1)), rel=5.01e-4)
        assert r[7] == ("yes" if float(r[2]) <= float(r[5]) else "no")
        assert r[8] == ("yes" if float(r[3]) < float(r[6]) else "no")


def test_frontier_is_non_dominated(quick):
    md = (quick / "results.md").read_text()
    rows = _md_rows(md, "| first k modes |")
    assert rows
    for k in {r[0] for r in rows}:
        pts = [(float(r[2]), float(r[3]), r[4] == "*") for r in rows if r[0] == k]
        for i, (c, e, on) in enumerate(pts):
            dominated = any(c2 <= c and e2 <= e and (c2 < c or e2 < e)
                            for j, (c2, e2, _) in enumerate(pts) if j != i)
            assert on == (not dominated), (k, pts[i])


def test_frontier_mask_brute_force():
    rng = np.random.default_rng(3)
    for _ in range(50):
        c = rng.integers(0, 6, 12).astype(float)
        e = rng.integers(0, 6, 12).astype(float)
        mask = frontier_mask(c, e)
        for i in range(c.size):
            dom = np.any((c <= c[i]) & (e <= e[i]) & ((c < c[i]) | (e < e[i])))
            assert mask[i] == (not dom)


def test_markdown_numbers_parse(quick):
    md = (quick / "results.md").read_text()
    assert re.search(r"Run wall time [0-9.]+ s", md)
    assert "elastica" in md and "joint parametrisation" in md


def test_mujoco_peer_row_against_euler_bernoulli():
    # the MuJoCo peer (the exported MJCF chain): its frequencies from MuJoCo's own mass matrix and
    # joint stiffness; a 16-joint equal-segment chain of the strip is within 0.6 % of
    # Euler-Bernoulli on its first three modes (second-order convergence of the chain)
    from prbdm_pin.bench.run import finite_segment_chain, mujoco_row
    from prbdm_pin.files.beam_file import load_beam

    beam = load_beam("examples/beams/uniform-narrow.json")
    model = finite_segment_chain(beam, 16)
    eb = np.array([_eb_omega(k) for k in (1, 2, 3)])
    row = mujoco_row(beam, model, eb, 0.01)
    assert row.kind == "mujoco" and row.sim_cpu_s_per_s > 0
    np.testing.assert_allclose(row.omega_model_rad_s, model.natural_frequencies()[:3], rtol=1e-6)
    assert np.all(np.abs(row.omega_model_rad_s / eb - 1) < 6e-3)
