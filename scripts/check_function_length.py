#!/usr/bin/env python3
"""List functions longer than a limit (lines from ``def`` to the last line of the body,
docstring included, decorators not) and exit 1 if there are any.

    python scripts/check_function_length.py                 # simgrasp/, 60 lines
    python scripts/check_function_length.py simgrasp tests --max-lines 50 --exclude '*_cli.py'
"""

from __future__ import annotations

import argparse
import ast
import fnmatch
import sys
from collections.abc import Iterator
from pathlib import Path

DEFAULT_MAX_LINES = 60


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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="*", type=Path, default=[Path("simgrasp")])
    parser.add_argument("--max-lines", type=int, default=DEFAULT_MAX_LINES)
    parser.add_argument(
        "--exclude", action="append", default=[], help="glob of file paths to skip (repeatable)"
    )
    args = parser.parse_args(argv)
    offenders = [
        (path, *found)
        for path in python_files(args.paths, args.exclude)
        for found in long_functions(path, args.max_lines)
    ]
    for path, line, name, length in offenders:
        print(f"{path}:{line}: {name} is {length} lines (max {args.max_lines})")
    return 1 if offenders else 0


if __name__ == "__main__":
    sys.exit(main())
