"""The grasp proposers simgrasp knows, by name: the one list that the chain, the gymnasium
policy, the settings' choices (``detector.kind``) and ``evaluate --detector`` read.

Importable without MuJoCo or NumPy: an entry names its proposer as a ``module:function``
string, imported only by :meth:`ProposerEntry.load`. A proposer is

    propose(view, geometry, detector, planner, seed) -> (grasps, detection)

with ``view`` a :class:`~simgrasp.grasping.cloud_view.CloudView`, ``geometry`` the gripper's
:class:`~simgrasp.grippers.geometry.GripperGeometry`, ``detector`` the
:class:`~simgrasp.grasping.trials.chain_config.ChainDetectorConfig` (its ``kind`` the entry's name),
``planner`` the :class:`~simgrasp.grasping.planning.planner_config.PlannerConfig` and ``seed`` the
trial's; it returns the grasps ranked best first and, for a handle detector, its
:class:`~simgrasp.handles.core.detection.Detection` (else None). A new proposer is one module with
that function and an entry here, or :func:`register_proposer` at run time.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Any

from simgrasp.registry import Registry


@dataclass(frozen=True)
class ProposerEntry:
    """A registered grasp proposer: its ``name``, the ``module:function`` proposing grasps, a
    one-line ``summary`` (for help texts) and whether it detects handles (``handles``: its
    detection is scored against the labeled handle) or is a baseline."""

    name: str
    loader: str
    summary: str
    handles: bool = False

    def load(self) -> Any:
        """The proposer function, its module imported now."""
        module, _, function = self.loader.partition(":")
        return getattr(importlib.import_module(module), function)


PROPOSERS: Registry[ProposerEntry] = Registry(
    "proposer",
    (
        ProposerEntry(
            "quadric",
            "simgrasp.grasping.planning.proposal:propose_on_handles",
            "quadric fits with the paper's criteria, grasps across each handle",
            handles=True,
        ),
        ProposerEntry(
            "tenpas",
            "simgrasp.grasping.planning.proposal:propose_on_handles",
            "ten Pas & Platt 2013's cylindrical shells, grasps across each handle",
            handles=True,
        ),
        ProposerEntry(
            "centroid",
            "simgrasp.grasping.planning.proposal:propose_at_centroid",
            "baseline: top-down grasps at the cloud centroid",
        ),
        ProposerEntry(
            "random",
            "simgrasp.grasping.planning.proposal:propose_antipodal",
            "baseline: random antipodal point pairs",
        ),
    ),
)
"""Registered grasp proposers by name; the first is the default."""

DEFAULT_PROPOSER = "quadric"
BUILTIN_PROPOSERS = tuple(PROPOSERS)
"""The proposers simgrasp ships (``evaluate``'s default sweep)."""


def proposer_names() -> tuple[str, ...]:
    """Names of the registered proposers, the default first."""
    return PROPOSERS.names()


def proposer_entry(name: str) -> ProposerEntry:
    """The entry of the proposer ``name``, else an error naming the choices."""
    return PROPOSERS.entry(name)


def register_proposer(entry: ProposerEntry) -> None:
    """Add a proposer at run time (its name must be new); it is then a choice of
    ``detector.kind`` in every settings tree built afterwards in this process."""
    PROPOSERS.register(entry)
