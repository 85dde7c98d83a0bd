"""File formats in one place.

Beam JSON, fit.json, model JSON, truth.json read back, and the URDF / MJCF / JSON exports with the
record each carries.
"""
