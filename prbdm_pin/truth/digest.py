"""Digest of the code a truth depends on: the truth package and every package module it imports.

A cached truth must never outlive the code that computed it. The dependency set is the
transitive closure of the package-internal imports of ``prbdm_pin.truth`` (found in the source by
``ast``, including imports inside functions), plus the ``__init__`` of every package on the way;
so an edit of, e.g., ``geometry.half_width_at`` changes the digest, while an edit of the fitting
or simulation code (which the truth never imports) does not. The versions of the numerical
libraries the truth runs on are part of the digest too.
"""

from __future__ import annotations

import ast
import functools
import hashlib
import re
from importlib import metadata
from pathlib import Path

__all__ = ["TRUTH_MODULES", "code_digest", "digest_of", "truth_modules"]

_PACKAGE = "prbdm_pin"
# The files the digest covers, written out so that moving or adding a module never silently
# changes what a cache key stands for: a test holds this list equal to the import closure
# :func:`truth_modules` finds in the source, so a move fails that test until the list is updated.
TRUTH_MODULES = (
    "prbdm_pin/__init__.py",
    "prbdm_pin/errors.py",
    "prbdm_pin/io/__init__.py",
    "prbdm_pin/io/atomic.py",
    "prbdm_pin/io/jsonfile.py",
    "prbdm_pin/io/records.py",
    "prbdm_pin/member/__init__.py",
    "prbdm_pin/member/beam_dict.py",
    "prbdm_pin/member/checks.py",
    "prbdm_pin/member/design.py",
    "prbdm_pin/member/geometry.py",
    "prbdm_pin/member/kirchhoff.py",
    "prbdm_pin/member/material.py",
    "prbdm_pin/member/round_section.py",
    "prbdm_pin/member/section.py",
    "prbdm_pin/member/section_law.py",
    "prbdm_pin/member/section_table.py",
    "prbdm_pin/options/__init__.py",
    "prbdm_pin/options/checks.py",
    "prbdm_pin/options/choices.py",
    "prbdm_pin/options/limits.py",
    "prbdm_pin/options/validate.py",
    "prbdm_pin/truth/__init__.py",
    "prbdm_pin/truth/anticlastic.py",
    "prbdm_pin/truth/argyris_forms.py",
    "prbdm_pin/truth/beam.py",
    "prbdm_pin/truth/beam_static.py",
    "prbdm_pin/truth/beam_derivatives.py",
    "prbdm_pin/truth/beam_gravity.py",
    "prbdm_pin/truth/beam_spatial.py",
    "prbdm_pin/truth/beam_timoshenko.py",
    "prbdm_pin/truth/cache.py",
    "prbdm_pin/truth/cache_clean.py",
    "prbdm_pin/truth/compute.py",
    "prbdm_pin/truth/compute_derivatives.py",
    "prbdm_pin/truth/corner_static.py",
    "prbdm_pin/truth/derivative_rules.py",
    "prbdm_pin/truth/digest.py",
    "prbdm_pin/truth/elastica.py",
    "prbdm_pin/truth/elastica_adjoint.py",
    "prbdm_pin/truth/elastica_derivatives.py",
    "prbdm_pin/truth/elastica_modes.py",
    "prbdm_pin/truth/entry.py",
    "prbdm_pin/truth/estimate.py",
    "prbdm_pin/truth/feature_mesh.py",
    "prbdm_pin/truth/law_mesh.py",
    "prbdm_pin/truth/mesh.py",
    "prbdm_pin/truth/mesh_budget.py",
    "prbdm_pin/truth/modal.py",
    "prbdm_pin/truth/mode_kinds.py",
    "prbdm_pin/truth/modes.py",
    "prbdm_pin/truth/morph.py",
    "prbdm_pin/truth/ordering.py",
    "prbdm_pin/truth/plate.py",
    "prbdm_pin/truth/plate_derivatives.py",
    "prbdm_pin/truth/plate_elements.py",
    "prbdm_pin/truth/plate_shape.py",
    "prbdm_pin/truth/plate_static.py",
    "prbdm_pin/truth/request.py",
    "prbdm_pin/truth/result.py",
    "prbdm_pin/truth/self_weight.py",
    "prbdm_pin/truth/settings.py",
    "prbdm_pin/truth/shape_forms.py",
    "prbdm_pin/truth/solid.py",
    "prbdm_pin/truth/solid_fe.py",
    "prbdm_pin/truth/solid_nonlinear.py",
    "prbdm_pin/truth/timoshenko_criterion.py",
    "prbdm_pin/truth/timoshenko_elements.py",
    "prbdm_pin/truth/timoshenko_sections.py",
    "prbdm_pin/truth/tip_response.py",
    "prbdm_pin/truth/tube_mesh.py",
    "prbdm_pin/truth/tube_solid.py",
    "prbdm_pin/truth/vtu.py",
    "prbdm_pin/version.py",
)

