"""Detection accuracy and handle recall against labeled handle regions (paper, Table I)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from simgrasp.handles.core.detection import Detection
from simgrasp.labels import HandleLabel


def detection_accuracy(detection: Detection, label: HandleLabel) -> float:
    """Share of candidate neighborhood centers inside the labeled handle (NaN: no candidate).

    The paper's accuracy: "fraction of neighborhood centers labeled handle that fall in a real
    handle region". The detection and label must be in the same (object) frame.
    """
    if not detection.candidates:
        return float("nan")
    return float(label.contains(detection.candidate_centers).mean())


def handle_recall(detection: Detection, label: HandleLabel) -> bool:
    """Whether some detected handle's center lies on the labeled handle."""
    if not detection.handles or not label.has_handle:
        return False
    centers = np.stack([h.center for h in detection.handles])
    return bool(label.contains(centers).any())


def score_detection(
    detection: Detection | None, object_T_frame: NDArray[np.float64], label: HandleLabel
) -> tuple[float | None, bool | None]:
    """Accuracy (None without candidates) and recall of a detection made in another frame,
    ``object_T_frame`` mapping it into the label's object frame; (None, None) without one."""
    if detection is None:
        return None, None
    in_object = detection.moved(object_T_frame)
    accuracy = detection_accuracy(in_object, label)
    return (None if np.isnan(accuracy) else accuracy), handle_recall(in_object, label)
