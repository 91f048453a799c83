"""The trial protocols by name: the one list that ``label-grasps --protocol``, ``trial
--protocol``, labeling and the docs read.

A protocol is a named sequence of trial phases (:mod:`simgrasp.grasping.trials.phases`) and
the settings they run with (a :class:`~simgrasp.grasping.trials.trial_config.TrialConfig`). A
new protocol is one entry of :data:`PROTOCOLS`. Importable without MuJoCo (command-line
parsers list the names): phases are named here and run by
:func:`simgrasp.grasping.trials.trial.run_trial`.
"""

from __future__ import annotations

from dataclasses import dataclass

from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.trial_config import (
    ACRONYM_FAST_TRIAL,
    ACRONYM_TRIAL,
    FAST_TRIAL,
    TrialConfig,
)

LIFT_TEST: tuple[str, ...] = ("settle", "pregrasp", "approach", "close", "lift", "hold", "tugs")
"""A grasp tested on the table: the object settles, the open gripper comes in from the
pre-grasp, closes, lifts, holds, and the object is tugged at (free-floating: the hand appears
at the grasp, and the object's gravity comes on instead of the lift)."""
SHAKE_TEST: tuple[str, ...] = ("settle", "pregrasp", "approach", "close", "shake")
"""A grasp tested by ACRONYM's shake after the close (free-floating, the approach does
nothing: the hand appears at the grasp)."""


@dataclass(frozen=True)
class TrialProtocol:
    """A registered protocol: its ``name``, a one-line ``summary`` (for help texts and the
    docs), the ``phases`` it runs in order (names of
    :data:`~simgrasp.grasping.trials.phases.PHASES`), its trial settings ``config`` and the
    ``results`` page (under ``docs/results/``) that measured it."""

    name: str
    summary: str
    phases: tuple[str, ...]
    config: TrialConfig
    results: str

    def __post_init__(self) -> None:
        if ("shake" in self.phases) != (self.config.shake is not None):
            raise SimgraspError(
                f"protocol {self.name!r}: a shake phase needs the config's shake settings, "
                "and shake settings need a shake phase"
            )


PROTOCOLS: dict[str, TrialProtocol] = {
    protocol.name: protocol
    for protocol in (
        TrialProtocol(
            "full",
            "every phase its full length: the trials of trial, evaluate and the env",
            LIFT_TEST,
            TrialConfig(),
            "docs/results/chain/",
        ),
        TrialProtocol(
            "fast",
            "the full protocol's phases, cut short where verdicts do not change: for labeling "
            "large grasp sets",
            LIFT_TEST,
            FAST_TRIAL,
            "docs/results/grasp-sets/",
        ),
        TrialProtocol(
            "acronym",
            "ACRONYM's test in free space: the hand appears at the grasp, closes and shakes",
            SHAKE_TEST,
            ACRONYM_TRIAL,
            "docs/results/acronym/",
        ),
        TrialProtocol(
            "acronym-fast",
            "acronym with one shaking cycle per motion instead of two: for labeling large sets",
            SHAKE_TEST,
            ACRONYM_FAST_TRIAL,
            "docs/results/acronym-fast/",
        ),
    )
}
"""Registered protocols by name; the first is the default."""

DEFAULT_PROTOCOL = "full"


def protocol_names() -> tuple[str, ...]:
    """Names of the registered protocols, the default first."""
    return tuple(PROTOCOLS)


def get_protocol(name: str) -> TrialProtocol:
    """The protocol called ``name``; a one-line error naming the choices otherwise."""
    if name not in PROTOCOLS:
        raise SimgraspError(f"unknown protocol {name!r}; use one of {', '.join(PROTOCOLS)}")
    return PROTOCOLS[name]


def default_phases(config: TrialConfig) -> tuple[str, ...]:
    """The phases a trial of ``config`` runs when no protocol names them (the ``--trial.*``
    settings of ``trial`` and ``evaluate``, the env): the shake test where ``config.shake`` is
    set, the lift test otherwise."""
    return SHAKE_TEST if config.shake is not None else LIFT_TEST
