"""Data shipped with whipple: built-in bicycles, published references, layouts, measured runs."""
