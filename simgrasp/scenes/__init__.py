"""scenes stage: MuJoCo scenes, cameras and rendering (grippers: simgrasp.grippers)."""
