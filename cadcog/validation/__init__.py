"""Does the predicted error match experiments: virtual campaigns as a lab records them, and the
verification of a campaign against the Monte Carlo (docs/method.md §6).
"""
