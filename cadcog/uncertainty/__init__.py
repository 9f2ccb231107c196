"""What the method's error is: the vectorised Monte Carlo, the paper's study over random
suspension points, distribution fits and the error budget by source.
"""
