"""Shared fixtures, and the hypothesis profiles.

Hypothesis profiles: CI runs the same examples on every machine; exploration is opt-in.

``reproducible`` (the default) derives the examples from each test's source, so a run on a clean
checkout draws exactly what the last green run drew. ``explore`` draws fresh random examples, to
hunt for new failures: ``python -m pytest -m stress --hypothesis-profile explore``. A failure
found there becomes a named regression test.
"""

import os

# One BLAS/OpenMP thread, as the package's workers and benchmarks pin it: a threaded reduction's
# last bits depend on the thread count, and some tests compare a worker's result with the same
# computation in this process (set before numpy is first imported, which is below).
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402
from paths import BEAMS  # noqa: E402

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


@pytest.fixture(scope="session")
def strip_truth(narrow, tmp_path_factory):
    """A truth.json of the uniform narrow strip from independent references, and its values.

    The first three Euler-Bernoulli frequencies and the elastica tip at P L^2 / EI = 1
    (``reference.strip_target``), written as a truth file that ``prbdm fit --truth`` reads.
    Returns ``(path, omega_rad_s, tip_position_m)``.
    """
    import json

    from reference import strip_target

    t = strip_target(narrow)
    omega = t.omega_truth_rad_s[:3]
    path = tmp_path_factory.mktemp("strip-truth") / "truth.json"
    path.write_text(json.dumps({"omega_rad_s": omega.tolist(),
                                "tip_position_m": t.tip_position_m.tolist(),
                                "tip_displacement_m": t.tip_displacement_m.tolist(),
                                "mac": [1.0] * omega.size}))
    return path, omega, t.tip_position_m


@pytest.fixture(scope="session")
def strip_fit(tmp_path_factory):
    """``strip_fit(n)``: the folder of one ``prbdm fit`` of the narrow strip, made once per n.

    An nR joint-spring eigen fit to the 1D beam truth (2 starts), as the plant and simulation
    commands' tests read it: ``ROOT/fit/fit.json`` and the truth cache ``ROOT/cache``. Tests
    read it and write elsewhere.
    """
    from prbdm_pin.cli import main

    made = {}

    def get(joints: int):
        if joints not in made:
            root = tmp_path_factory.mktemp(f"strip-fit-{joints}r")
            rc = main(["fit", str(BEAMS / "uniform-narrow.json"), "--joints", str(joints),
                       "--truth-model", "beam", "--objective", "eigen", "--stiffness", "joint",
                       "--starts", "2", "--cache-dir", str(root / "cache"),
                       "--out", str(root / "fit"), "-q"])
            assert rc == 0
            made[joints] = root
        return made[joints]

    return get

