"""The resumable-run engine shared by ``evaluate``, ``label-grasps`` and ``detect-eval``.

A run is a list of items, each turned into one JSON record by a task function. The engine runs
the items not yet recorded (in this process, in spawned worker processes, or as Ray tasks,
after warming the workers up: :mod:`simgrasp.runs.engine`), appends each record to the
output directory's JSONL log as it finishes (:mod:`simgrasp.runs.record_log`), holds the
directory for one run at a time (:mod:`simgrasp.runs.out_dir`) and refuses a directory that
was recorded with another configuration (:mod:`simgrasp.runs.identity`). It imports nothing of
the stages whose work it runs.
"""
