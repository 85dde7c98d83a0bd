"""Progress bars of the fits: one tick per start, or per NSGA-II generation."""

from __future__ import annotations

from ..io.progress import progress_bar

__all__ = ["start_bar", "PymooBar"]


def start_bar(total: int, enabled: bool = True):
    """Return a tqdm bar over a fit's ``total`` starts (a silent one when not ``enabled``)."""
    return progress_bar(total, enabled=enabled, desc="fit starts", unit="start")


class PymooBar:
    """A pymoo callback driving a tqdm bar, one tick per generation."""

    def __init__(self, total: int):
        self.bar = progress_bar(total, desc="NSGA-II", unit="gen")

    def __call__(self, algorithm) -> None:
        """Tick the bar once: pymoo calls this after each generation."""
        self.bar.update()

    def close(self) -> None:
        """Close the bar."""
        self.bar.close()
