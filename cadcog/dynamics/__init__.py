"""The spacecraft's inertia tensor from the swing of the same hangs that locate its CoG.

Reference: ``docs/method.md`` §9, ``docs/inertia.md``.
"""
