"""The codec seam: the engine, the world, the metrics, the report and the benches name no codec.

They learn what they need about a codec from the registry (`uma.codecs`), so adding one is its
codec module, a registry entry, a ladder file and tests. This test reads their source with `ast`
and fails on a codec's name in a string (docstrings aside: prose may name codecs) or in an
identifier (`h264_rungs`, `mbc_point`, a `_family` helper that maps names to families).
And the world talks to the engine only through its calls (`on_*`, `finish`): it never reads or
writes the engine's internals.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import uma
from uma.codecs import REGISTRY

ROOT = Path(uma.__file__).parent
# The simulation's codec modules are one codec's own code (the model codec's coders, the
# region codec's, the refresh's) and the context the codecs share: they may name it.
CODEC_MODULES = {"mbc_codecs.py", "face_region.py", "refresh.py", "context.py"}
SCOPE = (
    sorted((ROOT / "engine").rglob("*.py"))
    + [path for path in sorted((ROOT / "sim").rglob("*.py")) if path.name not in CODEC_MODULES]
    + sorted((ROOT / "metrics").rglob("*.py"))
    + sorted((ROOT / "report").rglob("*.py"))
    + sorted((ROOT / "bench").rglob("*.py"))
)
# Registered codecs, and the full-frame codecs the project adds next.
NAMES = tuple(sorted(set(REGISTRY) | {"vp8", "av1"}, key=len, reverse=True))
TOKENS = {part for name in NAMES for part in re.split(r"[-_]", name) if part != "face"}
IN_TEXT = re.compile(r"(?<![\w.-])(" + "|".join(map(re.escape, NAMES)) + r")(?![\w-])")
BANNED_IDENTIFIERS = {"_family"}
# Scenario keys users write (`engine.switching.to_mbc_below_kbps`): renaming them would break
# every scenario file, so they may be read, as attributes only.
CONFIG_KEYS = {"to_mbc_below_kbps", "to_h264_above_kbps"}
KEPT: set[tuple[str, str]] = set()  # (module, identifier) pairs allowed to name a codec


def _docstrings(tree: ast.AST) -> set[int]:
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                found.add(id(body[0].value))
    return found


def _identifiers(node: ast.AST) -> list[tuple[str, bool]]:
    """(identifier, is an attribute access) of `node`."""
    if isinstance(node, ast.Name):
        return [(node.id, False)]
    if isinstance(node, ast.Attribute):
        return [(node.attr, True)]
    if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
        return [(node.name, False)]
    if isinstance(node, ast.arg):
        return [(node.arg, False)]
    if isinstance(node, ast.keyword) and node.arg:
        return [(node.arg, False)]
    if isinstance(node, ast.alias):
        return [(node.asname or node.name.split(".")[-1], False)]
    return []


def codec_names_in(source: str, where: str = "<source>") -> list[str]:
    """Every place in `source` that names a codec other than through the registry."""
    tree = ast.parse(source)
    docstrings = _docstrings(tree)
    found = []
    for node in ast.walk(tree):
        line = getattr(node, "lineno", 0)
        text = node.value if isinstance(node, ast.Constant) else None
        if isinstance(text, str) and id(node) not in docstrings and IN_TEXT.search(text):
            found.append(f"{where}:{line}: string {text!r}")
        for name, attribute in _identifiers(node):
            if (where, name) in KEPT or (attribute and name in CONFIG_KEYS):
                continue
            if name in BANNED_IDENTIFIERS or TOKENS & set(name.lower().split("_")):
                found.append(f"{where}:{line}: identifier {name!r}")
    return found


def test_the_checker_finds_codec_names():
    source = '''
"""Docstrings may say h264 and mbc."""
def _family(codec):
    return "mbc" if codec == "h264-face" else f"{codec} vp8"
mbc_point = engine.to_mbc_below_kbps
def f(av1_rate=0): return kbps_h264
'''
    found = codec_names_in(source)
    assert any("'_family'" in f for f in found)
    assert any("'mbc'" in f for f in found) and any("'h264-face'" in f for f in found)
    assert any("' vp8'" in f for f in found)
    assert any("'mbc_point'" in f for f in found) and any("'av1_rate'" in f for f in found)
    assert any("'kbps_h264'" in f for f in found)
    assert not any("to_mbc_below_kbps" in f or "Docstrings" in f for f in found)
    # Event kinds and metric keys that only contain a name are not codec names themselves.
    assert codec_names_in('kind = "mbc_init_start"; key = "kbps_h264_face"') == []


def test_engine_world_metrics_report_and_bench_name_no_codec():
    found = []
    for path in SCOPE:
        where = str(path.relative_to(ROOT))
        found += codec_names_in(path.read_text(encoding="utf-8"), where)
    assert not found, "codec names outside the registry:\n" + "\n".join(found)


def _engine_uses(source: str) -> set[str]:
    """The attributes `source` reads or writes on an engine (`engine.X`, `world.engine.X`;
    `scenario.engine` is its configuration)."""
    used = set()
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.Attribute):
            continue
        owner = node.value
        if (isinstance(owner, ast.Name) and owner.id == "engine") or (
            isinstance(owner, ast.Attribute)
            and owner.attr == "engine"
            and isinstance(owner.value, ast.Name)
            and owner.value.id == "world"
        ):
            used.add(node.attr)
    return used


def test_the_world_talks_to_the_engine_only_through_its_calls():
    assert _engine_uses("engine.events.append(x); world.engine.on_frame(1)") == {
        "events",
        "on_frame",
    }
    for path in sorted((ROOT / "sim").glob("*.py")):
        inside = _engine_uses(path.read_text(encoding="utf-8"))
        internals = {name for name in inside if not name.startswith("on_") and name != "finish"}
        assert not internals, f"{path.name} reaches into the engine: {sorted(internals)}"
