"""Emit derived matrices as readable Python: a NumPy module and a CasADi module.

Both modules are printed from the same common-subexpression elimination of the same SymPy
expressions, so they compute the same thing by construction; tests cross-check them anyway.
A linear model (:class:`DerivedModel`) becomes one function of the parameters; a set of
functions of the parameters and state variables (:class:`DerivedFunctions`, the nonlinear
model) becomes one function per entry, each with its own subexpression elimination.
"""

from __future__ import annotations

import sympy as sm
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.precedence import PRECEDENCE
from sympy.printing.pycode import PythonCodePrinter

from .models import DerivedFunction, DerivedFunctions, DerivedModel
from .symbols import ALL_DESCRIPTIONS


class _CasadiPrinter(PythonCodePrinter):
    """Print elementary functions as CasADi calls (they accept SX, MX and numbers)."""

    def __init__(self):
        names = ("sin", "cos", "tan", "exp", "log", "sqrt")
        super().__init__({"user_functions": {name: f"casadi.{name}" for name in names}})

    def _print_Pow(self, expr, rational=False):  # noqa: N802 (SymPy printer protocol)
        if expr.exp == sm.S.Half:
            return f"casadi.sqrt({self._print(expr.base)})"
        if expr.exp == -sm.S.Half:
            return f"1/casadi.sqrt({self._print(expr.base)})"
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


def _scalar_path(arguments: tuple[str, ...]) -> list[str]:
    """Lines that turn 0-d arguments into NumPy scalars.

    One parameter set (a diagnosis fit evaluates thousands, one at a time) costs several times
    less as NumPy scalars than as 0-d arrays; the arithmetic is the same IEEE double arithmetic
    (the printed code has only +, -, *, / and NumPy functions), so the results are identical.
    """
    names = ", ".join(arguments)
    return ["    if not shape:",
            f"        {names}, = (value[()] for value in ({names},))"]


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
             f"    shape = {model.parameters[0]}.shape",
             *_scalar_path(model.parameters)]
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


def _functions_header(model: DerivedFunctions, backend: str, source_hash: str) -> str:
    order = list(ALL_DESCRIPTIONS)
    variables = sorted({name for function in model.functions for name in function.variables}, key=order.index)
    return (
        f'"""{model.description} ({backend}).\n\n'
        "GENERATED FILE - do not edit. Produced by ``whipple regenerate`` from the SymPy\n"
        f"derivation in derivation/ (model ``{model.name}``).\n\n"
        f"Derivation sources sha256: {source_hash}\n"
        f"SymPy version: {sm.__version__}\n\n"
        f"Equation form: {model.equation}.\n\n"
        "Functions: " + ", ".join(function.name for function in model.functions) + ".\n\n"
        "Parameters (SI units):\n"
        + "".join(f"    {name}: {ALL_DESCRIPTIONS[name]}\n" for name in model.parameters)
        + "\nVariables:\n"
        + "".join(f"    {name}: {ALL_DESCRIPTIONS[name]}\n" for name in variables)
        + '"""\n'
    )


def _function_cse(function: DerivedFunction):
    entries = []
    for expression, _ in function.outputs.values():
        entries.extend(expression if isinstance(expression, sm.MatrixBase) else [expression])
    return sm.cse(entries, symbols=sm.numbered_symbols("x"), order="canonical")


def _output_shape(expression) -> tuple[int, ...]:
    """() for a scalar, (n,) for a column vector, (rows, columns) for a matrix."""
    if not isinstance(expression, sm.MatrixBase):
        return ()
    rows, columns = expression.shape
    return (rows,) if columns == 1 else (rows, columns)


def _returned(function: DerivedFunction) -> str:
    """Every function returns a tuple of its outputs, also when there is only one."""
    names = tuple(function.outputs)
    return f"({names[0]},)" if len(names) == 1 else ", ".join(names)


def _index(shape: tuple[int, ...], k: int) -> str:
    """NumPy index of the k-th entry (row-major) of an output of the given trailing shape."""
    if not shape:
        return "..."
    if len(shape) == 1:
        return f"..., {k}"
    return f"..., {k // shape[1]}, {k % shape[1]}"


