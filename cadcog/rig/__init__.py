"""The suspension test rig as parameters: its inclinometer, body-frame geometry, the
:class:`~cadcog.rig.parameters.Rig` with its closed-form mass properties, and the rig file reader.
"""
