"""Fuzz the calibration data reader: CSV text built from header names of all three kinds
(ring-down, driven, FRF), numbers, NaN, bad tokens and ragged rows must give one of the three
data kinds, checked, or a BeamInputError naming the file; never another exception."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from prbdm_pin.errors import BeamInputError
from prbdm_pin.fitting.calibration_data import RingDown
from prbdm_pin.fitting.calibration_measured import (
    DrivenTrajectory,
    FrequencyResponse,
    read_calibration_data,
)

NAMES = ["t_s", "f_hz", "tip_z_m", "y:tip_z", "u:tip_force_z", "u:tip_z", "base_accel_z_m_s2",
         "tip_z/tip_force_z_re", "tip_z/tip_force_z_im", "tip_z_m/base_accel_z_m_s2_re",
         "tip_z_m/base_accel_z_m_s2_im", "tip_z/foo_re", "q[0]_rad", "", "a/b/c_re"]
TOKENS = st.one_of(st.floats(-1e3, 1e3, allow_nan=False).map(repr), st.sampled_from(
    ["nan", "inf", "-0", "1e999", "x", "", " 1", "0x1"]))
FAST = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@FAST
@given(head=st.lists(st.sampled_from(NAMES), min_size=1, max_size=5),
       rows=st.integers(0, 14), data=st.data())
def test_the_reader_returns_checked_data_or_refuses_by_name(tmp_path_factory, head, rows, data):
    lines = [",".join(head)]
    for i in range(rows):
        width = data.draw(st.sampled_from([len(head), len(head), len(head), len(head) + 1]))
        if data.draw(st.booleans()):  # mostly well-formed: increasing first column
            cells = [repr(float(i + 1))] + [repr(float(np.cos(i + j))) for j in range(width - 1)]
        else:
            cells = [data.draw(TOKENS) for _ in range(width)]
        lines.append(",".join(cells))
    path = tmp_path_factory.mktemp("fuzz") / "data.csv"
    path.write_text("\n".join(lines) + "\n")
    try:
        got = read_calibration_data(path)
    except BeamInputError as exc:
        assert str(exc).startswith(f"data {str(path)!r}: "), exc
        return
    assert isinstance(got, (RingDown, DrivenTrajectory, FrequencyResponse))
    # a returned kind is checked: finite, increasing, enough samples
    axis = got.f_hz if isinstance(got, FrequencyResponse) else got.t_s
    values = got.H if isinstance(got, FrequencyResponse) else got.y
    assert axis.size >= 8 and np.all(np.diff(axis) > 0) and np.all(np.isfinite(values))
