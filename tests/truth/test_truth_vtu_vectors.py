"""The truth's VTU carries each mode's displacement vector: the 1D beam's against the closed-form
cantilever mode, and none for the solid, whose in-plane parts are not stored."""

from __future__ import annotations

import meshio
import numpy as np
from paths import BEAMS
from reference import BETA_L

from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.truth import compute_truth
from prbdm_pin.truth.vtu import write_modes_vtu


def _cantilever_mode(x: np.ndarray, L: float, k: int) -> np.ndarray:
    b = BETA_L[k] / L
    s = (np.cosh(BETA_L[k]) + np.cos(BETA_L[k])) / (np.sinh(BETA_L[k]) + np.sin(BETA_L[k]))
    return np.cosh(b * x) - np.cos(b * x) - s * (np.sinh(b * x) - np.sin(b * x))


def test_the_beams_displacement_vector_is_the_closed_form_mode(tmp_path):
    beam = load_beam(BEAMS / "uniform-narrow.json")
    truth = compute_truth(beam, model="beam", modes=2, static=False)
    m = meshio.read(write_modes_vtu(truth.modal, tmp_path / "modes.vtu"))
    x = m.points[:, 0]
    for k in range(2):
        v = m.point_data[f"displacement_mode_{k + 1}"]
        assert v.shape == (x.size, 3) and not np.any(v[:, :2])  # the axis does not stretch
        ref = _cantilever_mode(x, beam.length_m, k)
        ref = ref / ref[np.argmax(np.abs(ref))]
        got = v[:, 2] / v[np.argmax(np.abs(v[:, 2])), 2]  # the sign of a mode is free
        # the Hermite truth's nodal deflection against the closed form: discretisation and the
        # closed form's cancellation near the tip (cosh - sinh at beta L = 4.7), below 1e-6
        np.testing.assert_allclose(got, ref, atol=1e-6)
        np.testing.assert_array_equal(v[:, 2], m.point_data[f"uz_mode_{k + 1}"])


def test_the_solid_writes_no_vector(tmp_path):
    beam = load_beam(BEAMS / "uniform-narrow.json")
    truth = compute_truth(beam, model="solid", modes=1, static=False, mesh_level=0,
                          error_tol_pct=None)
    m = meshio.read(write_modes_vtu(truth.modal, tmp_path / "modes.vtu"))
    assert "uz_mode_1" in m.point_data and "displacement_mode_1" not in m.point_data
