"""Hypothesis profiles: CI runs the same examples on every machine; exploration is opt-in.

``reproducible`` (the default) derives the examples from each test's source, so a run on a clean
checkout draws exactly what the last green run drew. ``explore`` draws fresh random examples, to
hunt for new failures: ``python -m pytest -m stress --hypothesis-profile explore``. A failure
found there becomes a named regression test.
"""

from hypothesis import settings

settings.register_profile("reproducible", derandomize=True, database=None)
settings.register_profile("explore", derandomize=False, database=None)
settings.load_profile("reproducible")
