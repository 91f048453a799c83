"""Segmentation of a sensor scene cloud: the table plane and the objects on it (``segment``,
its settings ``segment_config``), splitting objects into parts (``segment_parts``), rims
(``segment_rims``) and the image-grid segmentation of organized clouds
(``organized_segments``)."""
