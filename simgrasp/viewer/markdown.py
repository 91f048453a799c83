"""The subset of Markdown our ``report.md`` files use, as HTML: ``#`` headings, pipe tables,
paragraphs, ``**bold**``, ``code`` and ``[text](link)``. Everything else is escaped text."""

from __future__ import annotations

import html
import re

_INLINE = (
    (re.compile(r"\*\*(.+?)\*\*"), r"<b>\1</b>"),
    (re.compile(r"`(.+?)`"), r"<code>\1</code>"),
    (re.compile(r"\[([^\]]+)\]\(([^)\s]+)\)"), r'<a href="\2">\1</a>'),
)


def inline(text: str) -> str:
    """One line's text, escaped, with bold, code and links."""
    out = html.escape(text, quote=True)
    for pattern, replacement in _INLINE:
        out = pattern.sub(replacement, out)
    return out


def _cells(line: str) -> list[str]:
    return [c.strip() for c in line.strip().strip("|").split("|")]


def _table(lines: list[str]) -> str:
    head = "".join(f"<th>{inline(c)}</th>" for c in _cells(lines[0]))
    rows = [
        "<tr>" + "".join(f"<td>{inline(c)}</td>" for c in _cells(line)) + "</tr>"
        for line in lines[2:]
    ]
    return f"<table><tr>{head}</tr>{''.join(rows)}</table>"


def markdown_html(text: str) -> str:
    """``text`` (the subset above) as HTML."""
    blocks: list[str] = []
    lines = text.splitlines()
    k = 0
    while k < len(lines):
        line = lines[k]
        if line.startswith("#"):
            level = min(len(line) - len(line.lstrip("#")), 6)
            blocks.append(f"<h{level}>{inline(line.lstrip('#').strip())}</h{level}>")
            k += 1
        elif line.startswith("|"):
            end = k
            while end < len(lines) and lines[end].startswith("|"):
                end += 1
            blocks.append(_table(lines[k:end]))
            k = end
        elif line.strip():
            end = k
            while end < len(lines) and lines[end].strip() and lines[end][0] not in "#|":
                end += 1
            blocks.append("<p>" + " ".join(inline(x) for x in lines[k:end]) + "</p>")
            k = end
        else:
            k += 1
    return "\n".join(blocks)
