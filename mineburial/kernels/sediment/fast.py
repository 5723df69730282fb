"""Fast fixed-cost rule for the sediment tractions (placeholder: calls the reference)."""

from mineburial._numba import kernel
from mineburial.kernels.sediment.reference import reference_tractions


@kernel
def fast_tractions(L, R, chi, c20, c21, c22, d0, vbody, law, bank):
    return reference_tractions(L, R, chi, c20, c21, c22, d0, vbody, law, bank)
