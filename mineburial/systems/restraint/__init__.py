"""Seed 004's restraining system: its model (case, configuration, run, Dataset), its ensemble and
its command. Its kernels are in :mod:`mineburial.kernels.restraint` (docs/design.md, "Layout")."""
