"""The falling mine (seed 000): its scenario and fields, its ensemble, Dataset and statistics,
its single drop, figure, commands, calibration and post-impact processes. Its kernels are in
:mod:`mineburial.kernels.mine` (docs/design.md, "Layout")."""
