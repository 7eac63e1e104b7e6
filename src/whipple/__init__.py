"""whipple: the linearized Whipple bicycle, derived, checked and confronted with data."""

__version__ = "0.1.0"
