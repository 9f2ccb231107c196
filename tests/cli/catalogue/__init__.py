"""The catalogue of bad inputs, a module a family of commands; run by
``tests/cli/test_bad_input.py``."""
