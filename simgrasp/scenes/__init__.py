"""scenes stage: MuJoCo scenes, grippers, cameras and rendering."""
