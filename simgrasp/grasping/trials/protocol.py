"""Names of the trial protocols (kept free of MuJoCo so command-line parsers can list them).

``full`` is the protocol of ``trial``, ``evaluate`` and the env; ``fast`` shortens every phase
for labeling large grasp sets (:data:`simgrasp.grasping.trials.trial.FAST_TRIAL`); ``acronym``
is ACRONYM's free-floating close and shake
(:data:`simgrasp.grasping.trials.trial_config.ACRONYM_TRIAL`); ``acronym-fast`` the same with one
shaking cycle per motion instead of two, for labeling large ACRONYM-style sets
(:data:`simgrasp.grasping.trials.trial_config.ACRONYM_FAST_TRIAL`).
"""

from __future__ import annotations

from typing import Literal

Protocol = Literal["full", "fast", "acronym", "acronym-fast"]
PROTOCOLS: tuple[Protocol, ...] = ("full", "fast", "acronym", "acronym-fast")
DEFAULT_PROTOCOL: Protocol = "full"
