"""A spacecraft from its CAD: the set-up file, test planning, mass budget and summary, the CubeSat
CoG envelope, requirements checks for CI, baselines and the Bayesian update of the CAD by a
measurement.
"""
