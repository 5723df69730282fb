"""The compiled kernels (numba).

This package holds the generic integration core, which knows no mine and no ship
(:mod:`.core`, :mod:`.integrators`, :mod:`.methods`, :mod:`.status`), the generic planar Kane
core (:mod:`.multibody`) and generic math (:mod:`.rotation`, :mod:`.crossflow`); each system's
kernels are a subpackage: :mod:`.mine` (the falling mine, seed 000) and :mod:`.restraint`
(seed 004's restraining system). docs/design.md, "Layout".
"""
