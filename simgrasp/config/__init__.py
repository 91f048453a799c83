"""Settings: frozen dataclass trees, the single source of every setting of a run.

:mod:`~simgrasp.config.fields` marks fields with command-line facts,
:mod:`~simgrasp.config.checks` declares and enforces what each field allows,
:mod:`~simgrasp.config.schema` walks a tree's leaves, :mod:`~simgrasp.config.tree` builds,
flattens and diffs trees, :mod:`~simgrasp.config.files` reads TOML/YAML and ``--set`` and
prints TOML, and :mod:`~simgrasp.config.arguments` generates the command-line flags.
Nothing here imports MuJoCo.
"""

from simgrasp.config.checks import Checked, SettingError
from simgrasp.config.fields import setting
from simgrasp.config.tree import build, diff, flatten

__all__ = ["Checked", "SettingError", "build", "diff", "flatten", "setting"]
