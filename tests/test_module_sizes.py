"""Small modules with one job: none over 400 lines, no function over 60, and the engine a
dispatcher under 200 lines that holds its own methods."""

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


# Functions allowed over 60 lines, each with its reason; the list may only shrink.
LONG_FUNCTIONS = {
    # numba compiles one loop nest; split, each part pays a call per pixel row (docs/measured.md)
    "fit/kernels.py:scores",
}


def _functions(tree: ast.AST):
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            yield node


def test_no_function_is_over_60_lines():
    long = {}
    for path in PACKAGE.rglob("*.py"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in _functions(tree):
            where = f"{path.relative_to(PACKAGE)}:{node.name}"
            if (n := node.end_lineno - node.lineno + 1) > 60 and where not in LONG_FUNCTIONS:
                long[where] = n
    assert not long, f"split these functions: {long}"


def test_the_long_function_exceptions_are_still_long():
    for where in sorted(LONG_FUNCTIONS):
        module, name = where.split(":")
        tree = ast.parse((PACKAGE / module).read_text(encoding="utf-8"))
        (node,) = [n for n in _functions(tree) if n.name == name]
        assert node.end_lineno - node.lineno + 1 > 60, (
            f"{where} is short now: drop it from the list"
        )


def test_the_engine_holds_its_own_methods():
    """No function from another module bound as a method, no module-level helper taking the engine."""
    tree = ast.parse((PACKAGE / "engine" / "engine.py").read_text(encoding="utf-8"))
    (engine,) = [n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "UmaEngine"]
    for node in engine.body:
        is_docstring = isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant)
        assert is_docstring or isinstance(node, ast.FunctionDef), (
            f"engine.py:{node.lineno}: the class body holds only its docstring and methods"
        )
    for path in (PACKAGE / "engine").rglob("*.py"):
        for node in _functions(ast.parse(path.read_text(encoding="utf-8"))):
            params = node.args.posonlyargs + node.args.args + node.args.kwonlyargs
            for arg in params:
                annotation = ast.unparse(arg.annotation) if arg.annotation else ""
                assert "UmaEngine" not in annotation, (
                    f"{path.name}:{node.lineno}: {node.name} takes the engine ({arg.arg})"
                )
