"""Emit derived matrices as readable Python: a NumPy module and a CasADi module.

Both modules are printed from the same common-subexpression elimination of the same SymPy
expressions, so they compute the same thing by construction; tests cross-check them anyway.
"""

from __future__ import annotations

import sympy as sm
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.precedence import PRECEDENCE
from sympy.printing.pycode import PythonCodePrinter

from .models import DerivedModel
from .symbols import ALL_DESCRIPTIONS


class _CasadiPrinter(PythonCodePrinter):
    """Print elementary functions as CasADi calls (they accept SX, MX and numbers)."""

    def __init__(self):
        names = ("sin", "cos", "tan", "exp", "log", "sqrt")
        super().__init__({"user_functions": {name: f"casadi.{name}" for name in names}})

    def _print_Pow(self, expr, rational=False):  # noqa: N802 (SymPy printer protocol)
        if expr.exp == sm.S.Half:
            return f"casadi.sqrt({self._print(expr.base)})"
        return super()._print_Pow(expr, rational=rational)


class _NumPyPrinter(NumPyPrinter):
    """NumPy printer that writes small integer powers as products (numpy.power is slow)."""

    def __init__(self):
        super().__init__({"fully_qualified_modules": True})

    def _print_Pow(self, expr, rational=False):  # noqa: N802 (SymPy printer protocol)
        exponent = expr.exp
        if exponent.is_Integer and 1 <= abs(int(exponent)) <= 4:
            base = self.parenthesize(expr.base, PRECEDENCE["Mul"] + 1)
            product = "*".join([base] * abs(int(exponent)))
            return product if exponent > 0 else f"1/({product})"
        return super()._print_Pow(expr, rational=rational)


def _header(model: DerivedModel, backend: str, source_hash: str) -> str:
    return (
        f'"""{model.description}: linearized equation matrices ({backend}).\n\n'
        "GENERATED FILE - do not edit. Produced by ``whipple regenerate`` from the SymPy\n"
        f"derivation in derivation/ (model ``{model.name}``).\n\n"
        f"Derivation sources sha256: {source_hash}\n"
        f"SymPy version: {sm.__version__}\n\n"
        f"Equation form: {model.equation}.\n\n"
        "Parameters (SI units):\n"
        + "".join(f"    {name}: {ALL_DESCRIPTIONS[name]}\n" for name in model.parameters)
        + '"""\n'
    )


def _cse(model: DerivedModel):
    entries = [entry for matrix in model.matrices.values() for entry in matrix]
    replacements, reduced = sm.cse(entries, symbols=sm.numbered_symbols("x"), order="canonical")
    return replacements, reduced


def emit_numpy(model: DerivedModel, source_hash: str) -> str:
    """Module text with ``matrices(**parameters)`` broadcasting over arrays of parameters."""
    printer = _NumPyPrinter()
    replacements, reduced = _cse(model)
    arguments = ", ".join(model.parameters)
    lines = [_header(model, "NumPy", source_hash), "import numpy", "",
             f"PARAMETERS = {model.parameters!r}", f"OUTPUTS = {model.outputs!r}", "", "",
             f"def matrices({arguments}):",
             '    """Evaluate the matrices; parameters are arrays broadcast against each other.',
             "",
             "    Returns a tuple " + ", ".join(model.outputs)
             + " of arrays of shape broadcast_shape + their matrix shape.",
             '    """',
             f"    {arguments}, = numpy.broadcast_arrays("
             + ", ".join(f"numpy.asarray({name}, dtype=float)" for name in model.parameters) + ")",
             f"    shape = {model.parameters[0]}.shape"]
    for symbol, expression in replacements:
        lines.append(f"    {symbol} = {printer.doprint(expression)}")
    position = 0
    for name, matrix in model.matrices.items():
        rows, columns = matrix.shape
        lines.append(f"    {name} = numpy.zeros(shape + ({rows}, {columns}))")
        for k in range(rows * columns):
            value = reduced[position + k]
            if value != 0:
                lines.append(f"    {name}[..., {k // columns}, {k % columns}] = {printer.doprint(value)}")
        position += rows * columns
    lines.append(f"    return {', '.join(model.outputs)}")
    return "\n".join(lines) + "\n"


def emit_casadi(model: DerivedModel, source_hash: str) -> str:
    """Module text with ``matrices(p)`` for a CasADi vector p and ``function()``."""
    printer = _CasadiPrinter()
    replacements, reduced = _cse(model)
    lines = [_header(model, "CasADi", source_hash), "import casadi", "",
             f"PARAMETERS = {model.parameters!r}", f"OUTPUTS = {model.outputs!r}", "", "",
             "def matrices(p):",
             '    """The matrices as CasADi expressions of the parameter vector p (order PARAMETERS)."""',
             f"    {', '.join(model.parameters)}, = casadi.vertsplit(p)"]
    for symbol, expression in replacements:
        lines.append(f"    {symbol} = {printer.doprint(expression)}")
    position = 0
    for name, matrix in model.matrices.items():
        rows, columns = matrix.shape
        cells = [printer.doprint(reduced[position + k]) for k in range(rows * columns)]
        body = ", ".join("[" + ", ".join(cells[r * columns:(r + 1) * columns]) + "]" for r in range(rows))
        lines.append(f"    {name} = casadi.blockcat([{body}])")
        position += rows * columns
    lines += [f"    return {', '.join(model.outputs)}", "", "",
              "def function(symbol_type=casadi.SX):",
              f'    """casadi.Function p -> ({", ".join(model.outputs)}), p of length {len(model.parameters)}."""',
              f"    p = symbol_type.sym('p', {len(model.parameters)})",
              f"    return casadi.Function({model.name!r}, [p], list(matrices(p)), ['p'], list(OUTPUTS))"]
    return "\n".join(lines) + "\n"
