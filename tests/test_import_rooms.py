"""The rooms' arrows point down (docs/architecture.md) and no module imports itself round a circle.

Every `import uma.X...` in `uma/`, at the top or inside a function, is read with `ast`: a lazy
import is still an arrow. A room may import only rooms of a lower level; rooms on one level
are independent of each other, except where `SIDEWAYS` says so.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import uma

ROOT = Path(uma.__file__).parent

# Lowest first. `uma/__init__.py` and the single-module rooms form the floor.
LEVELS: list[set[str]] = [
    {"blas", "errors", "failure", "interrupt", "paths"},
    {"atomic", "codecs"},  # `codecs`: the codec registry, pure data
    {"__init__"},
    {"config"},
    {"control"},  # rate control, pure: the engine follows it, the world's receiver reports to it
    {"traces", "engine", "metrics", "video"},
    {"face"},  # reads a template from a video frame (`uma.face.clip`)
    {"fit"},  # uses face
    {"mbc"},  # uses fit and face
    {"sim"},  # may use mbc
    {"experiments", "report"},
    # `bench`: `uma bench sweep` times the experiments' executor; `api`: the Python API for
    # notebooks (`uma.run`, ...). `uma/__init__` reaches `uma.api` only through its module
    # `__getattr__` at first use (importlib, which this test does not read): a facade for
    # users, not an arrow any room may follow.
    {"bench", "api"},
    {"cli"},
    {"__main__"},
]
SIDEWAYS: set[tuple[str, str]] = set()
LEVEL = {room: i for i, rooms in enumerate(LEVELS) for room in rooms}


def _module_name(path: Path) -> str:
    parts = ("uma",) + path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _room(path: Path) -> str:
    parts = path.relative_to(ROOT).parts
    return parts[0] if len(parts) > 1 else path.stem


def _imports(path: Path) -> set[str]:
    """Absolute `uma.*` module names that `path` imports anywhere in its body."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            assert not node.level, f"{path}: relative import; the project imports absolutely"
            module = node.module or ""
            found.add(module)
            # `from uma.face import load` may name a sub-module
            found |= {f"{module}.{alias.name}" for alias in node.names}
    return {name for name in found if name == "uma" or name.startswith("uma.")}


def _modules() -> dict[str, Path]:
    return {_module_name(p): p for p in sorted(ROOT.rglob("*.py"))}


@functools.cache
def _package_imports() -> dict[str, frozenset[str]]:
    """`_imports` of every module of the package, read once for the tests that need them all."""
    return {name: frozenset(_imports(path)) for name, path in _modules().items()}


def test_every_room_has_a_level():
    rooms = {_room(path) for path in ROOT.rglob("*.py")}
    assert rooms <= set(LEVEL), f"rooms without a level in this test: {rooms - set(LEVEL)}"


def _wrong_arrows(imports: dict[str, set[str]], rooms: dict[str, str]) -> list[str]:
    """`module (room) imports target (room)` for every arrow that does not point down."""
    bad = []
    for name, targets in imports.items():
        room = rooms[name]
        for target in targets:
            other = rooms.get(target)
            if other is None or other == room or (room, other) in SIDEWAYS:
                continue
            if LEVEL[other] >= LEVEL[room]:
                bad.append(f"{name} ({room}) imports {target} ({other})")
    return sorted(bad)


def test_no_room_imports_a_higher_or_sideways_room():
    modules = _modules()
    imports = _package_imports()
    rooms = {name: _room(path) for name, path in modules.items()}
    bad = _wrong_arrows(imports, rooms)
    assert not bad, "arrows pointing up or sideways:\n" + "\n".join(bad)


def test_the_check_catches_a_lazy_upward_and_a_sideways_import(tmp_path):
    probe = tmp_path / "probe.py"
    probe.write_text("def f():\n    from uma.engine.policy import POLICIES\n")
    imports = {"uma.config.load": _imports(probe), "uma.traces.read": {"uma.metrics.results"}}
    rooms = {
        "uma.config.load": "config",
        "uma.engine.policy": "engine",
        "uma.traces.read": "traces",
        "uma.metrics.results": "metrics",
    }
    assert _wrong_arrows(imports, rooms) == [
        "uma.config.load (config) imports uma.engine.policy (engine)",
        "uma.traces.read (traces) imports uma.metrics.results (metrics)",
    ]


def test_no_import_circles_between_modules():
    modules = _modules()
    graph = {
        name: sorted(t for t in targets if t in modules and t != name)
        for name, targets in _package_imports().items()
    }
    # A package's __init__ re-exporting its own modules is not a circle of meaning: drop the
    # edges from a module back to a package that contains it.
    for name, targets in graph.items():
        graph[name] = [t for t in targets if not name.startswith(t + ".")]
    state: dict[str, int] = {}
    stack: list[str] = []
    circles: list[str] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for target in graph[node]:
            if state.get(target) == 1:
                circles.append(" -> ".join(stack[stack.index(target) :] + [target]))
            elif target not in state:
                visit(target)
        stack.pop()
        state[node] = 2

    for node in graph:
        if node not in state:
            visit(node)
    assert not circles, "import circles:\n" + "\n".join(circles)
