"""The phases of a grasp trial, by name (:data:`PHASES`): what protocols
(:mod:`simgrasp.grasping.trials.protocol`) are sequences of. One module per family: the start
(settle, pre-grasp, approach), the close, the lift and hold, the tugs, the shake. A new phase
is a :class:`TrialPhase` subclass and one entry here."""

from __future__ import annotations

from collections.abc import Sequence

from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.phases.base import TrialPhase
from simgrasp.grasping.trials.phases.close import Close
from simgrasp.grasping.trials.phases.lift import Hold, Lift
from simgrasp.grasping.trials.phases.shake import Shake
from simgrasp.grasping.trials.phases.start import Approach, Pregrasp, Settle
from simgrasp.grasping.trials.phases.tugs import Tugs

PHASES: dict[str, TrialPhase] = {
    phase.name: phase
    for phase in (Settle(), Pregrasp(), Approach(), Close(), Lift(), Hold(), Tugs(), Shake())
}
"""Every phase by name, in the order a trial on the table runs them."""


def phase_sequence(names: Sequence[str]) -> tuple[TrialPhase, ...]:
    """The phases called ``names``, in that order; a one-line error naming an unknown one."""
    unknown = [name for name in names if name not in PHASES]
    if unknown:
        known = ", ".join(PHASES)
        raise SimgraspError(f"unknown trial phase {unknown[0]!r}; the phases are {known}")
    return tuple(PHASES[name] for name in names)


__all__ = ["PHASES", "TrialPhase", "phase_sequence"]
