"""quadric stage."""
