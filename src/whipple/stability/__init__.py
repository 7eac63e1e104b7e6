"""Stability of linear bicycle models over forward speed.

Modules
-------
modes
    Following eigenvalues across speed and naming the modes (weave, capsize, castering).
eigen
    :func:`eigen_analysis`: eigenvalues, eigenvectors and mode labels at many speeds.
characteristic
    The Hopf and real conditions for a change of stability.
roots
    Locating the zeros of the conditions over speed for many models at once.
critical
    :func:`critical_speeds`: every crossing and the stable speed ranges.
uncertainty
    First-order standard deviation of a critical speed.
report
    :func:`analyse_bicycle`: everything ``whipple check`` reports.
sweep
    Many parameter sets from a CSV table.
plots
    Eigenvalues against speed (the seed paper's Figure 6).
"""
