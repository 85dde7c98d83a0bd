"""scripts/docs_tables.py: a benchmark run with its default output also writes the docs table; a
run with another output (a test, a variant study) leaves the docs alone."""

from __future__ import annotations

import importlib.util

from paths import ROOT


def _module():
    spec = importlib.util.spec_from_file_location("docs_tables",
                                                  ROOT / "scripts" / "docs_tables.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_default_output_also_writes_the_docs_table(tmp_path):
    mod = _module()
    default = tmp_path / "results" / "bench_x.md"
    written = mod.write_table(default, "| a |\n|---|\n| 1 |\n", default, "bench_x",
                              tmp_path / "docs")
    docs = tmp_path / "docs" / "bench_x.md"
    assert written == [default, docs]
    assert docs.read_text() == default.read_text() == "| a |\n|---|\n| 1 |\n"


def test_other_output_leaves_the_docs_alone(tmp_path):
    mod = _module()
    out = tmp_path / "elsewhere" / "x.md"
    written = mod.write_table(out, "text\n", tmp_path / "results" / "bench_x.md", "bench_x",
                              tmp_path / "docs")
    assert written == [out]
    assert out.read_text() == "text\n"
    assert not (tmp_path / "docs").exists()


def test_docs_tables_folder_is_the_one_the_benchmarks_page_includes():
    mod = _module()
    page = (ROOT / "docs" / "benchmarks.md").read_text(encoding="utf-8")
    assert mod.DOCS_TABLES == ROOT / "docs" / "benchmarks"
    for table in sorted(mod.DOCS_TABLES.glob("*.md")):
        assert f"{{include}} benchmarks/{table.name}" in page, f"{table.name} is not on the page"
