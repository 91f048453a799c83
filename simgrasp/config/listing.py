"""Every setting of a settings tree, one line each (``simgrasp settings COMMAND``): its dotted
key, default, type with what it allows, and the first sentence of its docstring.

The listing is a TOML file that sets every setting to its default (a setting without a default
or whose default is none is a comment), so it can be saved, edited and given back with
``--config``. A key one of whose prefixes is itself a setting (``evaluate``'s ``detector``
list beside ``detector.quadric.*``) is quoted, as TOML needs.
"""

from __future__ import annotations

import inspect

from simgrasp.config.files import toml_key, toml_value
from simgrasp.config.help import first_sentence, headline
from simgrasp.config.schema import Leaf, flag_name, leaves, trees
from simgrasp.config.values import to_plain, type_name


def settings_listing(cls: type, match: str = "") -> str:
    """The settings of ``cls`` whose key contains ``match``, those of the root first, then
    each settings tree's under a comment naming it."""
    every = list(leaves(cls))
    keys = {leaf.key for leaf in every}
    tree_classes = trees(cls)
    order = {name: i for i, name in enumerate(["", *tree_classes])}
    chosen = sorted(
        (leaf for leaf in every if match in leaf.key), key=lambda leaf: order[_tree(leaf)]
    )
    lines: list[str] = []
    current = ""
    for leaf in chosen:
        tree = _tree(leaf)
        if tree != current:
            current = tree
            about = headline(inspect.getdoc(tree_classes[tree]) or "")
            lines += ["", f"# {flag_name(tree)}.*: {about}"]
        lines.append(setting_line(leaf, keys))
    return "\n".join(lines).strip("\n") + "\n" if lines else ""


def _tree(leaf: Leaf) -> str:
    return leaf.key.split(".")[0] if "." in leaf.key else ""


def setting_line(leaf: Leaf, keys: set[str]) -> str:
    """``key = default  # (type: allowed) First sentence.`` (the setting commented out when it
    has no default or its default is none)."""
    kind = type_name(leaf.annotation) + (f": {leaf.allowed}" if leaf.allowed else "")
    key = toml_key(leaf.key, keys)
    if leaf.required:
        assignment, kind = f"# {key} = ...", f"{kind}; required"
    else:
        plain = to_plain(leaf.default)
        assignment = f"# {key} = none" if plain is None else f"{key} = {toml_value(plain)}"
    return f"{assignment}  # ({kind}) {first_sentence(leaf.doc)}"
