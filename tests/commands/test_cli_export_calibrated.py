"""prbdm export of a calibrated model JSON (one damping ratio per mode): JSON keeps the modal
form with the ratios, URDF and MJCF get the diagonal damping fitted to them (modal_fit) with
the achieved ratios recorded and a warning for a mode that misses; --damping and
--damping-form stiffness replace them; prbdm linearize/simulate --damping-form modal_fit run
the damping the MJCF carries. References: the API's own export with the same ratios (the
command's defaulting is what is under test; modal_fit's accuracy is tested in
tests/files/test_export_modal_fit.py against MuJoCo), the linear plant's poles."""

import json

import numpy as np
import pytest
from tolerances import eig_rtol

import prbdm_pin as pp
from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.cli import main
from prbdm_pin.files.export import export_record, read_export_record
from prbdm_pin.files.model_json import model_dict
from prbdm_pin.model.prbdm_model import build_model

RATIOS = [0.03, 0.02, 0.025]


@pytest.fixture()
def calibrated(tmp_path, reference_panel):
    L = np.array([0.15, 0.3, 0.3, 0.25]) * reference_panel.length_m
    model = build_model(reference_panel, L, finite_segment_stiffness(reference_panel, L))
    path = tmp_path / "calibrated.json"
    # what prbdm calibrate writes: the modal form with one ratio per mode
    path.write_text(json.dumps(model_dict(model, np.array(RATIOS), damping_form="modal")))
    return path, pp.load_model(path).model


def test_urdf_and_mjcf_get_the_fitted_form_json_keeps_the_ratios(calibrated, tmp_path, capsys):
    path, model = calibrated
    ref = export_record(model, "mjcf", np.array(RATIOS), "modal_fit")
    for fmt, out in (("mjcf", "m.xml"), ("urdf", "m.urdf")):
        assert main(["export", str(path), "--format", fmt, "--out", str(tmp_path / out)]) == 0
        rec = read_export_record((tmp_path / out).read_text())
        assert rec.damping_form == "modal_fit"
        np.testing.assert_array_equal(rec.damping_ratio, RATIOS)
        # the same arithmetic as the API's export with the ratios given
        np.testing.assert_array_equal(rec.joint_damping_Nms_per_rad,
                                      ref.joint_damping_Nms_per_rad)
        np.testing.assert_array_equal(rec.modal_damping_ratios, ref.modal_damping_ratios)
        cap = capsys.readouterr()
        assert "damping: modal_fit" in cap.out and "damping ratio errors" in cap.out
        warn = [x for x in cap.err.splitlines() if x.startswith("export warning: modal_fit")]
        assert len(warn) == 1 and "mode 1 gets" in warn[0]
    assert main(["export", str(path), "--format", "json", "--out", str(tmp_path / "j.json"),
                 "-q"]) == 0
    d = json.loads((tmp_path / "j.json").read_text())
    assert d["damping"]["form"] == "modal" and d["damping"]["ratio"] == RATIOS
    assert pp.load_model(tmp_path / "j.json").modal_damping_ratio.tolist() == RATIOS


def test_the_ratios_travel_through_a_urdf(calibrated, tmp_path):
    """calibrated JSON -> URDF (modal_fit) -> MJCF: the URDF's record carries the asked ratios
    on, so the MJCF gets the same fitted damping (the same arithmetic on the same model: the
    URDF holds the model's numbers with repr)."""
    path, _ = calibrated
    urdf, xml = tmp_path / "m.urdf", tmp_path / "m.xml"
    assert main(["export", str(path), "--format", "urdf", "--out", str(urdf), "-q"]) == 0
    np.testing.assert_array_equal(pp.load_model(urdf).modal_damping_ratio, RATIOS)
    assert main(["export", str(urdf), "--format", "mjcf", "--out", str(xml), "-q"]) == 0
    a, b = (read_export_record(f.read_text()) for f in (urdf, xml))
    assert b.damping_form == "modal_fit"
    np.testing.assert_array_equal(b.joint_damping_Nms_per_rad, a.joint_damping_Nms_per_rad)


def test_options_replace_the_recorded_ratios(calibrated, tmp_path):
    path, _ = calibrated
    out = tmp_path / "m.xml"
    assert main(["export", str(path), "--format", "mjcf", "--damping", "0.01", "--out",
                 str(out), "-q"]) == 0
    rec = read_export_record(out.read_text())
    assert rec.damping_form == "stiffness" and rec.damping_ratio.tolist() == [0.01] * 3
    assert main(["export", str(path), "--format", "mjcf", "--damping-form", "stiffness",
                 "--out", str(out), "-q"]) == 0
    rec = read_export_record(out.read_text())
    assert rec.damping_form == "stiffness" and rec.damping_ratio.tolist() == [RATIOS[0]] * 3


def test_linearize_modal_fit_has_the_mjcf_ratios(calibrated, tmp_path):
    import scipy.io

    path, model = calibrated
    assert main(["export", str(path), "--format", "mjcf", "--out", str(tmp_path / "m.xml"),
                 "-q"]) == 0
    rec = read_export_record((tmp_path / "m.xml").read_text())
    assert main(["linearize", str(path), "--damping-form", "modal_fit", "--out",
                 str(tmp_path / "lin"), "-q"]) == 0
    A = scipy.io.loadmat(tmp_path / "lin" / "linear_model.mat")["A"]
    lam = np.linalg.eigvals(A)
    lam = lam[lam.imag > 0.0]
    lam = lam[np.argsort(np.abs(lam))]
    # the same C in another state matrix: the eigen solves' eig_rtol
    np.testing.assert_allclose(-lam.real / np.abs(lam), rec.modal_damping_ratios,
                               rtol=10 * eig_rtol(model.natural_frequencies()))


def test_simulate_modal_fit_runs_the_recorded_ratios(calibrated, tmp_path):
    path, model = calibrated
    assert main(["simulate", str(path), "--duration", "0.1", "--initial-angle", "0.001",
                 "--damping-form", "modal_fit", "--output-dt", "0.001", "--method", "DOP853",
                 "--out", str(tmp_path / "s"), "-q"]) == 0
    csv = tmp_path / "s" / "trajectory.csv"
    head = csv.read_text().splitlines()[0].split(",")
    z = np.loadtxt(csv, delimiter=",", skiprows=1)[:, head.index("tip_z_m")]
    q0 = np.full(model.n_springs, 0.001)
    ours = pp.simulate(model, 0.1, q0=q0, damping_ratio=np.array(RATIOS), damping="modal_fit",
                       damping_pose=np.zeros(model.n_springs), output_dt_s=0.001,
                       method="DOP853").tip_position_m[:, 2]
    # the same integrator and tolerances on the same equations, written with repr: exact
    np.testing.assert_array_equal(z, ours)


@pytest.mark.parametrize("argv, match", [
    (["--damping", "-0.1"], "--damping"),
    (["--damping-form", "rayleigh"], "--damping-form"),
])
def test_bad_damping_is_one_line_exit_2(calibrated, tmp_path, capsys, argv, match):
    path, _ = calibrated
    out = tmp_path / "m.xml"
    try:  # argparse's own refusals (a bad choice) exit; the option checks return 2
        code = main(["export", str(path), "--format", "mjcf", *argv, "--out", str(out)])
    except SystemExit as exc:
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and match in err
    assert not out.exists()
