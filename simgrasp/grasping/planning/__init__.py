"""Grasp planning: grasp poses from detected handles (``planner``, its settings
``planner_config``, ``proposal``) and antipodal sampling on a mesh (``antipodal``)."""
