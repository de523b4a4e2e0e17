"""Small modules with one job: none over 400 lines, and the engine a dispatcher under 200."""

import ast
from pathlib import Path

PACKAGE = Path(__file__).parents[1] / "uma"


def test_no_module_is_over_400_lines():
    long = {
        str(path.relative_to(PACKAGE)): n
        for path in PACKAGE.rglob("*.py")
        if (n := len(path.read_text(encoding="utf-8").splitlines())) > 400
    }
    assert not long, f"split these modules: {long}"


def test_the_engine_class_is_a_dispatcher_under_200_lines():
    tree = ast.parse((PACKAGE / "engine" / "engine.py").read_text(encoding="utf-8"))
    (engine,) = [n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "UmaEngine"]
    assert engine.end_lineno - engine.lineno + 1 < 200
