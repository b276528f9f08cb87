"""Small arithmetic expressions of the reference coordinates x, y, z [mm] in a case file (an LCE
region's ``director_expression`` of ``lcefem run body``), read as data: never eval, exec or import.

The text is parsed by :func:`ast.parse` (mode "eval") and every node of the tree is checked against
an allow-list before anything is built from it:

* numbers (int or float literals), the names ``x``, ``y``, ``z`` (reference coordinates [mm]) and
  ``pi``;
* binary ``+ - * / **``, unary ``-`` and ``+``;
* calls of ``sin cos tan exp sqrt`` (one argument) and ``atan2`` (two: atan2(y, x)), by name only.

Anything else (attributes, subscripts, other names, keywords, comparisons, lambdas, strings, ...)
is refused with one line naming what is allowed. :func:`check_expression` does that at load time
(before any mesh is built); :func:`to_ufl` turns the checked tree into a UFL expression of a
:class:`ufl.SpatialCoordinate`, and :func:`to_numpy` into an array over points (the tests' and the
zero-length check's evaluation).
"""

from __future__ import annotations

import ast
import math

#: one-argument functions and atan2, the names allowed
FUNCTIONS = ("sin", "cos", "tan", "exp", "sqrt", "atan2")
NAMES = ("x", "y", "z", "pi")
ALLOWED = "numbers, x, y, z [mm], pi, + - * / **, unary -, " + " ".join(FUNCTIONS)
#: a case file's expression is short; a longer text is refused before parsing
MAX_LENGTH = 500
_BINOPS = (ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow)
_UNARY = (ast.USub, ast.UAdd)


class ExpressionError(ValueError):
    """An expression outside the allow-list: the message says what and what is allowed."""


def check_expression(text: str) -> ast.Expression:
    """The checked syntax tree of ``text`` (module docstring); :class:`ExpressionError`
    otherwise."""
    if not isinstance(text, str) or not text.strip():
        raise ExpressionError(f"{text!r}: allowed a non-empty string of {ALLOWED}")
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"{len(text)} characters: allowed at most {MAX_LENGTH}")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError, RecursionError, MemoryError) as exc:
        raise ExpressionError(
            f"{text!r}: not an expression ({type(exc).__name__}); allowed {ALLOWED}"
        ) from None
    try:
        _check(tree.body, text)
    except RecursionError:
        raise ExpressionError(f"{text!r}: nested too deeply") from None
    return tree


def _check(node: ast.AST, text: str) -> None:
    def refuse(what: str):
        raise ExpressionError(f"{text!r}: {what} is not allowed; allowed {ALLOWED}")

    if isinstance(node, ast.Constant):
        if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
            refuse(f"the constant {node.value!r}")
        return
    if isinstance(node, ast.Name):
        if node.id not in NAMES:
            refuse(f"the name {node.id!r}")
        return
    if isinstance(node, ast.BinOp):
        if not isinstance(node.op, _BINOPS):
            refuse(f"the operator {type(node.op).__name__}")
        _check(node.left, text)
        _check(node.right, text)
        return
    if isinstance(node, ast.UnaryOp):
        if not isinstance(node.op, _UNARY):
            refuse(f"the operator {type(node.op).__name__}")
        _check(node.operand, text)
        return
    if isinstance(node, ast.Call):
        if not isinstance(node.func, ast.Name) or node.func.id not in FUNCTIONS:
            if isinstance(node.func, ast.Attribute):
                refuse(f"calling the attribute .{node.func.attr}")
            refuse(
                "calling "
                + (
                    repr(node.func.id)
                    if isinstance(node.func, ast.Name)
                    else f"a {type(node.func).__name__}"
                )
            )
        if node.keywords:
            refuse("a keyword argument")
        wanted = 2 if node.func.id == "atan2" else 1
        if len(node.args) != wanted:
            raise ExpressionError(
                f"{text!r}: {node.func.id} takes {wanted} argument(s), got {len(node.args)}"
            )
        for arg in node.args:
            if isinstance(arg, ast.Starred):
                refuse("a starred argument")
            _check(arg, text)
        return
    refuse(f"a {type(node).__name__}")


def _build(node: ast.AST, names: dict, functions: dict, power, number=float):
    """The value of a checked tree with ``names`` {x, y, z, pi}, ``functions``, ``power`` and
    ``number`` (a literal's type) of a backend."""
    if isinstance(node, ast.Constant):
        return number(node.value)
    if isinstance(node, ast.Name):
        return names[node.id]
    if isinstance(node, ast.UnaryOp):
        v = _build(node.operand, names, functions, power, number)
        return -v if isinstance(node.op, ast.USub) else v
    if isinstance(node, ast.BinOp):
        a = _build(node.left, names, functions, power, number)
        b = _build(node.right, names, functions, power, number)
        op = node.op
        if isinstance(op, ast.Add):
            return a + b
        if isinstance(op, ast.Sub):
            return a - b
        if isinstance(op, ast.Mult):
            return a * b
        if isinstance(op, ast.Div):
            return a / b
        return power(a, b)
    args = [_build(a, names, functions, power, number) for a in node.args]
    return functions[node.func.id](*args)


def to_ufl(tree: ast.Expression, x):
    """The checked ``tree`` as a UFL expression of the spatial coordinate ``x`` (x[0], x[1], x[2]
    [mm]). Constant sub-expressions are folded in double precision (ExpressionError when they
    overflow or divide by zero)."""
    import ufl

    def fn(name):
        def call(*args):
            if all(isinstance(a, float) for a in args):  # fold: math keeps it a plain number
                return getattr(math, name)(*args)
            return getattr(ufl, name)(*args)

        return call

    functions = {name: fn(name) for name in FUNCTIONS}
    names = {"x": x[0], "y": x[1], "z": x[2], "pi": math.pi}
    try:
        return _build(tree.body, names, functions, lambda a, b: a**b)
    except (OverflowError, ZeroDivisionError, ValueError) as exc:
        raise ExpressionError(f"{ast.unparse(tree)!r}: {exc}") from None


def to_numpy(tree: ast.Expression, points):
    """The checked ``tree`` at ``points`` (n, 3) [mm]: an array (n,) (a constant is broadcast);
    NaN or inf where it is undefined (numpy's rules, warnings silenced)."""
    import numpy as np

    points = np.asarray(points, dtype=float)
    functions = {name: getattr(np, name) for name in FUNCTIONS if name != "atan2"}
    functions["atan2"] = np.arctan2
    names = {"x": points[:, 0], "y": points[:, 1], "z": points[:, 2], "pi": np.float64(math.pi)}
    with np.errstate(all="ignore"):
        value = _build(tree.body, names, functions, np.power, np.float64)
        return np.broadcast_to(np.asarray(value, dtype=float), (points.shape[0],)).copy()
