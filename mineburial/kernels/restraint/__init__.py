"""Seed 004's restraining system's kernels: its applied forces (:mod:`.forces`).

They run on the generic planar Kane core (:mod:`mineburial.kernels.multibody`), its generic
seabed contact (:mod:`mineburial.kernels.seabed_contact`: elastic foundation and regularised
Coulomb friction, for any body of a multibody system) and the integration core of
:mod:`mineburial.kernels`; the system's schema, tables and setup are
:mod:`mineburial.systems.restraint.model` (docs/restraint.md, docs/design.md "Layout").
"""
