"""The determinism rule, enforced: no module that can reach a trajectory calls libm's or
numpy's CPU-dependent functions (core/fmath.py's docstring says why).

glibc picks an FMA or a non-FMA variant of sin, cos, atan2, exp, log and their kin by
CPU, numpy picks SIMD kernels by CPU, and `np.dot`/`np.matmul`/`np.einsum`/`np.convolve`
sum in a BLAS order that depends on the CPU: one ulp there is a different run on another
machine. `math.hypot`'s extended-precision sum changes between CPython versions (3.12's
uses an FMA). btnav computes these with `btnav.core.fmath` instead. Drawing code never feeds
a trajectory, so `btnav/viz/` may use them. (The `@` operator is not checked: btnav's
own `Pose2D @ Pose2D` composition is the usual meaning, and it cannot be told from
numpy's matmul without running the code.)
"""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "btnav"

#: Functions whose bits depend on the CPU (libm's variants, numpy's SIMD or BLAS).
CPU_DEPENDENT = {
    "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "arcsin", "arccos", "arctan",
    "arctan2", "sinh", "cosh", "tanh", "exp", "exp2", "expm1", "log", "log2", "log10",
    "log1p", "pow", "power", "dot", "matmul", "einsum", "convolve", "inner", "tensordot",
    "vdot", "hypot",
}  # fmt: skip
MODULES = {"math", "np", "numpy"}
#: Code that never reaches a trajectory or a plan: pictures and animations.
ALLOWED = ("viz/",)


def offending_calls(path: Path) -> list[str]:
    """`file:line: module.function` for each call or import of a CPU-dependent function."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and isinstance(node.func.value, ast.Name)
            and node.func.value.id in MODULES
            and node.func.attr in CPU_DEPENDENT
        ):
            found.append(f"{path}:{node.lineno}: {node.func.value.id}.{node.func.attr}")
        elif isinstance(node, ast.ImportFrom) and node.module in ("math", "numpy"):
            names = [a.name for a in node.names if a.name in CPU_DEPENDENT]
            if names:
                found.append(f"{path}:{node.lineno}: from {node.module} import {names}")
    return found


def test_no_closed_loop_module_calls_a_cpu_dependent_function():
    files = [
        f
        for f in sorted(SRC.rglob("*.py"))
        if not f.relative_to(SRC).as_posix().startswith(ALLOWED)
    ]
    assert len(files) > 100  # the tree was found
    offences = [line for f in files for line in offending_calls(f)]
    assert not offences, "use btnav.core.fmath instead:\n" + "\n".join(offences)


def test_the_rule_sees_calls_and_imports(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text("import math\nfrom numpy import sin\nx = math.atan2(1.0, 2.0)\n")
    assert [line.split(": ", 1)[1] for line in offending_calls(bad)] == [
        "from numpy import ['sin']",
        "math.atan2",
    ]
