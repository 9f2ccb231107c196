"""The CAD layer: build123d models of a rig, exact OCCT mass properties and file export.

Everything that imports build123d (about 3 s) lives here, so that the numeric core and the
commands that do not need geometry start fast.
"""
