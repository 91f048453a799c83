"""envs stage: the gymnasium environment ``simgrasp/HandleGrasp-v0`` and scripted policies.

Modules: ``handle_grasp`` (the env and its config), ``observation`` and ``action`` (the
spaces and their encodings), ``policy`` (:class:`~simgrasp.envs.policy.DetectorPolicy`). The
env is registered by ``import simgrasp``, without importing this package.
"""
