"""What the model gets wrong on measured data, the physical cause, the extended model, the gain.

Modules
-------
observations
    One window's measured weave eigenvalue and mode shape, and the model's nearest mode.
causes
    Candidate causes: each a model change with one or two physical parameters.
fitting
    Whitened residuals of a model, and one cause fitted to observations (robust least squares).
consistency
    Whether a fitted cause holds across speeds: its jackknife spread over speed groups, and its
    values fitted to the low and the high speeds apart.
evidence
    Every cause fitted to all observations; evidence and verdict.
starts
    Starting values for a cause's fit: fixed points and the best points of a coarse grid.
families
    Families of causes that change the same physics (named when the data cannot tell their
    members apart), and pairs of causes fitted jointly.
evaluation
    Models scored on measured windows, per speed and overall: the weave eigenvalue's error and
    the samples' residual (``whipple evaluate``; the held-out gain's per-speed figures).
gain
    The extended model's error on speeds that its choice and fit never saw (the cause chosen
    by evidence or by prediction), and every candidate's error there without a choice.
amplitude
    The nonlinear model's weave at each window's measured amplitude against the linear one.
report
    The report as plain data, JSON and Markdown.
plots
    The report's figures.
"""
