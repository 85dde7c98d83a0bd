"""Where the repository's files are, for every test (one definition)."""

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BEAMS = ROOT / "examples" / "beams"
