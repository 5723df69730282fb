"""Analyses over a system's ensembles: maps (one ensemble a grid cell), compare (variants side by
side) and sensitivity (one-at-a-time and Sobol' indices); today the mine's (docs/design.md, "Layout")."""
