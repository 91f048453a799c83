"""The package reads as a newcomer expects: no import cycles between its modules nor between its
sub-packages, no module over 400 lines, no function over sixty lines."""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

PACKAGE = Path(__file__).parents[1] / "simgrasp"


def module_name(path: Path, package: Path = PACKAGE) -> str:
    parts = path.relative_to(package.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def is_type_checking(node: ast.AST) -> bool:
    """``if TYPE_CHECKING:`` (or ``typing.TYPE_CHECKING``): imports for annotations only."""
    if not isinstance(node, ast.If):
        return False
    test = node.test
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def import_nodes(tree: ast.AST) -> Iterator[ast.Import | ast.ImportFrom]:
    """Every import statement in ``tree``, at module level or inside a function or class, except
    those in the body of an ``if TYPE_CHECKING:`` block (its ``else`` still runs)."""
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, ast.Import | ast.ImportFrom):
            yield node
        if is_type_checking(node):
            assert isinstance(node, ast.If)
            for child in node.orelse:
                yield from import_nodes(ast.Module(body=[child], type_ignores=[]))
            continue
        yield from import_nodes(node)


def import_graph(package: Path = PACKAGE) -> dict[str, set[str]]:
    """Module -> the package modules it imports anywhere in its code, at module level or inside
    a function (a lazy import runs too), ``if TYPE_CHECKING:`` blocks aside; a
    ``from X import Y`` of a submodule Y counts as importing X.Y."""
    modules = {module_name(p, package): p for p in package.rglob("*.py")}
    graph: dict[str, set[str]] = {name: set() for name in modules}
    for name, path in modules.items():
        for node in import_nodes(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif node.module and not node.level:
                subs = [f"{node.module}.{alias.name}" for alias in node.names]
                targets = [s for s in subs if s in modules] or [node.module]
            else:
                continue
            graph[name] |= {t for t in targets if t in modules and t != name}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        for nxt in graph[node]:
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in graph:
        if node not in index:
            visit(node)
    return found


def test_no_import_cycles() -> None:
    """No two modules import each other, directly or round a loop, even from inside a
    function."""
    found = cycles(import_graph())
    assert found == [], found


def test_the_module_graph_fails_on_a_planted_function_level_cycle(tmp_path: Path) -> None:
    """A package whose modules close a loop only through an import inside a function (and one
    more only through ``if TYPE_CHECKING:``, which does not count) is caught."""
    package = tmp_path / "pkg"
    (package / "sub").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "sub" / "__init__.py").write_text("")
    (package / "a.py").write_text("from pkg.sub import b\n")
    (package / "sub" / "b.py").write_text("import pkg.c\n")
    (package / "c.py").write_text("def f():\n    if True:\n        from pkg import a\n")
    (package / "d.py").write_text(
        "from typing import TYPE_CHECKING\nimport pkg.e\nif TYPE_CHECKING:\n    import pkg.a\n"
    )
    (package / "e.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from pkg import d\n"
        "else:\n    import pkg.c\n"
    )
    graph = import_graph(package)
    assert graph["pkg.c"] == {"pkg.a"} and graph["pkg.e"] == {"pkg.c"}
    assert cycles(graph) == [["pkg.a", "pkg.c", "pkg.sub.b"]]
    (package / "c.py").write_text("def f():\n    return 1\n")  # the loop cut: none left
    assert cycles(import_graph(package)) == []


MAX_MODULE_LINES = 400


def top_level_unit(module: str) -> str | None:
    """The top-level sub-package or module of ``simgrasp.a.b...`` (``simgrasp.a``); None for
    the root package itself (the front door, which may name every sub-package)."""
    parts = module.split(".")
    if parts[0] != "simgrasp" or len(parts) < 2:
        return None
    return ".".join(parts[:2])


def imported_modules(path: Path) -> set[str]:
    """Every ``simgrasp`` module ``path`` imports, at module level or inside a function (an
    ``import`` inside a function is still a dependency), as dotted names."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            found.add(node.module)
            found |= {f"{node.module}.{alias.name}" for alias in node.names}
    return {name for name in found if name.split(".")[0] == "simgrasp"}


def package_graph() -> dict[str, set[str]]:
    """Top-level sub-package (or module) -> the other top-level ones its modules import."""
    graph: dict[str, set[str]] = {}
    for path in PACKAGE.rglob("*.py"):
        source = top_level_unit(module_name(path))
        if source is None:
            continue
        targets = {top_level_unit(name) for name in imported_modules(path)}
        graph.setdefault(source, set())
        graph[source] |= {t for t in targets if t is not None and t != source}
    for imported in list(graph.values()):
        for target in imported:
            graph.setdefault(target, set())
    return graph


def test_no_import_cycle_between_sub_packages() -> None:
    """Function-level imports count: a lazy import still ties two sub-packages together."""
    found = cycles(package_graph())
    assert found == [], found


def test_the_package_graph_sees_function_level_imports(tmp_path: Path) -> None:
    module = tmp_path / "module.py"
    module.write_text(
        "from simgrasp.errors import SimgraspError\n"
        "def f():\n    import simgrasp.grasping.trials.trial\n"
        "    from simgrasp.handles import detect\n"
    )
    assert imported_modules(module) == {
        "simgrasp.errors",
        "simgrasp.errors.SimgraspError",
        "simgrasp.grasping.trials.trial",
        "simgrasp.handles",
        "simgrasp.handles.detect",
    }


def test_no_module_is_over_400_lines() -> None:
    """One concept per module: a module that grows past 400 lines is split along its seams."""
    long = {
        str(path.relative_to(PACKAGE.parent)): lines
        for path in sorted(PACKAGE.rglob("*.py"))
        if (lines := len(path.read_text(encoding="utf-8").splitlines())) > MAX_MODULE_LINES
    }
    assert long == {}


def test_the_cycle_check_finds_a_cycle() -> None:
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == [["a", "b", "c"]]


MAX_FUNCTION_LINES = 60


def long_functions(path: Path, max_lines: int) -> list[str]:
    """``path:line: name is N lines`` for every function over ``max_lines`` (from ``def`` to
    the body's last line, docstring included, decorators not)."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), filename=str(path))):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            length = (node.end_lineno or node.lineno) - node.lineno + 1
            if length > max_lines:
                found.append(f"{path}:{node.lineno}: {node.name} is {length} lines")
    return found


def test_no_function_is_over_sixty_lines() -> None:
    """The package, the scripts, the benchmarks, the examples and the tests: long functions are
    split by phase."""
    root = PACKAGE.parent
    folders = [root / name for name in ("simgrasp", "scripts", "benchmarks", "examples", "tests")]
    files = [f for folder in folders if folder.is_dir() for f in sorted(folder.rglob("*.py"))]
    assert [line for f in files for line in long_functions(f, MAX_FUNCTION_LINES)] == []


def test_the_length_check_finds_a_long_function(tmp_path: Path) -> None:
    module = tmp_path / "long.py"
    module.write_text("def f():\n" + "    x = 1\n" * 60)
    assert long_functions(module, MAX_FUNCTION_LINES) == [f"{module}:1: f is 61 lines"]
