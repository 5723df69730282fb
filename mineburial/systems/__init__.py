"""Systems built on the planar multibody core (:mod:`mineburial.multibody`).

A system is a description (bodies, joints, mass matrices: data), its applied forces
(numba kernels in :mod:`mineburial.kernels`), its right-hand side and stop event, and a
summary. :mod:`mineburial.systems.restraint` is seed 004's restraining system.
"""
