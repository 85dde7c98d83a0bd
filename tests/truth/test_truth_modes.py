"""Mode classification and selection against known plate mode families."""


import numpy as np
import pytest
from paths import BEAMS

from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.truth import compute_truth
from prbdm_pin.truth.modes import label_modes, mac_matrix, select_modes
from prbdm_pin.truth.plate import plate_modal


@pytest.fixture(scope="module")
def square():
    return plate_modal(load_beam(BEAMS / "square-plate.json"), 0, 12)


def test_square_plate_labels(square):
    # cantilever plate: 1st bending, 1st torsion, 2nd bending, chordwise, 2nd torsion
    assert label_modes(square)[:5] == ("bending", "torsion", "bending", "chordwise", "torsion")


def test_mass_participation_sums_below_one_and_torsion_has_none(square):
    f = square.mpf_z_fraction
    assert 0.8 < f.sum() <= 1.0 + 1e-9
    assert np.all(f[~square.symmetric] < 1e-8)
    # first bending mode of a uniform cantilever carries 61.3 % of the mass (beam theory)
    assert abs(f[0] - 0.613) < 0.01


def test_selection_policies(square):
    paper = select_modes(square, 3, "paper")
    shape = select_modes(square, 3, "shape")
    assert list(shape) == [0, 2, 6]  # chordwise mode 4 (index 3) excluded by shape
    assert 0 in paper and 2 in paper and np.all(np.diff(paper) > 0)
    with pytest.raises(BeamInputError):
        select_modes(square, 3, "largest")


def test_mac_matrix_is_one_for_parallel_and_zero_for_orthogonal():
    a = np.array([[1.0, 2.0, 3.0], [1.0, 0.0, 0.0]])
    b = np.array([[-2.0, -4.0, -6.0], [0.0, 1.0, 0.0]])
    np.testing.assert_allclose(mac_matrix(a, b), [[1.0, 4.0 / 14.0], [1.0 / 14.0, 0.0]])


def test_compute_truth_uniform_narrow_all_bending_beam_like():
    beam = load_beam(BEAMS / "uniform-narrow.json")
    r = compute_truth(beam, modes=5, static=False)
    assert [r.labels[i] for i in r.mode_index] == ["bending"] * 5
    assert np.all(r.mac_beam > 0.99) and r.warnings == ()
    assert r.model == "plate" and r.omega_rad_s.flags.writeable is False


def test_compute_truth_warns_when_selected_mode_not_beam_like():
    beam = load_beam(BEAMS / "square-plate.json")
    r = compute_truth(beam, modes=5, static=False, mesh_level=0)
    assert any("not beam-like" in w for w in r.warnings)


def test_compute_truth_rejects_bad_arguments():
    beam = load_beam(BEAMS / "uniform-narrow.json")
    for kw in ({"model": "shell"}, {"selection": "x"}, {"modes": 0}, {"mesh_level": -1}):
        with pytest.raises(BeamInputError):
            compute_truth(beam, static=False, **kw)
