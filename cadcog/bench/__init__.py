"""At the bench: live acquisition from the measurement equipment (``cadcog acquire``).

- :mod:`~cadcog.bench.protocol`: the line protocol the firmware in ``firmware/`` speaks;
- :mod:`~cadcog.bench.swing`: settle detection, swing period and decay;
- :mod:`~cadcog.bench.link`: byte sources (a serial port through pyserial);
- :mod:`~cadcog.bench.recorder`: one hang, from the stream to averaged samples;
- :mod:`~cadcog.bench.readingsfile`: the readings CSV, appended durably, resumable;
- :mod:`~cadcog.bench.target`: what is measured (a rig or a spacecraft set-up), the planned hangs
  and the one call into the estimator;
- :mod:`~cadcog.bench.pendulum`, :mod:`~cadcog.bench.simulator`: the simulated device;
- :mod:`~cadcog.bench.session`: the guided test run.

Reference: ``docs/bench.md``.
"""
