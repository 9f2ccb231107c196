"""Command-line interface: ``cadcog`` (see :func:`main`)."""

from cadcog.cli._main import main

__all__ = ["main"]
