"""Interactive 3D views of what simgrasp writes: grasp sets, trials, detections, reports."""
