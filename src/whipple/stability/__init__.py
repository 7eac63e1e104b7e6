"""Stability of linear bicycle models over forward speed.

Modules
-------
modes
    Following eigenvalues across speed and naming the modes (weave, capsize, castering).
eigen
    :func:`eigen_analysis`: eigenvalues, eigenvectors and mode labels at many speeds.
characteristic
    The Hopf and real conditions for a change of stability, as CasADi expressions.
polynomial
    The characteristic polynomial, Hopf and real conditions as exact polynomials in v;
    the Routh-Hurwitz test.
polyroots
    All real roots of many polynomials in a speed interval at once.
root_spectrum
    The spectrum at each root: verification, direction and mode of a crossing.
crossing_modes
    The mode that crosses at a critical speed, named at the root.
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
