"""View providers (GUI side)."""
