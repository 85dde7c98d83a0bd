"""URDF/MJCF exports with per-mode damping ratios (the modal_fit form): MuJoCo's own free decay
of the MJCF gives the achieved ratios the record states; Pinocchio reads the URDF's joint
damping as the fitted c; the stiffness form's ratios give beta K back; linearize with the same
form has the same poles; the record reads back from the comment and the JSON."""

import json

import numpy as np
import pytest
from tolerances import eig_rtol

from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.export import (
    MODAL_FIT_WARN_PCT,
    export_model,
    export_record,
    mjcf_text,
    read_export_record,
)
from prbdm_pin.files.model_source import load_model
from prbdm_pin.model.hub import Hub
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.plant.linearize import linearize

mujoco = pytest.importorskip("mujoco")

LENGTHS = {3: np.array([0.15, 0.3, 0.3, 0.25]), 5: np.array([0.1, 0.2, 0.2, 0.2, 0.15, 0.15])}
CALIBRATED = np.array([0.03, 0.02, 0.025, 0.02, 0.01])
# free-decay amplitude, rad and rad/s: MuJoCo's equations are linear to this relative size
AMPLITUDE = 1e-6


@pytest.fixture(scope="module", params=[3, 5], ids=["3R", "5R"])
def chain(request, reference_panel):
    L = LENGTHS[request.param] * reference_panel.length_m / LENGTHS[request.param].sum()
    return build_model(reference_panel, L, finite_segment_stiffness(reference_panel, L))


def _mujoco_decay_ratios(text: str, n_rigid: int = 0, n_runs: int = 2, samples: int = 400
                         ) -> np.ndarray:
    """The modes' damping ratios from MuJoCo free decays of the MJCF: RK4 at 10 us, the state
    sampled every 0.1 ms, the sampled map x[i+1] = Phi x[i] fitted by least squares over
    random starts, and zeta = -Re(s) / |s| of s = log(eig Phi) / h (a fit of the decaying
    modes: no package code). The 2 ``n_rigid`` roots nearest s = 0 (a hub's rigid mode, split
    by the fit's noise) are left out."""
    m = mujoco.MjModel.from_xml_string(text)
    d = mujoco.MjData(m)
    m.opt.timestep, every = 1e-5, 10
    rng = np.random.default_rng(0)
    X0, X1 = [], []
    for _ in range(n_runs):
        mujoco.mj_resetData(m, d)
        d.qpos[:] = AMPLITUDE * rng.standard_normal(m.nv)
        d.qvel[:] = 100 * AMPLITUDE * rng.standard_normal(m.nv)
        xs = []
        for _ in range(samples):
            xs.append(np.concatenate([d.qpos, d.qvel]))
            for _ in range(every):
                mujoco.mj_step(m, d)
        xs = np.array(xs).T
        X0.append(xs[:, :-1])
        X1.append(xs[:, 1:])
    Phi = np.hstack(X1) @ np.linalg.pinv(np.hstack(X0))
    s = np.log(np.linalg.eigvals(Phi).astype(complex)) / (every * m.opt.timestep)
    s = s[np.argsort(np.abs(s))][2 * n_rigid:]
    s = s[s.imag > 0.0]
    s = s[np.argsort(np.abs(s))]
    return -s.real / np.abs(s)


def test_mujoco_free_decay_has_the_recorded_ratios(chain):
    xi = CALIBRATED[:chain.n_joints]
    text = mjcf_text(chain, xi)  # per-mode ratios: the fitted form by default
    rec = read_export_record(text)
    assert rec.damping_form == "modal_fit" and rec.damping_requested == "modal_fit"
    measured = _mujoco_decay_ratios(text)
    # nonlinear terms are O(AMPLITUDE) relative; RK4 at omega_max dt < 0.05 adds
    # (omega dt)^4 / 120 < 1e-7 (measured 1e-10 to 8e-9)
    np.testing.assert_allclose(measured, rec.modal_damping_ratios, rtol=AMPLITUDE)
    np.testing.assert_allclose(rec.damping_ratio_errors, rec.modal_damping_ratios - xi,
                               rtol=0, atol=0)  # stored as computed: a subtraction
    print(f"{chain.n_joints}R asked {xi}, MuJoCo decay {measured}")


def test_mujoco_free_decay_on_a_hub(chain):
    """On a hub the hinge ``hub`` stays undamped (its rigid mode leaves the decay fit at
    s = 0) and the flexible modes have the recorded ratios."""
    model = build_model(chain.beam, chain.lengths_m, chain.stiffness_Nm_per_rad,
                        hub=Hub(50.0, 0.05))
    text = mjcf_text(model, CALIBRATED[:chain.n_joints])
    rec = read_export_record(text)
    assert rec.damping_form == "modal_fit"
    assert mujoco.MjModel.from_xml_string(text).dof_damping[0] == 0.0
    # as above: the amplitude's nonlinearity bounds the agreement
    np.testing.assert_allclose(_mujoco_decay_ratios(text, n_rigid=1),
                               rec.modal_damping_ratios, rtol=AMPLITUDE)


