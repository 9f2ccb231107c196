"""Mass properties as values: the :class:`~cadcog.mass.properties.MassProperties` result, closed
forms, inertia in other points and frames, and material densities. Pure numpy; no CAD.
"""
