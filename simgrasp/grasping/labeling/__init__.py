"""Labeling grasp sets: reading them from files (``grasp_sets``), scoring each grasp in a trial
(``labeling``), the resumable run (``label_run``) and the agreement of two runs
(``label_compare``)."""
