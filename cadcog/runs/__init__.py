"""Runs: one composition per command, shared by the command and the API (campaign, setup init,
acquire, plan; the others still compose one layer down).

A run takes checked, typed arguments (paths, a rig or a set-up, options), does the work through
the library below it, stages its outputs and puts them in place together, and returns a result
whose ``to_dict()`` is the command's ``--json``. The command parses and prints;
:mod:`cadcog.api` checks Python arguments; neither composes the work again.
"""
