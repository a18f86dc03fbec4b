"""Electric energy of the drives: interval integration and regeneration policies (a plug-in family)."""
