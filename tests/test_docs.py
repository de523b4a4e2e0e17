"""The repository's documents stand on their own: links resolve, no doc outside the repo is cited."""

import re
from pathlib import Path

ROOT = Path(__file__).parents[1]
OUTSIDE = ("CONVENTIONS.md", "ARCHITECTURE.md", "DEVELOPERS.md")
TEXT_SUFFIXES = {".py", ".md", ".yaml", ".yml", ".toml", ".txt", ""}


def _files():
    for folder in ("uma", "tests", "docs", "scripts", "codecs", "scenarios", "traces", ".ci"):
        for path in (ROOT / folder).rglob("*"):
            if path.is_file() and path.suffix in TEXT_SUFFIXES and "__pycache__" not in path.parts:
                yield path
    yield from (ROOT / name for name in ("README.md", "Makefile", "pyproject.toml"))


def test_no_file_cites_a_document_outside_the_repository():
    me = Path(__file__).resolve()
    cited = [
        f"{path.relative_to(ROOT)}: {name}"
        for path in _files()
        if path.resolve() != me
        for name in OUTSIDE
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
    assert size < 30 * 1024, f"README.md is {size} bytes; move history and detail into docs/"
