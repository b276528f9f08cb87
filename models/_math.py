"""Elementary functions that accept numpy arrays, floats or UFL expressions alike.

The same material function then serves the FE forms (UFL), the reduced-order models and the
plots (numpy) without a second copy.
"""

from __future__ import annotations

import numpy as np
import ufl
from ufl.core.expr import Expr


def exp(x):
    return ufl.exp(x) if isinstance(x, Expr) else np.exp(x)


def ln(x):
    return ufl.ln(x) if isinstance(x, Expr) else np.log(x)


def sqrt(x):
    return ufl.sqrt(x) if isinstance(x, Expr) else np.sqrt(x)
