"""The bicycle and its equations: parameters, bicycle files, linear models, the generated code.

Modules
-------
parameter_table
    Every parameter's name, unit and description (shared with the derivation).
parameter_set
    The data objects (:class:`Bicycle`, extensions, controller) and their physical checks.
bicycle_file
    Reading and writing bicycle files (TOML, BicycleParameters text).

Parameters
----------
    The public entry point: :func:`load_bicycle`, :func:`validate` and the names above.
linear
    :class:`LinearModel`, ``x' = A(v) x + B(v) f`` with A, B polynomial in the speed.
first_order
    The first-order form of second-order and descriptor equations, for NumPy and CasADi.
assembly
    From a bicycle to its linear model, through the generated code.
tyre
    The tyre-compliance model.
verification
    The generated code against published matrices.
"""
