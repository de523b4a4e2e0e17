"""Render README.md's measured figures from the bench records in docs/results/.

    python scripts/readme_tables.py write    # regenerate every block of README.md in place
    python scripts/readme_tables.py check    # exit 1 naming the first line that differs

A block is `<!-- fig RENDERER FILE.json... [key=value...] -->` ... `<!-- /fig -->`. When the
opening marker ends its line the block is a table or paragraph (scripts/readme_blocks.py),
rebuilt whole and followed by a line naming the command and commit of each record it reads.
Otherwise it is inline on one line: `<!-- fig value FILE.json PATH [FORMAT] -->` is one number
of the record's `result` (dotted PATH, Python format spec), and `<!-- fig source FILE.json... -->`
in the same paragraph names the records' commands and commits. The records
are written by scripts/record_bench.py; each must hold `command`, `commit` and `result`.
Exit 0 up to date (or written); 1 a block differs, a record is missing or incomplete, or a
table row with measured figures stands outside any block; 2 bad usage.
"""

from __future__ import annotations

import json
import re
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

import readme_blocks  # noqa: E402  (beside this file)

__all__ = ["FiguresError", "Record", "check", "load_record", "main", "render", "value_at"]

ROOT = Path(__file__).resolve().parent.parent
RESULTS = "docs/results"
_BLOCK = re.compile(r"<!-- fig (?P<spec>[^>]*?) -->(?P<body>.*?)<!-- /fig -->", re.S)
_COMMIT = re.compile(r"^[0-9a-f]{40}$")
# A markdown table row holding a decimal figure (0.159, 3,116, 29.5 / 0.862): measured-looking.
_FIGURE_ROW = re.compile(r"^\s*\|.*\d[.,]\d.*\|\s*$")


class FiguresError(ValueError):
    """A block, a record or the README is not as it should be; the message names where."""


@dataclass(frozen=True)
class Record:
    """One bench record of docs/results/ (scripts/record_bench.py)."""

    name: str  # the file's name, e.g. headline.json
    command: str
    commit: str
    date_utc: str
    load_1m: Any
    cores: Any
    duration_s: Any
    result: dict[str, Any]
    raw: dict[str, Any]

    def provenance(self) -> str:
        """`command` on commit abc1234, linked to the record (which holds date, load, time)."""
        return f"`{self.command}` on `{self.commit[:7]}` ([record]({RESULTS}/{self.name}))"


def load_record(results_dir: Path, name: str, where: str) -> Record:
    """The record `name` in `results_dir`; FiguresError naming `where` if absent or incomplete."""
    path = results_dir / name
    if not name.endswith(".json") or "/" in name:
        raise FiguresError(f"{where}: expected a file name like headline.json, got {name!r}")
    if not path.is_file():
        raise FiguresError(f"{where}: names {RESULTS}/{name}, which does not exist")
    try:
        raw = json.loads(path.read_text(encoding="utf-8"))
    except ValueError as exc:
        raise FiguresError(f"{RESULTS}/{name}: expected JSON, got {exc}") from exc
    if not isinstance(raw, dict):
        raise FiguresError(f"{RESULTS}/{name}: expected a JSON object")
    command, commit, result = raw.get("command"), raw.get("commit"), raw.get("result")
    if not isinstance(command, str) or not command.startswith("uma bench "):
        raise FiguresError(f"{RESULTS}/{name}: expected `command` (uma bench ...), got {command!r}")
    if not isinstance(commit, str) or not _COMMIT.match(commit):
        raise FiguresError(f"{RESULTS}/{name}: expected `commit` (40 hex digits), got {commit!r}")
    if raw.get("dirty"):
        raise FiguresError(f"{RESULTS}/{name}: recorded from a dirty tree; record it again")
    if not isinstance(result, dict):
        raise FiguresError(f"{RESULTS}/{name}: expected `result`, the bench's JSON object")
    return Record(
        name, command, commit, str(raw.get("date_utc", "")), raw.get("load_1m"),
        raw.get("cores"), raw.get("duration_s"), result, raw,
    )  # fmt: skip


def value_at(data: Any, path: str, where: str) -> Any:
    """The value at a dotted path (a key may hold dots when quoted: a."b.c".d)."""
    for key in re.findall(r'"[^"]*"|[^.]+', path):
        key = key.strip('"')
        if not isinstance(data, dict) or key not in data:
            raise FiguresError(f"{where}: no {key!r} along {path!r}")
        data = data[key]
    return data


