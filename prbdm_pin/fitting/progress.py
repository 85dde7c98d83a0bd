"""Progress bars of the fits: one tick per start, or per NSGA-II generation."""

from __future__ import annotations

__all__ = ["start_bar", "PymooBar"]


def start_bar(total: int, enabled: bool = True):
    """Return a tqdm bar over a fit's ``total`` starts (a silent one when not ``enabled``)."""
    from tqdm.auto import tqdm

    return tqdm(total=total, disable=not enabled, desc="fit starts", unit="start")


class PymooBar:
    """A pymoo callback driving a tqdm bar, one tick per generation."""

    def __init__(self, total: int):
        from tqdm.auto import tqdm

        self.bar = tqdm(total=total, desc="NSGA-II", unit="gen")

    def __call__(self, algorithm) -> None:
        """Tick the bar once: pymoo calls this after each generation."""
        self.bar.update()

    def close(self) -> None:
        """Close the bar."""
        self.bar.close()
