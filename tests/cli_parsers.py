"""The parser of one ``simgrasp`` command, for tests that read its help or its actions."""

from __future__ import annotations

import argparse

from simgrasp.cli import build_parser


def command_parser(command: str) -> argparse.ArgumentParser:
    """The sub-parser of ``simgrasp command``, with its settings' flags."""
    parser = build_parser(command)
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices[command]
