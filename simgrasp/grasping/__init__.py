"""grasping stage: grasp poses from handles, grasp trials in MuJoCo and their scoring."""
