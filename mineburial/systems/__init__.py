"""Systems: what one realization of an ensemble simulates, one package a system.

:mod:`mineburial.systems.registry` declares every system an ensemble scenario may name
(its top-level ``system`` key): the falling mine (:mod:`mineburial.systems.mine`) and seed 004's
restraining system (:mod:`mineburial.systems.restraint`, built on the planar multibody core
:mod:`mineburial.multibody`). A system's numba kernels live in its subpackage of
:mod:`mineburial.kernels` (docs/design.md, "Layout").
"""
