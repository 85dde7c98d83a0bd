"""Calibrating a section-table member: its stiffness and inertia scales, against the planform
member it tabulates and against a ring-down of known frequency and damping."""

from __future__ import annotations

import numpy as np
import pytest
from paths import BEAMS
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.fitting.calibration_data import ring_down
from prbdm_pin.member.section_law import section_properties

LENGTHS = np.array([0.02, 0.3, 0.4, 0.28])
SPRINGS = np.array([3000.0, 2500.0, 1500.0])
SHIFT, ZETA = 1.03, 0.01  # mode 1 of the data: 1.03 omega_1, ratio 0.01


def _members():
    beam = pp.load_beam(BEAMS / "uniform-narrow.json")
    p = section_properties(beam, beam.x_m)
    table = pp.table_beam(beam.x_m, pp.SectionTable(
        EI_y_Nm2=p.EI_y_Nm2, EI_z_Nm2=p.EI_z_Nm2, GJ_Nm2=p.GJ_Nm2, rhoA_kg_m=p.rhoA_kg_m,
        rhoI_y_kg_m=p.rhoI_y_kg_m, rhoI_z_kg_m=p.rhoI_z_kg_m, rhoI_x_kg_m=p.rhoI_x_kg_m),
        material=beam.material)
    return beam, table


def test_a_table_calibrates_its_scales_as_the_planform_its_e():
    beam, table = _members()
    out = {}
    for b in (beam, table):
        model = pp.build_model(b, LENGTHS, SPRINGS)
        w = SHIFT * model.natural_frequencies()[0]
        t = np.arange(1000) / 250.0
        # mode 1 alone, as the modal damping form rings: exp(-zeta w t) cos(w_d t)
        y = np.exp(-ZETA * w * t) * np.cos(w * np.sqrt(1 - ZETA**2) * t)
        out[b.section is None] = pp.calibrate(model, ring_down(t, y[:, None], ["tip_z"]),
                                              "E,damping[0]")
    planform, tab = out[True], out[False]
    # noiseless, one mode: the scale is SHIFT^2 to the solver's tolerance (1e-8 on the
    # residual's relative change: 1e-7 here), the same for both members
    assert planform.E_scale == pytest.approx(SHIFT**2, rel=1e-7)
    assert tab.E_scale == pytest.approx(SHIFT**2, rel=1e-7)
    assert tab.values[1] == pytest.approx(ZETA, rel=1e-6)
    # the table's value is the scale itself, the planform's the scaled E in Pa
    assert tab.values[0] == pytest.approx(tab.E_scale, rel=50 * EPS)  # one product, rounding
    assert planform.values[0] == pytest.approx(beam.material.E_Pa * planform.E_scale,
                                               rel=50 * EPS)  # one product, rounding
    # the calibrated table is the table scaled: its stiffnesses by s_E (one product each, so
    # 2 EPS), its inertias by 1
    sec = tab.model.beam.section
    np.testing.assert_allclose(sec.EI_y_Nm2, tab.E_scale * table.section.EI_y_Nm2, rtol=2 * EPS)
    np.testing.assert_allclose(sec.GJ_Nm2, tab.E_scale * table.section.GJ_Nm2, rtol=2 * EPS)
    np.testing.assert_array_equal(sec.rhoA_kg_m, table.section.rhoA_kg_m)
    # and its chain is the calibrated planform's (the same properties, another path; the two
    # scales agree to the solver's 1e-7)
    np.testing.assert_allclose(tab.model.natural_frequencies(),
                               planform.model.natural_frequencies(), rtol=1e-7)
