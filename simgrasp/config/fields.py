"""Settings fields: a dataclass field that also says how it reaches the command line.

Every setting of a run is a field of a frozen dataclass; :func:`setting` adds the few facts
the generated command line needs beyond its type, default and docstring (an alias flag, the
choices when they come from a registry, a text parser, positional or flattened placement,
several values for a list, a place in the command's short ``--help``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any, Literal

META_KEY = "simgrasp"


@dataclasses.dataclass(frozen=True)
class FieldSpec:
    """Command-line facts of one field.

    Attributes:
        flag: an extra short flag (``"--views"`` for ``scene.num_views``).
        choices: allowed values, or a function returning them (a registry read lazily);
            checked when the config is made (:class:`~simgrasp.config.checks.Checked`), of each
            item for a list setting.
        parse: converts the flag's text to the value (e.g. ``START:STOP:STEP`` ranges).
        positional: a positional argument instead of a ``--flag``.
        flatten: for a nested config field, its fields are named without its own name.
        exclude: for a nested config field, dotted keys of it not offered on this command.
        metavar: the placeholder shown in ``--help``.
        output: a path the command writes, a ``"file"``, a ``"plot"`` (a file matplotlib
            can write, by its suffix) or a ``"dir"``: proved writable before the run starts
            (:func:`simgrasp.runs.out_dir.check_outputs`), so a run never works for minutes
            and then fails to save.
        suffixes: for an output ``"file"``, the suffixes it may end in (lower case, with the
            dot; empty: any), checked with the rest before the run.
        many: for a list setting (``tuple[X, ...]``), several space-separated values on the
            command line: a flag takes one or more (``--exclude A B``) and may be repeated,
            the values of all its uses joined in order (``--exclude A --exclude B``); its
            values run to the next flag, so a positional goes before it or after ``--``. A
            positional takes any number, none meaning its default (or, when it has none, the
            usual "missing" error, so that ``--config`` or ``--set`` may give it instead).
            Each value is also split at commas as every list setting's text is (``--set`` and
            plain list flags): ``--exclude A,B C`` is three items, so an item cannot hold a
            comma. Each item is converted to X and checked as X; ``parse``, if given, turns
            each value into a tuple.
        main: one of the few settings most runs of a command set (what it reads and writes,
            units, the detector's kind, the seed, the workers): listed in full by the
            command's short ``--help``, where every other setting is summed up by its tree
            (``--detector.*``) and listed by ``--help-all``. A positional or required setting
            is always listed. Marked here, on the field, wherever the field is nested.
    """

    flag: str | None = None
    choices: tuple[Any, ...] | Callable[[], tuple[Any, ...]] | None = None
    parse: Callable[[str], Any] | None = None
    positional: bool = False
    flatten: bool = False
    exclude: tuple[str, ...] = ()
    metavar: str | None = None
    output: Literal["file", "plot", "dir"] | None = None
    suffixes: tuple[str, ...] = ()
    many: bool = False
    main: bool = False


def setting(
    default: Any = dataclasses.MISSING,
    *,
    default_factory: Any = dataclasses.MISSING,
    **spec: Any,
) -> Any:
    """A dataclass field with command-line facts (:class:`FieldSpec` keywords)."""
    metadata = {META_KEY: FieldSpec(**spec)}
    if default_factory is not dataclasses.MISSING:
        return dataclasses.field(default_factory=default_factory, metadata=metadata)
    return dataclasses.field(default=default, metadata=metadata)


def field_spec(field: dataclasses.Field[Any]) -> FieldSpec:
    """The command-line facts of ``field`` (defaults when it has none)."""
    spec = field.metadata.get(META_KEY)
    return spec if isinstance(spec, FieldSpec) else FieldSpec()
