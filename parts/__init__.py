"""Rig parameter files shipped with cadcog (installed as ``cadcog._rigs``)."""
