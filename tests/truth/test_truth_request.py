"""TruthRequest carries what ``compute_truth`` and ``truth_gradient`` are asked: checked when
built (each error names its field), its defaults written once, its recorded form unchanged."""

from __future__ import annotations

import dataclasses
import inspect

import numpy as np
import pytest
from paths import BEAMS

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError
from prbdm_pin.truth import TruthRequest, compute_truth
from prbdm_pin.truth.request import RECORDED_FIELDS

BEAM = BEAMS / "uniform-narrow.json"


@pytest.mark.parametrize("field, value", [
    ("model", "shell"), ("model", 3), ("modes", 0), ("modes", 2.0), ("modes", True),
    ("mesh_level", 7), ("mesh_level", -1), ("selection", "x"), ("large_deflection", "big"),
    ("error_tol_pct", 0.0), ("error_tol_pct", "0.5"), ("static", "yes"), ("n_computed", 0),
    ("check_convergence", 1),
])
def test_every_field_is_checked_when_built_and_named(field, value):
    with pytest.raises(BeamInputError, match=rf"^{field} = "):
        TruthRequest(**{field: value})
    with pytest.raises(BeamInputError, match=rf"^truth_request\.{field} = "):
        TruthRequest.from_dict({field: value})


def test_a_request_is_frozen_and_numpy_scalars_become_python_ones():
    r = TruthRequest(modes=np.int64(3), mesh_level=np.int32(1), error_tol_pct=np.float64(0.2),
                     static=np.bool_(False))
    assert type(r.modes) is int and type(r.mesh_level) is int and type(r.static) is bool
    assert type(r.error_tol_pct) is float
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.modes = 4
    with pytest.raises(BeamInputError, match="modes = 0"):
        dataclasses.replace(r, modes=0)


def test_the_recorded_form_keeps_its_keys_and_adds_only_what_differs():
    assert tuple(TruthRequest().to_dict()) == RECORDED_FIELDS
    odd = TruthRequest(model="beam", modes=3, static=False, n_computed=40)
    d = odd.to_dict()
    assert tuple(d) == RECORDED_FIELDS + ("static", "n_computed")
    assert TruthRequest.from_dict(d) == odd
    # a file written before the extra fields existed reads with their defaults
    old = {k: d[k] for k in RECORDED_FIELDS}
    assert TruthRequest.from_dict(old) == dataclasses.replace(odd, static=True, n_computed=25)


def test_the_defaults_live_in_the_request_only():
    for fn in (compute_truth, pp.truth_gradient):
        params = inspect.signature(fn).parameters
        names = {f.name for f in dataclasses.fields(TruthRequest)}
        assert not names & set(params), fn.__name__
        assert params["request"].default is None


def test_keywords_build_the_request_a_request_gives():
    beam = pp.load_beam(BEAM)
    request = TruthRequest(model="beam", modes=3, static=False)
    a = compute_truth(beam, request)
    b = compute_truth(beam, model="beam", modes=3, static=False)
    assert np.array_equal(a.omega_rad_s, b.omega_rad_s) and a.static_linear is None
    assert np.array_equal(request.compute(beam).omega_rad_s, a.omega_rad_s)
    g = pp.truth_gradient(beam, ("thickness",), request)
    assert np.array_equal(g.omega_rad_s, pp.truth_gradient(
        beam, ("thickness",), model="beam", modes=3, static=False).omega_rad_s)


def test_a_request_is_given_once_and_whole():
    beam = pp.load_beam(BEAM)
    with pytest.raises(BeamInputError, match=r"model='beam'"):
        compute_truth(beam, "beam")
    with pytest.raises(TypeError, match="not both"):
        compute_truth(beam, TruthRequest(model="beam"), modes=3)
    with pytest.raises(TypeError, match=r"\['mesh'\]"):
        compute_truth(beam, model="beam", mesh=1)
    with pytest.raises(BeamInputError, match="must be one of"):
        pp.truth_gradient(beam, ("thickness",), TruthRequest(model="solid"))
