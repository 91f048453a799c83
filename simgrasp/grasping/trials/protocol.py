"""Names of the trial protocols (kept free of MuJoCo so command-line parsers can list them).

``full`` is the protocol of ``trial``, ``evaluate`` and the env; ``fast`` shortens every phase
for labeling large grasp sets (:data:`simgrasp.grasping.trials.trial.FAST_TRIAL`).
"""

from __future__ import annotations

from typing import Literal

Protocol = Literal["full", "fast"]
PROTOCOLS: tuple[Protocol, ...] = ("full", "fast")
DEFAULT_PROTOCOL: Protocol = "full"