def test_pinocchio_reads_the_fitted_damping_from_the_urdf(chain, tmp_path):
    import pinocchio as pin

    from prbdm_pin.files.urdf_file import load_urdf

    xi = CALIBRATED[:chain.n_joints]
    path = export_model(chain, tmp_path / "m.urdf", "urdf", xi)
    rec = read_export_record(path.read_text())
    pm = pin.buildModelFromUrdf(str(path))
    # repr in the file: the same doubles back
    np.testing.assert_array_equal(pm.damping, rec.joint_damping_Nms_per_rad)
    np.testing.assert_array_equal(load_urdf(path).pin_model.damping,
                                  rec.joint_damping_Nms_per_rad)
    assert np.all(rec.joint_damping_Nms_per_rad >= 0.0)


def test_stiffness_form_ratios_give_the_stiffness_form_damping(chain):
    w = np.asarray(chain.natural_frequencies())
    xi1 = 0.5 * w[0] / w[-1]
    stiff = export_record(chain, "mjcf", xi1, "stiffness")
    fitted = export_record(chain, "mjcf", stiff.modal_damping_ratios, "modal_fit")
    # as tests/simulation/test_modal_fit.py: the modes' accuracy times the fit's conditioning
    # (cond(G) < 100 on these chains)
    tol = 100 * eig_rtol(w)
    np.testing.assert_allclose(fitted.joint_damping_Nms_per_rad,
                               stiff.joint_damping_Nms_per_rad, rtol=tol)
    np.testing.assert_allclose(fitted.modal_damping_ratios, stiff.modal_damping_ratios, rtol=tol)
    assert not fitted.warnings


def test_linearize_with_modal_fit_has_the_exported_ratios(chain):
    xi = CALIBRATED[:chain.n_joints]
    rec = export_record(chain, "urdf", xi)
    lam = np.linalg.eigvals(linearize(chain, damping_ratio=xi, damping="modal_fit").A)
    lam = lam[lam.imag > 0.0]
    lam = lam[np.argsort(np.abs(lam))]
    w = np.asarray(chain.natural_frequencies())
    # the same C, the state matrix written another way: the eigen solves' eig_rtol
    np.testing.assert_allclose(-lam.real / np.abs(lam), rec.modal_damping_ratios,
                               rtol=10 * eig_rtol(w))


def test_record_round_trips_and_warns_on_a_miss(chain, tmp_path):
    xi = CALIBRATED[:chain.n_joints]
    rec = export_record(chain, "mjcf", xi)
    miss = np.abs(rec.damping_ratio_errors) > 0.01 * MODAL_FIT_WARN_PCT * xi
    assert miss.any()  # these chains cannot carry these ratios on a diagonal: mode 1 misses
    text = " ".join(rec.warnings)
    for i in np.flatnonzero(miss):
        assert f"mode {i + 1} gets" in text
    back = read_export_record(mjcf_text(chain, xi))
    for f in ("joint_damping_Nms_per_rad", "modal_damping_ratios", "damping_ratio_errors",
              "damping_ratio"):
        np.testing.assert_array_equal(getattr(back, f), getattr(rec, f))  # repr: lossless
    assert back.warnings == rec.warnings
    d = json.loads(export_model(chain, tmp_path / "m.json", "json", xi,
                                damping_form="modal_fit").read_text())
    assert d["damping"]["form"] == "modal_fit"
    assert d["damping"]["ratio_errors"] == rec.damping_ratio_errors.tolist()
    # the asked ratios travel on with the file (as a calibrated model JSON's do)
    np.testing.assert_array_equal(load_model(tmp_path / "m.json").modal_damping_ratio, xi)
    d = json.loads(export_model(chain, tmp_path / "n.json", "json", xi).read_text())
    assert d["damping"]["form"] == "modal" and d["damping"]["ratio"] == xi.tolist()


def test_asked_forms_for_a_diagonal_file(chain):
    """Per-mode ratios asked as "modal" of a URDF get the fitted form and say so; as
    "stiffness" they are refused (that form takes one ratio); one ratio stays the stiffness
    form by default."""
    xi = CALIBRATED[:chain.n_joints]
    rec = export_record(chain, "urdf", xi, "modal")
    assert rec.damping_requested == "modal" and rec.damping_form == "modal_fit"
    assert "wrote the diagonal damping fitted to the ratios" in rec.warnings[0]
    with pytest.raises(BeamInputError, match="damping_ratio"):
        export_record(chain, "urdf", xi, "stiffness")
    assert export_record(chain, "urdf", 0.02).damping_form == "stiffness"


@pytest.mark.parametrize("bad, match", [
    ("neg", r"damping_ratio\[1\]"), ("count", "damping_ratio has shape")])
def test_bad_ratios_refused_before_writing(chain, tmp_path, bad, match):
    xi = CALIBRATED[:chain.n_joints].copy()
    if bad == "neg":
        xi[1] = -0.01
    else:
        xi = xi[:-1]
    for fmt in ("urdf", "mjcf"):
        with pytest.raises(BeamInputError, match=match):
            export_model(chain, tmp_path / f"m.{fmt}", fmt, xi, damping_form="modal_fit")
        assert not (tmp_path / f"m.{fmt}").exists()