def _numpy_function(function: DerivedFunction, parameters: tuple[str, ...], printer) -> list[str]:
    arguments = (*parameters, *function.variables)
    replacements, reduced = _function_cse(function)
    lines = [f"def {function.name}({', '.join(arguments)}):",
             f'    """{function.summary}',
             "",
             "    Arguments are arrays broadcast against each other. Returns a tuple of, with",
             "    shape broadcast_shape + the shape given:",
             ""]
    for name, (expression, description) in function.outputs.items():
        lines.append(f"    {name} {_output_shape(expression)}: {description}")
    lines += ['    """',
              f"    {', '.join(arguments)}, = numpy.broadcast_arrays("
              + ", ".join(f"numpy.asarray({name}, dtype=float)" for name in arguments) + ")",
              f"    shape = {arguments[0]}.shape"]
    for symbol, expression in replacements:
        lines.append(f"    {symbol} = {printer.doprint(expression)}")
    position = 0
    for name, (expression, _) in function.outputs.items():
        shape = _output_shape(expression)
        lines.append(f"    {name} = numpy.zeros(shape + {shape!r})" if shape else f"    {name} = numpy.zeros(shape)")
        size = 1 if not shape else int(sm.prod(shape))
        for k in range(size):
            value = reduced[position + k]
            if value != 0:
                lines.append(f"    {name}[{_index(shape, k)}] = {printer.doprint(value)}")
        position += size
    lines.append(f"    return {_returned(function)}")
    return lines


def _functions_preamble(model: DerivedFunctions, backend: str, module: str, source_hash: str) -> list[str]:
    """Header, import and the PARAMETERS, VARIABLES and OUTPUTS tables of a functions module."""
    return [_functions_header(model, backend, source_hash), f"import {module}", "",
            f"PARAMETERS = {model.parameters!r}",
            "VARIABLES = {" + ", ".join(f"{f.name!r}: {f.variables!r}" for f in model.functions) + "}",
            "OUTPUTS = {" + ", ".join(f"{f.name!r}: {tuple(f.outputs)!r}" for f in model.functions) + "}"]


def emit_numpy_functions(model: DerivedFunctions, source_hash: str) -> str:
    """Module text with one broadcasting NumPy function per entry of ``model.functions``."""
    printer = _NumPyPrinter()
    lines = _functions_preamble(model, "NumPy", "numpy", source_hash)
    for function in model.functions:
        lines += ["", "", *_numpy_function(function, model.parameters, printer)]
    return "\n".join(lines) + "\n"


def _casadi_function(function: DerivedFunction, parameters: tuple[str, ...], printer) -> list[str]:
    replacements, reduced = _function_cse(function)
    lines = [f"def {function.name}(p, variables):",
             f'    """{function.summary}',
             "",
             "    p: the parameters (order PARAMETERS); variables: "
             + ", ".join(function.variables) + ".",
             "    Returns a tuple of CasADi expressions:",
             ""]
    for name, (expression, description) in function.outputs.items():
        lines.append(f"    {name} {_output_shape(expression)}: {description}")
    lines += ['    """',
              f"    {', '.join(parameters)}, = casadi.vertsplit(p)",
              f"    {', '.join(function.variables)}, = casadi.vertsplit(variables)"]
    for symbol, expression in replacements:
        lines.append(f"    {symbol} = {printer.doprint(expression)}")
    position = 0
    for name, (expression, _) in function.outputs.items():
        shape = _output_shape(expression)
        size = 1 if not shape else int(sm.prod(shape))
        cells = [printer.doprint(reduced[position + k]) for k in range(size)]
        if not shape:
            lines.append(f"    {name} = {cells[0]}")
        elif len(shape) == 1:
            lines.append(f"    {name} = casadi.vertcat({', '.join(cells)})")
        else:
            rows, columns = shape
            body = ", ".join("[" + ", ".join(cells[r * columns:(r + 1) * columns]) + "]" for r in range(rows))
            lines.append(f"    {name} = casadi.blockcat([{body}])")
        position += size
    lines.append(f"    return {_returned(function)}")
    return lines


def emit_casadi_functions(model: DerivedFunctions, source_hash: str) -> str:
    """Module text with one CasADi function per entry of ``model.functions``, and ``function(name)``."""
    printer = _CasadiPrinter()
    lines = _functions_preamble(model, "CasADi", "casadi", source_hash)
    for function in model.functions:
        lines += ["", "", *_casadi_function(function, model.parameters, printer)]
    lines += ["", "",
              "def function(name, symbol_type=casadi.SX):",
              '    """casadi.Function (p, variables) -> OUTPUTS[name] of the function called name."""',
              "    p = symbol_type.sym('p', len(PARAMETERS))",
              "    variables = symbol_type.sym('variables', len(VARIABLES[name]))",
              "    outputs = list(globals()[name](p, variables))",
              "    return casadi.Function(name, [p, variables], outputs, ['p', 'variables'], list(OUTPUTS[name]))"]
    return "\n".join(lines) + "\n"
