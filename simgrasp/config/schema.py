"""The leaves of a settings tree: every scalar setting of a nested frozen dataclass, with its
dotted key, resolved type, default and the sentence that documents it.

A field whose type is a dataclass is a branch (``detector`` holds ``quadric`` holds
``shell_test``); every other field is a leaf (``detector.quadric.shell_test``). A branch marked
``flatten`` adds no part to its leaves' keys, so a command's options and its run config share
one namespace (``--seed`` beside ``--detector.kind``).
"""

from __future__ import annotations

import ast
import dataclasses
import functools
import inspect
import textwrap
import typing
from collections.abc import Iterator
from typing import Any

from simgrasp.config.checks import describe
from simgrasp.config.fields import FieldSpec, field_spec

MISSING: Any = dataclasses.MISSING


@dataclasses.dataclass(frozen=True)
class Leaf:
    """One scalar setting of a tree.

    Attributes:
        path: attribute names from the root to the field.
        key: the user's dotted name (branches marked ``flatten`` left out).
        annotation: the field's resolved type.
        default: its default in the root's default tree (``MISSING`` when required).
        doc: its docstring (first paragraph, one line).
        spec: its command-line facts.
    """

    path: tuple[str, ...]
    key: str
    annotation: Any
    default: Any
    doc: str
    spec: FieldSpec
    marked: Any = None
    """The field's type with its ``Annotated`` marks (ranges), as declared."""

    @property
    def required(self) -> bool:
        return self.default is MISSING

    @property
    def main(self) -> bool:
        """Whether the command's short ``--help`` lists it: a positional, a required setting or
        one marked ``main`` (:attr:`FieldSpec.main`)."""
        return self.spec.main or self.spec.positional or self.required

    @property
    def allowed(self) -> str:
        """What the setting allows (``> 0``, ``one of a, b``; empty when its type says it)."""
        return describe(self.marked, self.spec.choices)


def flag_name(key: str) -> str:
    """``detector.quadric.shell_test`` -> ``--detector.quadric.shell-test``."""
    return "--" + key.replace("_", "-")


def is_branch(annotation: Any) -> bool:
    """Whether a field of this type is a nested settings dataclass."""
    return isinstance(annotation, type) and dataclasses.is_dataclass(annotation)


def field_default(field: dataclasses.Field[Any]) -> Any:
    """The default value of ``field`` (calling its factory), or ``MISSING``."""
    if field.default is not MISSING:
        return field.default
    if callable(field.default_factory):
        return field.default_factory()
    return MISSING


@functools.cache
def type_hints(cls: type) -> dict[str, Any]:
    """Field name -> type, ``Annotated`` marks stripped."""
    return typing.get_type_hints(cls)


@functools.cache
def marked_hints(cls: type) -> dict[str, Any]:
    """Field name -> type with its ``Annotated`` marks (:mod:`simgrasp.config.checks`)."""
    return typing.get_type_hints(cls, include_extras=True)


def leaves(
    cls: type, default: Any = MISSING, *, _path: tuple[str, ...] = (), _key: tuple[str, ...] = ()
) -> Iterator[Leaf]:
    """Every leaf of the settings tree rooted at ``cls``, in field order; ``default`` is the
    tree's default instance when the root has one (nested defaults are read from it)."""
    docs = attribute_docs(cls)
    for field in dataclasses.fields(cls):
        spec = field_spec(field)
        annotation = type_hints(cls)[field.name]
        value = getattr(default, field.name) if default is not MISSING else field_default(field)
        path, key = (*_path, field.name), _key if spec.flatten else (*_key, field.name)
        if is_branch(annotation):
            sub = leaves(annotation, value, _path=path, _key=key)
            excluded = {".".join((*key, name)) for name in spec.exclude}
            yield from (leaf for leaf in sub if leaf.key not in excluded)
        else:
            doc = docs.get(field.name, "")
            marked = marked_hints(cls)[field.name]
            yield Leaf(path, ".".join(key), annotation, value, doc, spec, marked)


def trees(cls: type) -> dict[str, type]:
    """The first-level settings trees of ``cls``: the key of each branch whose leaves' keys
    start with it (``detector`` for ``detector.quadric.shell_test``; a flattened branch's
    own branches count as the root's) -> the branch's dataclass."""
    found: dict[str, type] = {}
    for field in dataclasses.fields(cls):
        annotation = type_hints(cls)[field.name]
        if not is_branch(annotation):
            continue
        if field_spec(field).flatten:
            found.update(trees(annotation))
        else:
            found[field.name] = annotation
    return found


@functools.cache
def attribute_docs(cls: type) -> dict[str, str]:
    """Field name -> the first paragraph of its docstring, joined into one line: the string
    literal after the field (``x: int = 0`` then ``\"\"\"...\"\"\"``), or its entry in the
    class docstring's ``Attributes:`` section; base classes first, overridden by subclasses."""
    docs: dict[str, str] = {}
    for klass in reversed(cls.__mro__):
        if not dataclasses.is_dataclass(klass):
            continue
        docs.update(_google_attributes(inspect.getdoc(klass) or ""))
        docs.update(_literal_docs(klass))
    return docs


def _literal_docs(cls: type) -> dict[str, str]:
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(cls)))
    except (OSError, TypeError):  # no source (e.g. a class made at run time)
        return {}
    body = tree.body[0].body if tree.body and isinstance(tree.body[0], ast.ClassDef) else []
    docs = {}
    for node, after in zip(body, body[1:], strict=False):
        if (
            isinstance(node, ast.AnnAssign)
            and isinstance(node.target, ast.Name)
            and isinstance(after, ast.Expr)
            and isinstance(after.value, ast.Constant)
            and isinstance(after.value.value, str)
        ):
            docs[node.target.id] = _first_paragraph(after.value.value)
    return docs


def _google_attributes(doc: str) -> dict[str, str]:
    """``name: text`` entries (with indented continuation lines) of an ``Attributes:`` section."""
    lines = doc.splitlines()
    if "Attributes:" not in lines:
        return {}
    entries: dict[str, list[str]] = {}
    current: list[str] | None = None
    for line in lines[lines.index("Attributes:") + 1 :]:
        if line and not line.startswith(" "):
            break
        stripped = line.strip()
        head, sep, rest = stripped.partition(":")
        if sep and line.startswith("    ") and not line.startswith("     ") and head.isidentifier():
            current = entries.setdefault(head, [rest.strip()])
        elif current is not None and stripped:
            current.append(stripped)
    return {name: " ".join(words) for name, words in entries.items()}


def _first_paragraph(text: str) -> str:
    return " ".join(inspect.cleandoc(text).split("\n\n")[0].split())
