"""The base of every trial phase: a name and ``run(state) -> failure | None``."""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import TYPE_CHECKING, ClassVar

if TYPE_CHECKING:
    from simgrasp.grasping.trials.result import Failure
    from simgrasp.grasping.trials.state import TrialState


class TrialPhase(ABC):
    """One step of a grasp trial (settle, approach, close, lift, ...). A protocol
    (:mod:`simgrasp.grasping.trials.protocol`) names a sequence of phases;
    :func:`~simgrasp.grasping.trials.trial.run_trial` runs them in turn on one
    :class:`~simgrasp.grasping.trials.state.TrialState` until one fails, recording each one's
    wall time under its ``name``. A phase keeps no state of its own: what it leaves for the
    later phases goes into the trial state."""

    name: ClassVar[str]
    """How protocols name the phase (and its key in a record's ``timings_s``)."""

    @abstractmethod
    def run(self, state: TrialState) -> Failure | None:
        """Step the trial through this phase; the failure that ends the trial here, or None
        to go on."""
