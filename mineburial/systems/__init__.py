"""Systems: what one realization of an ensemble simulates.

:mod:`mineburial.systems.registry` declares every system an ensemble scenario may name
(its top-level ``system`` key): the falling mine and seed 004's restraining system.

Systems built on the planar multibody core (:mod:`mineburial.multibody`) live here too:
a description (bodies, joints, mass matrices: data), its applied forces (numba kernels in
:mod:`mineburial.kernels`), its right-hand side and stop event, and a summary.
:mod:`mineburial.systems.restraint.model` is seed 004's restraining system.
"""
