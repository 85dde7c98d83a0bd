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

__all__ = ["code_digest", "digest_of", "truth_modules"]

_PACKAGE = "prbdm_pin"
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

    It digests the relative paths and bytes of :func:`truth_modules` under ``root`` and the
    numerical libraries' versions.
    """
    root = Path(__file__).resolve().parents[2] if root is None else Path(root)
    h = hashlib.sha256()
    for path in truth_modules(root):
        h.update(path.relative_to(root).as_posix().encode() + b"\0")
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