# libraries whose numerics the truth's numbers come from
_LIBRARIES = ("numpy", "scipy", "scikit-fem")


def _module_file(root: Path, name: str) -> Path | None:
    """Return the source file of package module ``name`` (dotted) under ``root``.

    ``root`` is the folder holding the package; None when ``name`` is not a module of it.
    """
    parts = name.split(".")
    if parts[0] != _PACKAGE:
        return None
    base = root.joinpath(*parts)
    for p in (base.with_suffix(".py"), base / "__init__.py"):
        if p.is_file():
            return p
    return None


def _module_name(root: Path, path: Path) -> tuple[str, bool]:
    """Dotted module name of ``path`` and whether it is a package ``__init__``."""
    rel = path.relative_to(root).with_suffix("")
    parts = list(rel.parts)
    is_pkg = parts[-1] == "__init__"
    if is_pkg:
        parts = parts[:-1]
    return ".".join(parts), is_pkg


# an import statement at the start of a line, with a parenthesised name list or backslash
# continuations; ``_IMPORT_WORD`` counts every ``import`` keyword the file may hold
_IMPORT_STMT = re.compile(
    rb"^[ \t]*(?:import[ \t]|from[ \t]+[.\w]+[ \t]+import\b)"
    rb"(?:[^\n(#]*\([^)]*\)[^\n]*|[^\n]*(?:\\\n[^\n]*)*)", re.M)
_IMPORT_WORD = re.compile(rb"\bimport\b")


def _import_nodes(path: Path) -> list[ast.stmt]:
    """Return the import statements of ``path`` (all of them, also those inside functions).

    Parsing a whole module is most of the digest's cost, so only the import statements are
    parsed when every ``import`` word of the file is in one of them; otherwise (an ``import``
    after ``;`` or ``:``, or in a comment or a string) the whole module is. A string line that
    looks like an import can only add a module to the closure, never drop one.
    """
    source = path.read_bytes()
    found = [m.group() for m in _IMPORT_STMT.finditer(source)]
    if sum(len(_IMPORT_WORD.findall(s)) for s in found) == len(_IMPORT_WORD.findall(source)):
        try:
            tree = ast.parse(b"\n".join(s.strip() for s in found), filename=str(path))
            return list(tree.body)
        except SyntaxError:
            pass
    tree = ast.parse(source, filename=str(path))
    return [n for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom))]


def _imported_names(root: Path, path: Path) -> set[str]:
    """Dotted names of every module (and possible submodule) that ``path`` imports."""
    name, is_pkg = _module_name(root, path)
    package = name.split(".") if is_pkg else name.split(".")[:-1]
    out: set[str] = set()
    for node in _import_nodes(path):
        if isinstance(node, ast.Import):
            out.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                keep = len(package) - (node.level - 1)
                if keep <= 0:
                    continue
                base = ".".join(package[:keep] + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            out.add(base)
            # ``from pkg import name``: name may be a submodule
            out.update(f"{base}.{alias.name}" for alias in node.names)
    # importing a.b.c runs a/__init__ and a/b/__init__ too
    return {".".join(n.split(".")[:k]) for n in out for k in range(1, n.count(".") + 2)}


def truth_modules(root: Path | None = None) -> list[Path]:
    """Source files the truth package depends on, sorted: the closure of its package imports.

    Parameters
    ----------
    root : Path, optional
        Folder holding the ``prbdm_pin`` package (default: the installed one).
    """
    root = Path(__file__).resolve().parents[2] if root is None else Path(root)
    todo = sorted((root / _PACKAGE / "truth").glob("*.py"))
    seen: set[Path] = set()
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        for name in _imported_names(root, path):
            dep = _module_file(root, name)
            if dep is not None and dep not in seen:
                todo.append(dep)
    return sorted(seen)


def digest_of(root: Path | None = None) -> str:
    """Return the code digest: SHA-256 of the truth's modules and the libraries' versions.

    It digests the relative paths and bytes of the files of :data:`TRUTH_MODULES` under
    ``root`` (a listed file that is missing digests as absent) and the numerical libraries'
    versions.
    """
    root = Path(__file__).resolve().parents[2] if root is None else Path(root)
    h = hashlib.sha256()
    for rel in TRUTH_MODULES:
        path = root / rel
        h.update(rel.encode() + b"\0")
        if not path.is_file():
            h.update(b"absent\0")
            continue
        data = path.read_bytes()
        h.update(len(data).to_bytes(8, "little") + data)
    for lib in _LIBRARIES:
        try:
            version = metadata.version(lib)
        except metadata.PackageNotFoundError:
            version = "absent"
        h.update(f"{lib}=={version}\0".encode())
    return h.hexdigest()


@functools.lru_cache(maxsize=1)
def code_digest() -> str:
    """:func:`digest_of` the installed package (computed once per process)."""
    return digest_of()
