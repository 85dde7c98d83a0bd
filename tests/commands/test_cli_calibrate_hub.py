"""``prbdm calibrate --hub``: a ring-down CSV of the scaled 1D beam truth on a hub in, E and rho
fitted apart within their standard errors, the hub kept in calibration.json and the calibrated
model JSON (and taken from a model JSON that has one); a zero hub inertia and a damping[k]
beyond the flexible modes exit 2 with one line and write nothing."""

import json

import numpy as np
import pytest
from hub_ring_down_truth import hub_ring_down, hub_truth

import prbdm_pin as pp
from prbdm_pin.bench.run import finite_segment_chain
from prbdm_pin.cli import main
from prbdm_pin.files.model_json import model_dict
from prbdm_pin.model.hub import Hub
from prbdm_pin.model.prbdm_model import build_model

S_E, S_RHO, ZETA = 0.95, 1.04, np.array([0.01, 0.005])
J_H, RADIUS = 0.5, 0.05
pytestmark = pytest.mark.filterwarnings("ignore::prbdm_pin.model.hub_check.LightHubWarning")


@pytest.fixture(scope="module")
def ring_csv(narrow, tmp_path_factory):
    M, K, Cq = hub_truth(narrow, S_E, S_RHO, J_H, RADIUS)
    q0, v0 = np.zeros(M.shape[0]), np.zeros(M.shape[0])
    q0[1], q0[2], v0[2] = 0.05, 0.01, 0.3
    t = np.arange(750) / 250.0  # 3 s at 250 Hz
    y = hub_ring_down(M, K, Cq, ZETA, t, q0, v0)
    y = y + 0.02 * np.abs(y).max(axis=0) * np.random.default_rng(4).standard_normal(y.shape)
    path = tmp_path_factory.mktemp("hub-ring") / "ring.csv"
    rows = ["t_s,tip_z_m,hub_angle_rad"]
    rows += [",".join(repr(float(v)) for v in r) for r in np.column_stack([t, y])]
    path.write_text("\n".join(rows) + "\n")
    return path


def _model_json(chain, path, hub=None):
    if hub is not None:
        chain = build_model(chain.beam, chain.lengths_m, chain.stiffness_Nm_per_rad,
                            min_fraction=0.25 / 40, hub=hub)
    path.write_text(json.dumps(model_dict(chain)))
    return path


@pytest.mark.parametrize("on_hub", [False, True])
def test_e_and_rho_apart_and_the_hub_kept(narrow, ring_csv, tmp_path, on_hub):
    chain = finite_segment_chain(narrow, 40)  # hub frequencies within 4e-4 of the truth's
    src = _model_json(chain, tmp_path / "m.json", Hub(J_H, RADIUS) if on_hub else None)
    out = tmp_path / "cal"
    hub = [] if on_hub else ["--hub", f"{J_H}:{RADIUS}"]
    assert main(["calibrate", str(src), "--data", str(ring_csv), "--parameters",
                 "E,rho,damping[0],damping[1]", *hub, "--out", str(out), "-q"]) == 0
    rec = json.loads((out / "calibration.json").read_text())
    assert rec["hub"] == {"inertia_kg_m2": J_H, "radius_m": RADIUS, "axis": "y"}
    p = rec["parameters"]
    want = {"E": narrow.material.E_Pa * S_E, "rho": narrow.material.rho_kg_m3 * S_RHO,
            "damping[0]": ZETA[0], "damping[1]": ZETA[1]}
    for name, v in want.items():
        # one seed: 3 sigma (0.3 % per parameter); the 40-segment chain's model-form error is
        # below a third of the standard errors (tests/fitting/test_calibrate_hub.py)
        assert abs(p[name]["value"] - v) <= 3 * p[name]["std_error"], (name, p[name], v)
    model = pp.read_model_json(out / "model.json")
    assert model.hub == Hub(J_H, RADIUS)
    assert model.beam.material.rho_kg_m3 == p["rho"]["value"]


@pytest.mark.parametrize("extra, needle", [
    (["--parameters", "E,rho", "--hub", "0:0.05"], "--hub = '0:0.05': Hub inertia_kg_m2 = 0.0"),
    (["--parameters", "E,rho", "--hub-axis", "y"], "--hub-axis = 'y': needs --hub"),
    (["--parameters", "E,damping[3]", "--hub", "0.5:0.05"],
     "damping[3] is flexible mode 4's; the model on its hub has 3 flexible modes"),
])
def test_bad_hub_input_exits_2_with_one_line_and_writes_nothing(narrow, ring_csv, tmp_path,
                                                                capsys, extra, needle):
    src = _model_json(finite_segment_chain(narrow, 3), tmp_path / "m3.json")
    out = tmp_path / "never"
    assert main(["calibrate", str(src), "--data", str(ring_csv), *extra, "--out",
                 str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err, err
    assert not out.exists()
