"""Seed 004's restraining system's kernels: its applied forces (:mod:`.forces`) and its
seabed contact (:mod:`.seabed_contact`: elastic foundation and regularised Coulomb friction).

They run on the generic planar Kane core (:mod:`mineburial.kernels.multibody`) and the
integration core of :mod:`mineburial.kernels`; the system's schema, tables and setup are
:mod:`mineburial.systems.restraint` (docs/restraint.md, docs/design.md "Where things are").
"""
