"""Bytes on disk.

Atomic writes, JSON the package did not write (size and depth capped), the plain-data form of the
result dataclasses, and whole output folders that are never left half-written.
"""
