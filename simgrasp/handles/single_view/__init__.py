"""The single-view detector: the quadric detector's candidates on one camera's view, kept by the
shipped classifier over their features (:mod:`.candidate_features`) or the standoff test
(:mod:`.standoff`), those on the view's body wall dropped (:mod:`.body_wall`); :mod:`.view_kind`
says whether a cloud is one view at all."""
