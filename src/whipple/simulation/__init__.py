"""Synthetic measured runs: what a riderless bicycle on a treadmill or the ground would record.

Modules
-------
scenario
    :class:`RunScenario`: speed, pushes, catches, sensors, seed.
simulator
    :func:`simulate_run`: the linear model integrated exactly between samples.
discretization
    Exact zero-order-hold discretization (batched matrix exponentials).
speedometer_signal
    The raw magnet-ring speedometer signal.
run_writer
    Writing simulated runs as run files.
"""
