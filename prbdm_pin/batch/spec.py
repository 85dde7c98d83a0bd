"""What a batch computes and over which beams.

The fit settings (the joints, the fit's options and the truth model), the spec that determines
the results, one task per beam of a shard.

No numpy at import (see the package docstring): the settings are checked with plain Python.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import BeamInputError, InputTypeError
from ..options.checks import check_choice, check_int
from ..options.choices import TRUTH_MODELS
from ..options.objects import FitOptions
from ..options.validate import MAX_SEED, MAX_SHARD_BEAMS, check_joints, check_type

if TYPE_CHECKING:
    from ..member.geometry import Beam

__all__ = ["FitSettings", "BeamTask", "BatchSpec", "parse_shard", "plan_tasks", "check_int",
           "check_choice"]


@dataclass(frozen=True)
class FitSettings:
    """What every beam of a batch computes: one truth and one fit.

    Attributes
    ----------
    joints : int
        Number of PRBDM joints n (n + 1 links).
    options : FitOptions
        The fit's options, as for :func:`prbdm_pin.fit` (its ``seed`` is replaced by each
        beam's own fit seed, drawn from the batch's root seed).
    truth_model : str
        ``"plate"``, ``"plate-morley"``, ``"solid"`` or ``"beam"`` (1D Euler-Bernoulli,
        milliseconds).
    cache_dir : str or None
        Truth cache folder (does not change results, so it is not part of the manifest).

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> options = pp.FitOptions(objective="eigen", stiffness="joint", starts=1)
    >>> settings = pp.FitSettings(joints=2, options=options, truth_model="beam")
    >>> settings.joints, settings.truth_model
    (2, 'beam')
    >>> pp.FitSettings(joints=2, truth_model="shell")
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: truth_model = 'shell': must be one of plate, ...
    """

    joints: int
    options: FitOptions = field(default_factory=FitOptions)
    truth_model: str = "plate"
    cache_dir: str | None = None

    def __post_init__(self) -> None:
        """Check the joints, the options and the truth model (BeamInputError naming the field)."""
        from ..chain.layout import check_min_fraction

        check_joints(self.joints)  # the command line's --joints cap (PRBDM_MAX_JOINTS)
        if not isinstance(self.options, FitOptions):
            raise InputTypeError(f"options = {self.options!r:.80}: must be a FitOptions")
        check_min_fraction(self.options.min_fraction, self.joints)
        check_choice("truth_model", self.truth_model, TRUTH_MODELS)

    def replace(self, **changes: Any) -> FitSettings:
        """Return a copy with ``changes`` applied.

        ``changes`` may name ``joints``, ``truth_model``, ``cache_dir`` or any option of
        :class:`FitOptions`.
        """
        own = {k: changes.pop(k) for k in ("joints", "truth_model", "cache_dir")
               if k in changes}
        if changes:
            own["options"] = self.options.replace(**changes)
        return dataclasses.replace(self, **own)

    @property
    def n_frequencies(self) -> int:
        """Frequencies matched (``options.frequencies`` or ``joints``)."""
        f = self.options.frequencies
        return self.joints if f is None else f


@dataclass(frozen=True)
class BeamTask:
    """One work item: the beam of index ``index`` and what to compute for it.

    ``beam`` is None for a random batch: the worker regenerates beam ``index`` from ``seed``
    (cheaper to ship than the beam, and reproducible anywhere).

    Attributes
    ----------
    index : int
        The beam's index in the batch (0-based).
    seed : int
        The batch's root seed.
    settings : FitSettings
        What is fitted (joints, fit options, truth model).
    name : str
        The beam's name in the records (``beam-<index>`` or the beam file's stem).
    beam : Beam or None
        The beam of a beam-file batch; None for a random batch.
    """

    index: int
    seed: int
    settings: FitSettings
    name: str
    beam: Beam | None = None


@dataclass(frozen=True)
class BatchSpec:
    """The arguments that determine a batch's results (they go into ``DIR/batch.json``).

    Attributes
    ----------
    seed : int
        Root seed of the per-beam ``SeedSequence``.
    settings : FitSettings
    n_beams : int or None
        Number of random beams; None when the beams come from ``beams_dir``.
    beams_dir : str or None
        Folder of beam JSON files (sorted by file name; index = position).
    shard : tuple of int
        ``(i, N)``: this run takes the beams with index % N == i.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> options = pp.FitOptions(objective="eigen", stiffness="joint", starts=1)
    >>> settings = pp.FitSettings(joints=2, options=options, truth_model="beam")
    >>> spec = pp.BatchSpec(seed=1, settings=settings, n_beams=3, shard=(0, 1))
    >>> spec.n_beams, spec.shard
    (3, (0, 1))
    """

    seed: int
    settings: FitSettings
    n_beams: int | None = None
    beams_dir: str | None = None
    shard: tuple[int, int] = (0, 1)

    def __post_init__(self) -> None:
        """Check the seed, the beams and the shard (BeamInputError naming the field)."""
        check_type("settings", self.settings, FitSettings)
        check_int("seed", self.seed, 0, high=MAX_SEED)
        if (self.n_beams is None) == (self.beams_dir is None):
            raise BeamInputError(
                f"beams = {self.n_beams!r}, beams_dir = {self.beams_dir!r}: give exactly one"
            )
        if self.n_beams is not None:
            check_int("beams", self.n_beams, 1)
        if isinstance(self.shard, (str, bytes)) or not hasattr(self.shard, "__len__") \
                or len(self.shard) != 2:
            raise InputTypeError(f"shard = {self.shard!r:.60}: must be a pair (i, N)")
        i, n = self.shard
        check_int("shard count", n, 1)
        if not (isinstance(i, int) and 0 <= i < n):
            raise BeamInputError(f"shard = {i}/{n}: the index must be in 0 .. {n - 1}")
        if self.n_beams is not None and (self.n_beams - i + n - 1) // n > MAX_SHARD_BEAMS:
            raise BeamInputError(f"beams = {self.n_beams}: {(self.n_beams - i + n - 1) // n} "
                                 f"beams in one shard (at most {MAX_SHARD_BEAMS}, as prbdm "
                                 "batch --beams): split the study into shards")


def parse_shard(text: str) -> tuple[int, int]:
    """Parse ``"i/N"`` into ``(i, N)`` with 0 <= i < N."""
    try:
        i_s, n_s = text.split("/")
        i, n = int(i_s), int(n_s)
    except ValueError:
        raise BeamInputError(f"shard = {text!r}: must be i/N, e.g. 0/4") from None
    if n < 1 or not 0 <= i < n:
        raise BeamInputError(f"shard = {text!r}: needs N >= 1 and 0 <= i < N")
    return i, n


def plan_tasks(spec: BatchSpec) -> list[BeamTask]:
    """Every beam of this run's shard, by ascending index.

    Beam files are read and validated here, before any work starts, and shipped to the workers
    (a cluster needs no shared file system).
    """
    i_shard, n_shard = spec.shard
    if spec.n_beams is not None:
        return [BeamTask(i, spec.seed, spec.settings, f"beam-{i}")
                for i in range(i_shard, spec.n_beams, n_shard)]
    from ..files.beam_file import load_beam

    folder = Path(spec.beams_dir)
    if not folder.is_dir():
        raise BeamInputError(f"beams_dir = {str(folder)!r}: not a folder")
    files = sorted(folder.glob("*.json"))
    if not files:
        raise BeamInputError(f"beams_dir = {str(folder)!r}: holds no *.json beam files")
    tasks = []
    for i, path in enumerate(files):
        if i % n_shard != i_shard:
            continue
        try:
            beam = load_beam(path)
        except BeamInputError as exc:
            raise BeamInputError(f"beam file {path.name}: {exc}") from None
        tasks.append(BeamTask(i, spec.seed, spec.settings, path.stem, beam))
    return tasks

