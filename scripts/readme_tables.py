"""Render README.md's measured figures from the bench records in docs/results/.

    python scripts/readme_tables.py write    # regenerate every block of README.md in place
    python scripts/readme_tables.py check    # exit 1 naming the first line that differs

A block is `<!-- fig RENDERER FILE.json... [key=value...] -->` ... `<!-- /fig -->`. When the
opening marker ends its line the block is a table or paragraph (scripts/readme_blocks.py),
rebuilt whole and followed by a line naming the command and commit of each record it reads.
Otherwise it is inline on one line: `<!-- fig value FILE.json PATH [FORMAT] -->` is one number
of the record's `result` (dotted PATH, Python format spec), and `<!-- fig source FILE.json... -->`
in the same paragraph names the records' commands and commits. `<!-- fig records -->` (a
block naming no record) is the table of every record in docs/results/: its command, commit,
load, wall time and date. The records are written by scripts/record_bench.py; each must hold
`command`, `commit` and `result`. docs/measured.md is rendered the same way, except that its
hand-made tables of older measurements may stand outside blocks (they quote sessions, not
records). Exit 0 up to date (or written); 1 a block differs, a record is missing or
incomplete, or a README table row with measured figures stands outside any block; 2 bad usage.
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

__all__ = [
    "FiguresError",
    "Record",
    "check",
    "load_record",
    "main",
    "records_table",
    "render",
    "value_at",
]

ROOT = Path(__file__).resolve().parent.parent
RESULTS = "docs/results"
# The documents rendered: path, whether a figure row outside a block is an error in it, and
# the records' folder as its links reach it.
DOCUMENTS = (
    ("README.md", True, RESULTS),
    ("docs/measured.md", False, "results"),
    ("docs/targets.md", True, "results"),
)
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

    def provenance(self, results_link: str = RESULTS) -> str:
        """`command` on commit abc1234, linked to the record (which holds date, load, time)."""
        return f"`{self.command}` on `{self.commit[:7]}` ([record]({results_link}/{self.name}))"


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
    if words[0] == "records":
        if len(words) > 1:
            raise FiguresError(f"{where}: `<!-- fig records -->` names no record, got {spec!r}")
        return words[0], files, rest, args
    if not files:
        raise FiguresError(f"{where}: names no record (FILE.json): {spec!r}")
    return words[0], files, rest, args


def _inline(renderer: str, records: list[Record], rest: list[str], where: str, link: str) -> str:
    if renderer == "value":
        if len(records) != 1 or len(rest) not in (1, 2):
            raise FiguresError(f"{where}: expected `value FILE.json PATH [FORMAT]`")
        value = value_at(records[0].result, rest[0], where)
        if not isinstance(value, (int, float)) or isinstance(value, bool):
            raise FiguresError(f"{where}: {rest[0]!r} is {value!r}, not a number")
        return format(value, rest[1] if len(rest) == 2 else "")
    if renderer == "source":
        return "; ".join(r.provenance(link) for r in records)
    raise FiguresError(f"{where}: unknown inline renderer {renderer!r} (value, source)")


def _load(record: Record) -> str:
    load = record.load_1m if isinstance(record.load_1m, dict) else {}
    return f"{load.get('before', '?')} -> {load.get('after', '?')}"


def records_table(results_dir: Path, where: str, results_link: str = RESULTS) -> str:
    """The table of every record in `results_dir`: command, commit, load, wall s, date."""
    names = sorted(path.name for path in results_dir.glob("*.json"))
    if not names:
        raise FiguresError(f"{where}: {RESULTS} holds no records")
    rows = [
        "| record | command | commit | load | wall s | date |",
        "|---|---|---|---|---|---|",
    ]
    for name in names:
        record = load_record(results_dir, name, where)
        wall_s = record.duration_s
        wall = f"{wall_s:.0f}" if isinstance(wall_s, (int, float)) else "?"
        rows.append(
            f"| [`{name}`]({results_link}/{name}) | `{record.command}` "
            f"| {record.commit[:7]} | {_load(record)} | {wall} | {record.date_utc[:10]} |"
        )
    return "\n".join(rows)


def _render_block(match: re.Match, text: str, results_dir: Path, readme: str, link: str) -> str:
    line = text.count("\n", 0, match.start()) + 1
    where = f"{readme}:{line}"
    renderer, files, rest, args = _parse_spec(match["spec"], where)
    opening = match.group(0)[: match.start("body") - match.start()]
    if renderer == "records":
        return f"{opening}\n{records_table(results_dir, where, link)}\n<!-- /fig -->"
    records = [load_record(results_dir, name, where) for name in files]
    if not match["body"].startswith("\n"):
        if "\n" in match["body"]:
            raise FiguresError(f"{where}: an inline figure must end on its own line")
        body = _inline(renderer, records, rest, where, link)
        return f"{opening}{body}<!-- /fig -->"
    if rest:
        raise FiguresError(f"{where}: expected FILE.json names and key=value, got {rest}")
    render_fn = readme_blocks.RENDERERS.get(renderer)
    if render_fn is None:
        names = ", ".join(sorted(readme_blocks.RENDERERS))
        raise FiguresError(f"{where}: unknown renderer {renderer!r} (one of {names})")
    try:
        whole = renderer in readme_blocks.WHOLE_RECORDS
        body = render_fn([r.raw if whole else r.result for r in records], args)
    except (KeyError, TypeError, ValueError) as exc:
        raise FiguresError(f"{where}: {renderer} cannot render {files}: {exc!r}") from exc
    sources = "; ".join(r.provenance(link) for r in records)
    return f"{opening}\n{body.rstrip()}\n\nFrom {sources}.\n<!-- /fig -->"


def render(
    text: str,
    results_dir: Path,
    readme: str = "README.md",
    strict: bool = True,
    results_link: str = RESULTS,
) -> str:
    """`text` with every block regenerated from the records in `results_dir`.

    `strict` refuses a table row with figures outside any block (the README's rule);
    `results_link` is the records' folder as the document's links reach it.
    """
    if strict:
        _check_rows_outside_blocks(text, readme)
    return _BLOCK.sub(lambda m: _render_block(m, text, results_dir, readme, results_link), text)


def _check_rows_outside_blocks(text: str, readme: str) -> None:
    outside = _BLOCK.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    for number, line in enumerate(outside.splitlines(), 1):
        if _FIGURE_ROW.match(line):
            raise FiguresError(
                f"{readme}:{number}: a table row with figures outside any figures block "
                f"(generate it from docs/results/): {line.strip()[:80]}"
            )


def check(
    readme_path: Path, results_dir: Path, strict: bool = True, results_link: str = RESULTS
) -> str | None:
    """None when a document is what its records render; else the first difference, one line."""
    text = readme_path.read_text(encoding="utf-8")
    try:
        wanted = render(text, results_dir, readme_path.name, strict, results_link)
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
    results_dir = ROOT / RESULTS
    for name, strict, link in DOCUMENTS:
        if args[0] == "check":
            problem = check(ROOT / name, results_dir, strict, link)
            if problem:
                print(f"readme_tables: {name}: {problem}", file=sys.stderr)
                return 1
        elif not _write(ROOT / name, results_dir, strict, link):
            return 1
    return 0


def _write(document: Path, results_dir: Path, strict: bool, link: str) -> bool:
    text = document.read_text(encoding="utf-8")
    try:
        wanted = render(text, results_dir, document.name, strict, link)
    except FiguresError as exc:
        print(f"readme_tables: {exc}", file=sys.stderr)
        return False
    if wanted != text:
        tmp = document.with_name(f".{document.name}.tmp")
        tmp.write_text(wanted, encoding="utf-8")
        tmp.replace(document)
    return True


if __name__ == "__main__":
    sys.exit(main())
