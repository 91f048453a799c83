"""Handle labels found automatically on a mesh: the quadric detector run on virtual scans of it
(:mod:`.virtual_scan`), its candidates pooled and clustered into handle parts
(:mod:`.auto_label`) and each part's surface grown into a labeled region (:mod:`.label_surface`).
The detector never imports this package."""
