"""From measured runs to weave eigenvalues.

Modules
-------
runs, layouts
    Reading run files (native CSV, or any layout described by a small TOML file).
bundled
    The measured runs shipped with whipple (two experiments) and their experiment file.
experiment_file
    Experiment files: groups of runs, each with its bicycle and controller.
speedometer
    Forward speed from a raw speedometer signal; its regression over a window.
swings, windows
    Free-coasting windows, found automatically.
reference_windows
    Windows files, and the comparison of two sets of windows.
weave_starts, lsq_covariance, projection, weavefit
    The seed paper's damped sinusoid fitted by variable projection, with its covariance.
refit
    Refits of the damped sinusoid from starts near their optima, many windows at once.
mode_shape
    The weave's mode shape: a second signal's amplitude relative to the roll rate.
experiment
    :func:`measure_run`: every window of a run fitted, or rejected with a reason.
plots
    Runs, fits and measured eigenvalues (the seed paper's Figures 4 to 6).
"""
