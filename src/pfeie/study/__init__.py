"""Studies over many ground motions: one model, many records and intensities.

The factorised system is built once and shared by every record; the per-record demands
(peak and residual slip, opening, safety factors, stresses) go into one table; incremental
dynamic analysis (IDA) curves and fragility functions are fitted from it.
"""

__all__: list[str] = []
