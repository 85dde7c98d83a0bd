"""Atomic writes: the target appears whole or not at all, no temporary file is left behind."""

from __future__ import annotations

import json
import os

import pytest

from prbdm_pin.io.atomic import AtomicFile, atomic_path, atomic_write_bytes, atomic_write_json


def test_text_bytes_and_json_land_whole(tmp_path):
    p = atomic_write_json(tmp_path / "sub" / "a.json", {"x": [1.0, 2.0]}, indent=1)
    assert json.loads(p.read_text()) == {"x": [1.0, 2.0]} and p.read_text().endswith("\n")
    assert atomic_write_bytes(tmp_path / "b.bin", b"\x00\x01").read_bytes() == b"\x00\x01"
    assert sorted(q.name for q in tmp_path.iterdir()) == ["b.bin", "sub"]


def test_a_failed_block_keeps_the_old_file_and_no_temporary(tmp_path):
    p = tmp_path / "entry.npz"
    p.write_bytes(b"old")
    with pytest.raises(RuntimeError):
        with AtomicFile(p, "wb", fsync=True, prefix=".entry-") as fh:
            fh.write(b"new, half")
            raise RuntimeError("killed")
    assert p.read_bytes() == b"old"
    assert [q.name for q in tmp_path.iterdir()] == ["entry.npz"]
    with AtomicFile(p, "wb", fsync=True) as fh:
        fh.write(b"new")
    assert p.read_bytes() == b"new"


def test_atomic_path_renames_on_success_only(tmp_path):
    p = tmp_path / "fig.png"
    with pytest.raises(OSError):
        with atomic_path(p) as tmp:
            raise OSError("writer failed")
    assert not os.path.exists(tmp) and list(tmp_path.iterdir()) == []
    with atomic_path(p) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(b"png")
    assert p.read_bytes() == b"png" and [q.name for q in tmp_path.iterdir()] == ["fig.png"]


def test_the_umask_decides_the_mode(tmp_path):
    old = os.umask(0o027)
    try:
        p = atomic_write_bytes(tmp_path / "m", b"")
    finally:
        os.umask(old)
    assert p.stat().st_mode & 0o777 == 0o640
