"""``prbdm view``: its files read back, and bad input refused by name with nothing written."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest
import scipy.optimize
from paths import BEAMS, ROOT
from PIL import Image
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.cli import main

LENGTHS = np.array([0.25, 0.2, 0.15])
FORCE_N = np.array([0.0, 0.0, -1.5])


@pytest.fixture(scope="module")
def urdf(tapered, tmp_path_factory):
    lengths = LENGTHS * tapered.length_m / LENGTHS.sum()
    model = pp.build_model(tapered, lengths, pp.finite_segment_stiffness(tapered, lengths))
    path = tmp_path_factory.mktemp("view-model") / "model.urdf"
    model.write_urdf(path)
    return path, model


def _static_tip_displacement(lengths: np.ndarray, k: np.ndarray, f: np.ndarray) -> np.ndarray:
    """The planar chain's tip displacement under a dead tip force, by hand (x, z; m).

    Equilibrium k_j th_j = dtip/dth_j . F, with the tip x = l_0 + sum l_i cos(phi_i),
    z = -sum l_i sin(phi_i), phi_i = th_1 + ... + th_i (a rotation about +y turns x to -z).
    """
    def tip(th):
        phi = np.cumsum(th)
        return np.array([lengths[0] + np.sum(lengths[1:] * np.cos(phi)),
                         -np.sum(lengths[1:] * np.sin(phi))])

    def residual(th):
        phi = np.cumsum(th)
        dx = -np.cumsum((lengths[1:] * np.sin(phi))[::-1])[::-1]
        dz = -np.cumsum((lengths[1:] * np.cos(phi))[::-1])[::-1]
        return k * th - (dx * f[0] + dz * f[2])

    th = scipy.optimize.fsolve(residual, np.zeros(k.size), xtol=1e3 * EPS)
    return tip(th) - tip(np.zeros(k.size))


def test_view_writes_modes_animation_and_a_vtu_series_starting_at_the_static_pose(
        urdf, tmp_path, capsys):
    path, model = urdf
    out = tmp_path / "view"
    rc = main(["view", str(path), "--no-truth", "--force", ",".join(map(str, FORCE_N)),
               "--frames", "4", "--modes", "2", "--out", str(out)])
    assert rc == 0, capsys.readouterr().err
    assert "truth not drawn" in capsys.readouterr().err
    names = sorted(p.name for p in out.iterdir())
    assert names == ["model_modes.vtu", "modes.png", "response.gif", "trajectory.pvd",
                     "trajectory_0000.vtu", "trajectory_0001.vtu", "trajectory_0002.vtu",
                     "trajectory_0003.vtu"]
    assert Image.open(out / "response.gif").n_frames == 4
    sets = ET.parse(out / "trajectory.pvd").getroot().findall("./Collection/DataSet")
    assert [s.get("file") for s in sets] == [f"trajectory_{i:04d}.vtu" for i in range(4)]
    times = [float(s.get("timestep")) for s in sets]
    assert times[0] == 0.0 and np.all(np.diff(times) > 0)
    # released from rest in the static pose: the first frame's tip is the static tip
    first = meshio.read(out / "trajectory_0000.vtu").point_data["displacement"]
    ref = _static_tip_displacement(np.asarray(model.lengths_m), model.stiffness_Nm_per_rad,
                                   FORCE_N)
    # the package's static solve stops at a residual of 1e-10 of the load terms (well
    # below this); the reference's fsolve at 1e3 EPS: 1e-9 of the deflection bounds both
    np.testing.assert_allclose(first[-1, [0, 2]], ref, rtol=0,
                               atol=1e-9 * np.linalg.norm(ref))
    assert len(meshio.read(out / "model_modes.vtu").point_data) == 4  # 2 modes, 2 fields


def _refused(argv, what, capsys, out):
    rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and what in lines[0], err
    assert not out.exists()


def test_bad_input_is_refused_by_name_with_nothing_written(urdf, tmp_path, capsys):
    path, _ = urdf
    out = tmp_path / "never"
    _refused(["view", str(tmp_path / "missing.json"), "--no-truth", "--out", str(out)],
             "not found", capsys, out)
    _refused(["view", str(BEAMS / "tapered.json"), "--no-truth", "--out", str(out)],
             "is a beam file", capsys, out)
    other = tmp_path / "other.json"
    other.write_text(json.dumps({"hello": 1}))
    _refused(["view", str(other), "--no-truth", "--out", str(out)], "MODEL", capsys, out)
    _refused(["view", str(path), "--modes", "0", "--out", str(out)], "--modes = 0", capsys,
             out)
    _refused(["view", str(path), "--modes", "9", "--no-truth", "--out", str(out)],
             "--modes = 9", capsys, out)
    _refused(["view", str(path), "--frames", "0", "--out", str(out)], "--frames = 0", capsys,
             out)
    from matplotlib.animation import FFMpegWriter

    if not FFMpegWriter.isAvailable():
        _refused(["view", str(path), "--format", "mp4", "--force", "0,0,-1", "--out", str(out)],
                 "--format mp4: needs ffmpeg", capsys, out)
    a_file = tmp_path / "a_file"
    a_file.write_text("mine")
    _refused(["view", str(path), "--no-truth", "--out", str(a_file)], "--out", capsys,
             tmp_path / "nothing")
    assert a_file.read_text() == "mine"
    # a URDF has no beam, so no tip force to release from
    _refused(["view", str(path), "--no-truth", "--out", str(out)], "--force", capsys, out)
    # a hub turns under a tip force: no static pose to release from
    hub = ROOT / "tests" / "files" / "planar_golden" / "tapered_3R_hub.urdf"
    _refused(["view", str(hub), "--force", "0,0,-1", "--out", str(out)],
             "--response release", capsys, out)


def test_meshcat_absent_is_refused_before_anything_is_written(urdf, tmp_path, capsys):
    import importlib.util

    if importlib.util.find_spec("meshcat") is not None:
        pytest.skip("meshcat is installed here")
    path, _ = urdf
    out = tmp_path / "view"
    _refused(["view", str(path), "--meshcat", "--no-truth", "--force", "0,0,-1", "--out",
              str(out)], "meshcat is not installed", capsys, out)


def test_a_fit_is_drawn_beside_its_truth_from_the_cache(strip_fit, tmp_path, capsys):
    from prbdm_pin.commands.view_truth import view_truth
    from prbdm_pin.files.model_source import load_model

    root = strip_fit(2)
    fit = root / "fit" / "fit.json"
    out = tmp_path / "view"
    rc = main(["view", str(fit), "--cache-dir", str(root / "cache"), "--response", "none",
               "--out", str(out)])
    err = capsys.readouterr().err
    assert rc == 0, err
    assert "truth: beam" in err
    assert sorted(p.name for p in out.iterdir()) == ["model_modes.vtu", "modes.png",
                                                     "truth_modes.vtu"]
    # the pairs: the fit's records; the shapes: the truth's centreline (a 1D beam has no width)
    source = load_model(fit)
    seen = view_truth(source, 2, str(root / "cache"), True, True)
    records = {r["omega_model_rad_s"]: r["omega_truth_rad_s"] for r in source.fit.modes}
    omega = source.model.natural_frequencies()
    np.testing.assert_array_equal(seen.shapes.omega_rad_s,
                                  [records[min(records, key=lambda m: abs(m - w))]
                                   for w in omega[:2]])
    modal = seen.truth.modal
    for k, w in enumerate(seen.shapes.omega_rad_s):
        i = int(np.flatnonzero(modal.omega_rad_s == w)[0])  # the same cached numbers
        np.testing.assert_array_equal(seen.shapes.deflection[k], modal.centerline_uz[i])
    assert seen.shapes.twist is None


def test_a_model_json_gives_the_truth_frequencies_it_recorded_without_shapes(urdf, tmp_path,
                                                                             capsys):
    from prbdm_pin.commands.view_truth import view_truth
    from prbdm_pin.files.model_source import load_model

    _, model = urdf
    omega = model.natural_frequencies()
    recorded = omega * np.array([1.01, 0.98])  # a truth 1 % below and 2 % above the model
    path = pp.export_model(model, tmp_path / "model.json", "json",
                           omega_truth_rad_s=recorded)
    seen = view_truth(load_model(path), 2, None, True, True)
    assert seen.shapes.stations_m is None and seen.truth is None
    np.testing.assert_array_equal(seen.shapes.omega_rad_s, recorded)  # read back from JSON
    assert "truth shapes not available" in seen.note
    out = tmp_path / "view"
    rc = main(["view", str(path), "--response", "none", "--out", str(out)])
    assert rc == 0
    assert "truth shapes not available" in capsys.readouterr().err
    assert sorted(p.name for p in out.iterdir()) == ["model_modes.vtu", "modes.png"]
