"""Plots (matplotlib, Agg), one module per kind: ``detection`` (a detection on its cloud),
``segmentation`` (a segmented scene cloud), ``object_labels`` and ``scene_labels`` (labeled
handles of an object / a real scene), ``grasp_labels`` (a labeled grasp set). The sweep reports'
plots stay in :mod:`simgrasp.evaluation.report` (they are part of ``write_report``)."""
