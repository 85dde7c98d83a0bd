"""Shared fixtures, and the hypothesis profiles.

Hypothesis profiles: CI runs the same examples on every machine; exploration is opt-in.

``reproducible`` (the default) derives the examples from each test's source, so a run on a clean
checkout draws exactly what the last green run drew. ``explore`` draws fresh random examples, to
hunt for new failures: ``python -m pytest -m stress --hypothesis-profile explore``. A failure
found there becomes a named regression test.
"""

import pytest
from hypothesis import settings
from paths import BEAMS

settings.register_profile("reproducible", derandomize=True, database=None)
settings.register_profile("explore", derandomize=False, database=None)
settings.load_profile("reproducible")


# --- shared fixtures: the shipped beams, loaded once per session (a Beam is frozen) -----------


@pytest.fixture(scope="session")
def narrow():
    """The uniform narrow strip (examples/beams/uniform-narrow.json)."""
    from prbdm_pin.files.beam_file import load_beam

    return load_beam(BEAMS / "uniform-narrow.json")


@pytest.fixture(scope="session")
def tapered():
    """The tapered beam (examples/beams/tapered.json)."""
    from prbdm_pin.files.beam_file import load_beam

    return load_beam(BEAMS / "tapered.json")


@pytest.fixture(scope="session")
def reference_panel():
    """The paper's reference random panel (examples/beams/reference-random.json)."""
    from prbdm_pin.files.beam_file import load_beam

    return load_beam(BEAMS / "reference-random.json")


@pytest.fixture(scope="session")
def truth_of():
    """``compute_truth`` with its results kept for the session (a TruthResult is frozen).

    ``truth_of(beam, **fields)`` computes a truth the first time a test asks for it and hands
    the same result to every later test that asks for the same beam and request.
    """
    from prbdm_pin.truth import compute_truth
    from prbdm_pin.truth.request import TruthRequest

    kept = {}

    def get(beam, **fields):
        key = (beam.fingerprint(), repr(TruthRequest(**fields)))
        if key not in kept:
            kept[key] = compute_truth(beam, **fields)
        return kept[key]

    return get
