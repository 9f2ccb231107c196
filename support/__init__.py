"""Independent generators and fixtures shared by ``tests/`` and ``benchmarks/``.

Not part of the installed package (``pyproject.toml`` lists cadcog's packages by name). What
lives here is the truth cadcog is checked against, so it must not borrow cadcog's estimators
or error models: the four that simulate physics (:mod:`support.swing_truth`,
:mod:`support.rig_campaigns`, :mod:`support.forward_model`, :mod:`support.phone_logs`) and the
phone's scenarios import nothing from cadcog (``tests/test_support.py`` checks it); the others
read cadcog's inputs (a rig, a set-up, the CAD's mass properties), write its files or run it.

- :mod:`support.swing_truth`: the nonlinear rigid body on a massless wire (the swing's truth);
- :mod:`support.swing_files`: campaigns of that body written as swing and readings files;
- :mod:`support.estimator_runs`: ``cadcog inertia`` run in-process on those files, and scored;
- :mod:`support.rig_campaigns`: the paper rig's static hangs from the documented physics (one
  wire and one sensor per campaign, the stiff wire's elastica integrated numerically);
- :mod:`support.forward_model`: a spacecraft on its ME, hung and read, for the set-up's checks;
- :mod:`support.phone_logs`: a phone's or a MEMS accelerometer's whole log of a test;
- :mod:`support.phone_scenarios`: its named tests (sensor figures, bodies, wire exits) and a
  command that writes one log with its truth;
- :mod:`support.rigtools`: the paper rig as a dictionary, and rig files written from one;
- :mod:`support.stepfixtures`: STEP assemblies written through OCCT's XCAF document.

Tests import it as ``support.…`` (pytest puts the repository root on ``sys.path``); the
benchmarks insert the root themselves.
"""
