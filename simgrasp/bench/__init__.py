"""The handle-grasping benchmark: fixed suites of scenes, any method, scores against what was
possible (``simgrasp bench``; docs/commands/bench.md).

Modules: ``suites`` (the frozen suite definitions), ``scene_build`` (a scene built and seen
from its definition), ``observation`` (what a method sees, and its export as files),
``export`` (a suite's scenes as folders), ``grasp_files`` (a method's answer read and
checked), ``methods`` (in-process methods), ``execution`` (an answer executed in its scene),
``scene_task`` (one scene's record), ``oracle`` (what was possible per scene), ``runner``
(suites on the run engine), ``summary`` (scores and report).
"""