def _parse_spec(spec: str, where: str) -> tuple[str, list[str], list[str], dict[str, str]]:
    words = spec.split()
    if not words:
        raise FiguresError(f"{where}: expected `<!-- fig RENDERER FILE.json ... -->`")
    files = [w for w in words[1:] if w.endswith(".json") and "=" not in w]
    args = dict(w.split("=", 1) for w in words[1:] if "=" in w)
    rest = [w for w in words[1:] if w not in files and "=" not in w]
    if not files:
        raise FiguresError(f"{where}: names no record (FILE.json): {spec!r}")
    return words[0], files, rest, args


def _inline(renderer: str, records: list[Record], rest: list[str], where: str) -> str:
    if renderer == "value":
        if len(records) != 1 or len(rest) not in (1, 2):
            raise FiguresError(f"{where}: expected `value FILE.json PATH [FORMAT]`")
        value = value_at(records[0].result, rest[0], where)
        if not isinstance(value, (int, float)) or isinstance(value, bool):
            raise FiguresError(f"{where}: {rest[0]!r} is {value!r}, not a number")
        return format(value, rest[1] if len(rest) == 2 else "")
    if renderer == "source":
        return "; ".join(r.provenance() for r in records)
    raise FiguresError(f"{where}: unknown inline renderer {renderer!r} (value, source)")


def _render_block(match: re.Match, text: str, results_dir: Path, readme: str) -> str:
    line = text.count("\n", 0, match.start()) + 1
    where = f"{readme}:{line}"
    renderer, files, rest, args = _parse_spec(match["spec"], where)
    records = [load_record(results_dir, name, where) for name in files]
    opening = match.group(0)[: match.start("body") - match.start()]
    if not match["body"].startswith("\n"):
        if "\n" in match["body"]:
            raise FiguresError(f"{where}: an inline figure must end on its own line")
        body = _inline(renderer, records, rest, where)
        return f"{opening}{body}<!-- /fig -->"
    if rest:
        raise FiguresError(f"{where}: expected FILE.json names and key=value, got {rest}")
    render_fn = readme_blocks.RENDERERS.get(renderer)
    if render_fn is None:
        names = ", ".join(sorted(readme_blocks.RENDERERS))
        raise FiguresError(f"{where}: unknown renderer {renderer!r} (one of {names})")
    try:
        body = render_fn([r.result for r in records], args)
    except (KeyError, TypeError, ValueError) as exc:
        raise FiguresError(f"{where}: {renderer} cannot render {files}: {exc!r}") from exc
    sources = "; ".join(r.provenance() for r in records)
    return f"{opening}\n{body.rstrip()}\n\nFrom {sources}.\n<!-- /fig -->"


def render(text: str, results_dir: Path, readme: str = "README.md") -> str:
    """`text` with every block regenerated from the records in `results_dir`."""
    _check_rows_outside_blocks(text, readme)
    return _BLOCK.sub(lambda m: _render_block(m, text, results_dir, readme), text)


def _check_rows_outside_blocks(text: str, readme: str) -> None:
    outside = _BLOCK.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    for number, line in enumerate(outside.splitlines(), 1):
        if _FIGURE_ROW.match(line):
            raise FiguresError(
                f"{readme}:{number}: a table row with figures outside any figures block "
                f"(generate it from docs/results/): {line.strip()[:80]}"
            )


def check(readme_path: Path, results_dir: Path) -> str | None:
    """None when README.md is what its records render; else the first difference, one line."""
    text = readme_path.read_text(encoding="utf-8")
    try:
        wanted = render(text, results_dir, readme_path.name)
    except FiguresError as exc:
        return str(exc)
    if wanted == text:
        return None
    for number, (have, want) in enumerate(
        zip(text.splitlines() + [""], wanted.splitlines() + [""], strict=False), 1
    ):
        if have != want:
            return f"{readme_path.name}:{number}: is {have!r}, the records give {want!r}"
    return f"{readme_path.name}: differs from what its records render"


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1 or args[0] not in ("write", "check"):
        print("usage: readme_tables.py write|check", file=sys.stderr)
        return 2
    readme, results_dir = ROOT / "README.md", ROOT / RESULTS
    if args[0] == "check":
        problem = check(readme, results_dir)
        if problem:
            print(f"readme_tables: {problem}", file=sys.stderr)
            return 1
        return 0
    text = readme.read_text(encoding="utf-8")
    try:
        wanted = render(text, results_dir, readme.name)
    except FiguresError as exc:
        print(f"readme_tables: {exc}", file=sys.stderr)
        return 1
    if wanted != text:
        tmp = readme.with_name(f".{readme.name}.tmp")
        tmp.write_text(wanted, encoding="utf-8")
        tmp.replace(readme)
    return 0


if __name__ == "__main__":
    sys.exit(main())
