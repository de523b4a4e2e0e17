"""The repository's documents stand on their own: links resolve, no doc outside the repo is cited."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
# The documents beside the clone (the shared folder and its parent), whatever their names:
# the repository may use the shared data, but must not send a reader to those documents.
OUTSIDE_FOLDERS = (ROOT.parent, ROOT.parent / "shared")
TEXT_SUFFIXES = {".py", ".md", ".yaml", ".yml", ".toml", ".txt", ""}


def _files():
    for folder in ("uma", "tests", "docs", "scripts", "codecs", "scenarios", "traces", ".ci"):
        for path in (ROOT / folder).rglob("*"):
            if path.is_file() and path.suffix in TEXT_SUFFIXES and "__pycache__" not in path.parts:
                yield path
    yield from (ROOT / name for name in ("README.md", "Makefile", "pyproject.toml"))


def _outside_documents() -> set[str]:
    return {
        doc.name
        for folder in OUTSIDE_FOLDERS
        if folder.is_dir()
        for doc in folder.glob("*.md")
        if doc.name != "README.md"  # a name too common to tell a citation from a mention
    }


def test_no_file_cites_a_document_outside_the_repository():
    outside = _outside_documents()
    if not outside:
        pytest.skip("no documents beside the clone to check against")
    cited = [
        f"{path.relative_to(ROOT)}: {name}"
        for path in _files()
        for name in sorted(outside)
        if name in path.read_text(encoding="utf-8", errors="replace")
    ]
    assert not cited, cited


def test_every_relative_link_in_the_docs_resolves():
    broken = []
    for doc in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        for target in re.findall(r"\]\(([^)#\s]+)", doc.read_text(encoding="utf-8")):
            if "://" in target:
                continue
            if not (doc.parent / target).exists():
                broken.append(f"{doc.relative_to(ROOT)} -> {target}")
    assert not broken, broken


def test_the_readme_is_what_a_user_needs_under_30_kb():
    size = len((ROOT / "README.md").read_bytes())
    assert size < 30_000, f"README.md is {size} bytes; move history and detail into docs/"
