"""Synthetic measured runs: what a riderless bicycle on a treadmill or the ground would record.

Modules
-------
scenario
    :class:`RunScenario`: speed, pushes, catches, sensors, seed.
procedure
    What both simulators share: samples, speed profile, pushes, the hand, sensors, metadata.
simulator
    :func:`simulate_run`: the linear model integrated exactly between samples.
nonlinear_run
    :func:`simulate_nonlinear_run`: the same runs with the nonlinear model as the true motion.
nonlinear_bicycle
    The nonlinear equations with the controller, steer damping, rear wheel drive and hand.
nonlinear
    :func:`simulate`: the nonlinear equations integrated from a state, with given torques.
discretization
    Exact zero-order-hold discretization (batched matrix exponentials).
speedometer_signal
    The raw magnet-ring speedometer signal.
run_writer
    Writing simulated runs as run files.
"""
