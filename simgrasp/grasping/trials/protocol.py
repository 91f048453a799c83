"""Names of the trial protocols (kept free of MuJoCo so command-line parsers can list them).

``full`` is the protocol of ``trial``, ``evaluate`` and the env; ``fast`` shortens every phase
for labeling large grasp sets (:data:`simgrasp.grasping.trials.trial.FAST_TRIAL`); ``acronym``
is ACRONYM's free-floating close and shake
(:data:`simgrasp.grasping.trials.trial_config.ACRONYM_TRIAL`).
"""

from __future__ import annotations

from typing import Literal

Protocol = Literal["full", "fast", "acronym"]
PROTOCOLS: tuple[Protocol, ...] = ("full", "fast", "acronym")
DEFAULT_PROTOCOL: Protocol = "full"
