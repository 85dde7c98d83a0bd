"""``prbdm truth`` end to end, cache reuse and VTU export."""

import json

import meshio
import numpy as np
from paths import BEAMS
from reference import BETA_L as REF_BETA_L

from prbdm_pin.cli import main
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.truth import compute_truth

BETA_L = REF_BETA_L[:3]


def test_cli_writes_truth_json_and_vtu(tmp_path):
    rc = main([
        "truth", str(BEAMS / "uniform-narrow.json"), "--modes", "3", "--no-static",
        "--out", str(tmp_path), "--quiet",
    ])
    assert rc == 0
    doc = json.loads((tmp_path / "truth.json").read_text())
    beam = load_beam(BEAMS / "uniform-narrow.json")
    rhoA = beam.material.rho_kg_m3 * 2 * beam.half_width_m[0] * beam.thickness_m
    eb = BETA_L**2 * np.sqrt(beam.root_EI_Nm2 / rhoA)
    excess = np.array(doc["omega_rad_s"]) / eb - 1
    assert np.all((excess > 0.002) & (excess < 0.005))
    m = meshio.read(tmp_path / "modes.vtu")
    assert "uz_mode_1" in m.point_data and m.points.shape[0] == m.point_data["uz_mode_1"].size


def test_cli_bad_model_is_usage_error(tmp_path, capsys):
    try:
        rc = main(["truth", str(BEAMS / "uniform-narrow.json"), "--model", "x", "--out", "d"])
    except SystemExit as exc:
        rc = exc.code
    assert rc == 2


def test_cache_returns_stored_result(tmp_path):
    beam = load_beam(BEAMS / "uniform-narrow.json")
    r1 = compute_truth(beam, modes=3, static=False, cache_dir=tmp_path)
    assert len(list(tmp_path.glob("truth-*.npz"))) == 1
    r2 = compute_truth(beam, modes=3, static=False, cache_dir=tmp_path)
    np.testing.assert_array_equal(r1.omega_rad_s, r2.omega_rad_s)
    r3 = compute_truth(beam, modes=3, static=False, cache_dir=tmp_path, mesh_level=0)
    assert len(list(tmp_path.glob("truth-*.npz"))) == 2 and r3.mesh_level == 0


def test_cache_key_follows_the_truth_code(tmp_path, monkeypatch):
    # results of edited truth code are never served: the key holds a digest of its source
    from prbdm_pin.truth import cache

    beam = load_beam(BEAMS / "uniform-narrow.json")
    compute_truth(beam, model="beam", modes=3, static=False, cache_dir=tmp_path)
    assert len(list(tmp_path.glob("truth-*.npz"))) == 1
    assert len(cache.code_digest()) == 64
    monkeypatch.setattr(cache, "code_digest", lambda: "0" * 64)
    compute_truth(beam, model="beam", modes=3, static=False, cache_dir=tmp_path)
    assert len(list(tmp_path.glob("truth-*.npz"))) == 2
