"""scripts/check_function_length.py: lists functions over the limit and fails on them."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).parents[1] / "scripts" / "check_function_length.py"


def _function(name: str, lines: int) -> str:
    """Source of a function ``lines`` lines long (the ``def`` line included)."""
    body = "".join(f"    x{i} = {i}\n" for i in range(lines - 2))
    return f"def {name}():\n{body}    return 0\n"


def _check(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(SCRIPT), *args], capture_output=True, text=True, check=False
    )


def test_functions_over_the_limit_are_listed_and_fail(tmp_path: Path) -> None:
    source = tmp_path / "module.py"
    method = "".join(f"    {line}\n" for line in _function("m", 61).splitlines())
    nested = "class Holder:\n" + method
    source.write_text(_function("short", 60) + _function("long", 61) + nested)
    done = _check(str(tmp_path))
    assert done.returncode == 1
    assert done.stdout.splitlines() == [
        f"{source}:61: long is 61 lines (max 60)",
        f"{source}:123: Holder.m is 61 lines (max 60)",
    ]


def test_a_clean_tree_and_excluded_files_pass(tmp_path: Path) -> None:
    (tmp_path / "ok.py").write_text(_function("short", 60))
    (tmp_path / "skip_cli.py").write_text(_function("long", 80))
    assert _check(str(tmp_path), "--exclude", "*_cli.py").returncode == 0
    assert _check(str(tmp_path), "--max-lines", "50").returncode == 1
