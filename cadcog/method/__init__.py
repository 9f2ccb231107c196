"""The measurement method, from readings to the compensated CoG: the error model of each plumb
line, the readings CSV, the plumb-line estimators (pairwise and generalised least squares) and
:func:`~cadcog.method.estimate.estimate_cog`.
"""
