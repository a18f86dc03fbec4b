"""Searching placements: the best and worst by an objective (optimize), and maps over grids (sweep)."""
