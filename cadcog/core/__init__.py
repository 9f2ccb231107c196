"""Foundations every layer uses: errors, units, tolerances, input bounds, atomic output files,
process pools and the strict TOML reader. Nothing here knows about rigs or spacecraft.
"""
