"""handles stage."""
