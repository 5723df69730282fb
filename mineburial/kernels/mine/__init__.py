"""The falling mine's kernels (seed 000): its equations of motion and their fluid, sediment,
overburden and rest laws, its body protocol (:mod:`.bodies`), its parameter and state layout
(:mod:`.layout`), its drop driver on the integration core (:mod:`.stepper`) and the scour
kernels (docs/scour.md).

They run on the generic integration core of :mod:`mineburial.kernels` (:mod:`~mineburial.kernels.core`,
:mod:`~mineburial.kernels.integrators`, :mod:`~mineburial.kernels.methods`,
:mod:`~mineburial.kernels.status`) and its generic math (:mod:`~mineburial.kernels.rotation`,
:mod:`~mineburial.kernels.crossflow`); docs/design.md, "Layout".
"""
