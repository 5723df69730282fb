"""Validation and benchmark suite: model comparison, Sobol' sensitivity, validation cases.

* :mod:`mineburial.analyses.compare` -- ``mineburial compare``: the same sampled drops
  under several variants of one scenario field (physics model, sediment resistance, ...).
* :mod:`mineburial.analyses.sensitivity` -- ``mineburial sensitivity``: first-order and
  total Sobol' indices of penetration and burial for every random input.
* :mod:`mineburial.validation.references` -- closed forms and independent numerical
  references (shared by the validation report and the tests).
* :mod:`mineburial.validation.cases` and :mod:`mineburial.validation.report` --
  ``mineburial validate``: every validation case, one row per quantity, as Markdown, PNG
  figures and JSON.
"""
