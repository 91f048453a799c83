#!/usr/bin/env python3
"""List functions longer than a limit (lines from ``def`` to the last line of the body,
docstring included, decorators not) and exit 1 if there are any.

    python scripts/check_function_length.py                 # simgrasp/, 60 lines
    python scripts/check_function_length.py simgrasp tests --max-lines 50 --exclude '*_cli.py'
"""

from __future__ import annotations

import ast
import fnmatch
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from simgrasp.config import Checked, setting
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import PositiveInt

DEFAULT_MAX_LINES = 60


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    paths: tuple[Path, ...] = setting((Path("simgrasp"),), positional=True, many=True)
    """Files and folders to check (a folder: every ``.py`` file under it)."""
    max_lines: PositiveInt = DEFAULT_MAX_LINES
    """Longest function allowed, in lines."""
    exclude: tuple[str, ...] = setting((), many=True, metavar="GLOB")
    """Globs of file paths to skip (several, or the flag repeated)."""


def long_functions(path: Path, max_lines: int) -> Iterator[tuple[int, str, int]]:
    """(line, qualified name, length) of every function in ``path`` over ``max_lines``."""
    tree = ast.parse(path.read_text(), filename=str(path))

    def visit(node: ast.AST, prefix: str) -> Iterator[tuple[int, str, int]]:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
                name = f"{prefix}{child.name}"
                if not isinstance(child, ast.ClassDef):
                    length = (child.end_lineno or child.lineno) - child.lineno + 1
                    if length > max_lines:
                        yield child.lineno, name, length
                yield from visit(child, f"{name}.")
            else:
                yield from visit(child, prefix)

    yield from visit(tree, "")


def python_files(paths: list[Path], excludes: list[str]) -> list[Path]:
    """The ``.py`` files under ``paths`` whose path matches none of the ``excludes`` globs."""
    files = [f for p in paths for f in ([p] if p.is_file() else sorted(p.rglob("*.py")))]
    return [f for f in files if not any(fnmatch.fnmatch(str(f), g) for g in excludes)]


def run(options: Options) -> int:
    """Print every function over the limit; exit status 1 if there is one."""
    offenders = [
        (path, *found)
        for path in python_files(list(options.paths), list(options.exclude))
        for found in long_functions(path, options.max_lines)
    ]
    for path, line, name, length in offenders:
        print(f"{path}:{line}: {name} is {length} lines (max {options.max_lines})")
    return 1 if offenders else 0


def main(argv: list[str] | None = None) -> int:
    return script_main(Options, run, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())
