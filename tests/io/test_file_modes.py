"""One file mode for every output: 0666 & ~umask (0644 under umask 022, 0600 under 077), as a
file opened with open(path, "w") gets; temporary files from tempfile.mkstemp used to leave
fit.json, truth.json and results.csv 0600 beside a 0644 results.jsonl."""

import os
import stat
from pathlib import Path

import numpy as np
import pytest
from paths import ROOT

from prbdm_pin.cli import main
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.io.atomic import atomic_write_text
from prbdm_pin.io.output_folder import output_folder

BEAM_FILE = ROOT / "examples" / "beams" / "uniform-narrow.json"


def mode(path: Path) -> int:
    return stat.S_IMODE(path.stat().st_mode)


@pytest.fixture
def umask():
    old = os.umask(0o022)

    def set_to(value: int) -> None:
        os.umask(value)

    yield set_to
    os.umask(old)


def write_every_kind(folder: Path) -> list[Path]:
    """One file of each writer: text (fit.json, truth.json, results.csv), PNG plots, VTU."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    from prbdm_pin.truth import compute_truth
    from prbdm_pin.truth.vtu import write_modes_vtu
    from prbdm_pin.views.plots import plot_planform, save_png

    beam = load_beam(BEAM_FILE)
    plot_planform(beam, np.array([0.25, 0.5, 0.25]), folder / "planform.png")
    paths = [atomic_write_text(folder / "results.csv", "a,b\n1,2\n"),
             folder / "planform.png",
             write_modes_vtu(compute_truth(beam, model="beam", modes=2, static=False).modal,
                             folder / "modes.vtu")]
    fig = plt.figure()
    save_png(fig, folder / "response.png")
    plt.close(fig)
    return paths + [folder / "response.png"]


@pytest.mark.parametrize("mask, file_mode, dir_mode", [(0o022, 0o644, 0o755),
                                                       (0o077, 0o600, 0o700),
                                                       (0o002, 0o664, 0o775)])
def test_every_writer_gives_the_umask_mode(tmp_path, umask, mask, file_mode, dir_mode):
    umask(mask)
    with output_folder(tmp_path / "out", ["results.csv", "planform.png", "modes.vtu",
                                          "response.png"]) as stage:
        names = [p.name for p in write_every_kind(stage)]
    out = tmp_path / "out"
    assert mode(out) == dir_mode
    # what open() gives a new file under the same umask
    (tmp_path / "plain.txt").write_text("x")
    assert mode(tmp_path / "plain.txt") == file_mode
    assert {n: mode(out / n) for n in names} == {n: file_mode for n in names}


def test_cli_outputs_are_0644_under_umask_022(tmp_path, umask, capsys):
    umask(0o022)
    truth, fit, sim = tmp_path / "truth", tmp_path / "fit", tmp_path / "sim"
    assert main(["truth", str(BEAM_FILE), "--model", "beam", "--modes", "3", "--out",
                 str(truth), "--quiet"]) == 0
    assert main(["fit", str(BEAM_FILE), "--joints", "2", "--truth", str(truth / "truth.json"),
                 "--starts", "1", "--out", str(fit), "--quiet"]) == 0
    assert main(["simulate", str(fit / "fit.json"), "--duration", "0.05", "--out", str(sim),
                 "--quiet"]) == 0
    files = sorted(p for d in (truth, fit, sim) for p in d.iterdir())
    assert {p.name for p in files} >= {"truth.json", "modes.vtu", "fit.json", "model.urdf",
                                       "planform.png", "trajectory.csv", "response.png"}
    assert {p.name: mode(p) for p in files} == {p.name: 0o644 for p in files}
    assert [mode(d) for d in (truth, fit, sim)] == [0o755] * 3
