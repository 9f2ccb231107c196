"""Every numerical tolerance cadcog uses, in one documented place.

Lengths are in mm, relative values are dimensionless. Change a value here, not at the call site.
"""

#: Distance within which a point counts as lying on a plane or face (mm). Parameter files give
#: positions to 1e-3 mm at best; 1e-6 mm only absorbs floating-point round-off.
ON_SURFACE_MM = 1e-6

#: A suspension point this far inside a face of the body's box still sits on that face (mm).
#: Every file cadcog writes gives positions to 1e-3 mm (a rounding of at most 5e-4 mm), and
#: OCCT's bounding box of curved faces is ~1e-7 mm larger than the part, so a point the tool
#: itself produced is never refused as lying inside the body. A point deeper than this needs its
#: face named (``[[candidates.points]] face = "+x"``): it sits on the model, not on its box.
SUSPENSION_ON_FACE_MM = 0.01

#: Least angle (degrees) between a hang's vertical and the inclinometer's x-y plane for its
#: readings to be trusted: the vertical's z component is sqrt(1 - sin²X - sin²Y), whose error
#: grows as 1/cos of that angle's complement; below 10° a 0.1° reading error moves it by more
#: than 0.5°, and the readings' noise can push sin²X + sin²Y past 1 (the vertical is then
#: rescaled onto the plane). ``cadcog plan`` does not use such points.
MIN_VERTICAL_ELEVATION_DEG = 10.0

#: Overlap depth below which two boxes are considered touching rather than intersecting (mm).
CONTACT_MM = 1e-6

#: Relative accuracy requested from OCCT's adaptive Gauss integration of volume properties
#: (``BRepGProp.VolumeProperties_s`` with ``Eps``). Planar and cylindrical faces integrate
#: exactly, so the achieved error is usually far smaller; the achieved estimate is reported.
OCCT_INTEGRATION_EPS = 1e-9

#: Chordal deflection used when tessellating B-rep solids for STL export (mm, absolute). The
#: volume between a curved face and its inscribed tessellation is at most this deflection times
#: the face area, which is how the STL cross-check's tolerance is derived.
STL_DEFLECTION_MM = 1e-3

#: Angular deflection for tessellation (degrees).
STL_ANGULAR_DEFLECTION_DEG = 5.0

#: Relative agreement expected between exact B-rep integration and the closed forms.
CLOSED_FORM_RTOL = 1e-9

#: Significant digits kept when writing floats to ground-truth JSON. Fifteen digits round-trip
#: every value OCCT computes to well within its integration error, and drop the last-bit noise
#: that differs between platforms, so golden files stay byte-stable.
JSON_SIGNIFICANT_DIGITS = 15

#: Entries of a vector or matrix smaller than this fraction of its largest entry are round-off
#: (OCCT's integration leaves ~1e-13 relative residue in products of inertia that are exactly
#: zero by symmetry) and are written to ground truth as 0.
ROUNDOFF_RELATIVE = 1e-11

#: Smallest angle between two plumb lines for their closest approach to be trusted (degrees).
#: The estimate's sensitivity to a lateral error of either line grows as 1/sin(angle): ×11.5 at
#: 5°. Pairs below this raise :class:`cadcog.core.errors.IllConditionedError`; the joint estimator
#: skips them in its pair diagnostics. Configurable per call.
MIN_PAIR_ANGLE_DEG = 5.0

#: Probability below which a suspension's residual (squared distance of its line from the joint
#: estimate over its variance, ~χ² with 2 degrees of freedom) flags it as inconsistent.
OUTLIER_PROBABILITY = 0.003

#: Axis-aligned boxes of two solids must overlap by more than this on every axis (mm) for the
#: pair to be tested for overlap with a boolean; boxes that only touch are pruned.
BOX_OVERLAP_MM = 1e-3

#: A common volume of two solids at or below this (mm³) is contact, not overlap: touching faces
#: and modelling-tolerance interpenetration of real CAD (0.004 mm³ is typical) stay below it.
CONTACT_VOLUME_MM3 = 0.01

#: ... and at or below this fraction of the smaller solid's volume.
CONTACT_VOLUME_RELATIVE = 1e-6

#: Overlapping solids double-count mass; above this fraction of the total mass the computation
#: refuses (``--allow-overlap`` or ``--resolve-overlaps`` choose), below it each solid counts as
#: it is and a note says how much was double-counted.
OVERLAP_REFUSE_MASS_FRACTION = 1e-3

#: A body's placement in an assembly is taken as rigid (rotation and translation, so its
#: placement-free mass properties can be reused for every instance) when its scale factor is 1
#: and its rotation is orthonormal to this tolerance; otherwise the placed shape is integrated.
RIGID_PLACEMENT_TOLERANCE = 1e-9

#: Self-calibration of the wire scale λ: the information the lines give on λ once the CoG is
#: free, relative to what they would give if every offset moved its line sideways, below which
#: λ is declared unidentifiable (the bolt axes lie along their verticals, or the CoG absorbs
#: the offsets).
WIRE_IDENTIFIABILITY = 1e-6

#: Smallest dimension (mm) of a solid cadcog builds from parameters (rig parts, the example
#: CubeSat's panels and components). OCCT resolves 1e-7 mm, but a solid thinner than 10 µm is a
#: typo in a parameter file, and boxes of 1e-300 mm make OCCT fail deep inside.
MIN_SOLID_DIMENSION_MM = 0.01

#: How far the false-alarm rate of ``cadcog validate``'s campaign verdict may stray from its
#: stated level (absolute, 0.02 = ±2 percentage points at 5 %), measured on null campaigns from
#: an independent generator (``benchmarks/study_validation_adc.py``, ``docs/validation.md``).
VALIDATION_SIZE_TOLERANCE = 0.02

#: Largest gap between the measurement equipment's base and the model's bounding box (mm) that a
#: set-up may give: the ME is bolted onto the spacecraft (an adapter plate at most), so a base
#: centre farther away is a typo or a unit slip (``base_center_mm`` in m or in.), not a set-up.
ME_BASE_MAX_GAP_MM = 50.0

#: Default 1 σ of a weighing (kg): a lab scale of 1 g resolution. Every command and API function
#: that takes ``--mass-sigma-kg`` / ``mass_sigma_kg`` defaults to it (one figure, here).
DEFAULT_WEIGHING_SIGMA_KG = 0.001


#: An object's compensated CoG further outside its box (the rig's proof mass, a set-up's model
#: bounding box) than this many of its σ on an axis, plus :data:`OUTSIDE_BODY_MARGIN_MM`, is
#: refused: a rigid body's CoG lies inside its convex hull, so the test did not locate it (a
#: weighed mass far from the hung object's, readings of another object, a wrong hang). A set-up
#: warns from 3 σ (``spacecraft.setup``).
OUTSIDE_BODY_SIGMAS = 5.0

#: See :data:`OUTSIDE_BODY_SIGMAS` (mm): what a CoG a hair outside a face may be off by.
OUTSIDE_BODY_MARGIN_MM = 1.0
