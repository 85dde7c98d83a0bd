"""A model JSON that records one damping ratio per mode (a calibration's) runs with them in
prbdm linearize and prbdm simulate unless --damping-ratio / --damping says otherwise: the
linear plant's poles against the recorded ratios, and the command's run against the API's."""

import json

import numpy as np

import prbdm_pin as pp
from prbdm_pin.cli import main

BEAM = "examples/beams/uniform-narrow.json"
RATIOS = [0.05, 0.01, 0.03]


def _model_json(tmp_path):
    fit = tmp_path / "fit"
    assert main(["fit", BEAM, "--joints", "3", "--truth-model", "beam", "--stiffness", "joint",
                 "--objective", "eigen", "--starts", "2", "--out", str(fit), "-q"]) == 0
    path = tmp_path / "m.json"
    assert main(["export", str(fit / "fit.json"), "--format", "json", "--out", str(path),
                 "-q"]) == 0
    d = json.loads(path.read_text())
    d["damping"]["ratio"] = d["damping"]["modal_ratios"] = RATIOS
    path.write_text(json.dumps(d))
    return path


def _pole_ratios(lin_dir):
    import scipy.io

    A = scipy.io.loadmat(lin_dir / "linear_model.mat")["A"]
    lam = np.linalg.eigvals(A)
    lam = lam[lam.imag > 0]
    lam = lam[np.argsort(np.abs(lam))]
    return -lam.real / np.abs(lam)


def test_recorded_ratios_are_the_default(tmp_path):
    path = _model_json(tmp_path)
    assert main(["linearize", str(path), "--out", str(tmp_path / "a"), "-q"]) == 0
    # the poles of A: each mode's -Re/|lambda| is its ratio (an eigen solve of a 6x6)
    np.testing.assert_allclose(_pole_ratios(tmp_path / "a"), RATIOS, rtol=1e-9)
    assert main(["linearize", str(path), "--damping-ratio", "0.04", "--out",
                 str(tmp_path / "b"), "-q"]) == 0
    np.testing.assert_allclose(_pole_ratios(tmp_path / "b"), 0.04, rtol=1e-9)
    # simulate runs with them: the command's trajectory is the API's with the recorded ratios
    # (the modal damping's own accuracy is tested in tests/simulation), not the 2 % default's
    assert main(["simulate", str(path), "--duration", "0.2", "--initial-angle", "0.001",
                 "--output-dt", "0.001", "--method", "DOP853", "--out",
                 str(tmp_path / "s"), "-q"]) == 0
    head = (tmp_path / "s" / "trajectory.csv").read_text().splitlines()[0].split(",")
    z = np.loadtxt(tmp_path / "s" / "trajectory.csv", delimiter=",", skiprows=1)[
        :, head.index("tip_z_m")]
    model = pp.load_model(path).model
    q0 = np.full(model.n_springs, 0.001)
    runs = [pp.simulate(model, 0.2, q0=q0, damping_ratio=zeta, output_dt_s=0.001,
                        method="DOP853").tip_position_m[:, 2] for zeta in (np.array(RATIOS), 0.02)]
    # the same integrator and tolerances on the same equations, written with repr: exact
    np.testing.assert_array_equal(z, runs[0])
    assert np.abs(z - runs[1]).max() > 1e-3 * np.abs(z).max()
