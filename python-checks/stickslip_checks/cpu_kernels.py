"""Which CPU-dependent kernels this process runs, as the bits they give: a float64 sum, a
matrix product (OpenBLAS), numpy's tanh and exp, the C library's exp and tanh, and
onnxruntime's float64 and float32 matrix products with tanh. Each line is a short hash
of the results on fixed pseudo-random inputs, so two runs under different CPU settings
(scripts/second-cpu.sh) show which kernels changed: a line that differs ran other code.

Usage: python -m stickslip_checks.cpu_kernels [--json OUT.json]
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import sys
from pathlib import Path

import numpy as np


def _digest(values) -> str:
    return hashlib.sha256(np.ascontiguousarray(values, dtype=np.float64).tobytes()).hexdigest()[:12]


def _onnxruntime(rng: np.random.Generator) -> dict[str, str]:
    """A 2-100-100-1 tanh network in float64 and float32 on 5000 points."""
    import onnxruntime
    from onnx import TensorProto, helper, numpy_helper

    shapes = {"W1": (2, 100), "W2": (100, 100), "W3": (100, 1)}
    weights = {name: rng.standard_normal(shape) for name, shape in shapes.items()}
    points = rng.standard_normal((5000, 2))
    nodes = [helper.make_node("MatMul", ["x", "W1"], ["a"]), helper.make_node("Tanh", ["a"], ["b"]),
             helper.make_node("MatMul", ["b", "W2"], ["c"]), helper.make_node("Tanh", ["c"], ["d"]),
             helper.make_node("MatMul", ["d", "W3"], ["y"])]
    out = {}
    for dtype, elem in ((np.float64, TensorProto.DOUBLE), (np.float32, TensorProto.FLOAT)):
        inits = [numpy_helper.from_array(w.astype(dtype), name) for name, w in weights.items()]
        graph = helper.make_graph(nodes, "kernels", [helper.make_tensor_value_info("x", elem, ["n", 2])],
                                  [helper.make_tensor_value_info("y", elem, ["n", 1])], inits)
        model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)])
        model.ir_version = 8
        session = onnxruntime.InferenceSession(model.SerializeToString(),
                                               providers=["CPUExecutionProvider"])
        result = session.run(None, {"x": points.astype(dtype)})[0]
        out[f"onnxruntime {np.dtype(dtype).name} MLP"] = _digest(result)
    return out


def fingerprints() -> dict[str, str]:
    """Kernel name -> hash of its results on this process's CPU settings."""
    rng = np.random.default_rng(33)
    x = rng.standard_normal(100_003)
    a, b = rng.standard_normal((300, 200)), rng.standard_normal((200, 1500))
    v = rng.uniform(-5.0, 5.0, 100_000)
    few = v[:20_000].tolist()
    out = {
        "numpy sum (pairwise)": _digest(np.sum(x)),
        "numpy matmul (OpenBLAS dgemm)": _digest(a @ b),
        "numpy dot (OpenBLAS ddot)": _digest(np.dot(x, x)),
        "numpy tanh": _digest(np.tanh(v)),
        "numpy exp": _digest(np.exp(v)),
        "numpy sin": _digest(np.sin(v)),
        "C library exp (math.exp)": _digest([math.exp(t) for t in few]),
        "C library tanh (math.tanh)": _digest([math.tanh(t) for t in few]),
    }
    out.update(_onnxruntime(rng))
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m stickslip_checks.cpu_kernels",
                                     description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--json", type=Path, default=None, help="also write them here")
    args = parser.parse_args(argv)
    result = fingerprints()
    width = max(map(len, result))
    for name, digest in result.items():
        print(f"{name:{width}}  {digest}")
    if args.json:
        args.json.write_text(json.dumps(result, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
