"""File formats in one place.

Beam JSON, fit.json, model JSON, truth.json read back, and the URDF / MJCF / JSON exports with the
record each carries; ``model_source.load_model`` reads a PRBDM from whichever of them holds one.
"""
