"""A MATLAB fitrnet network (.mat) as an ONNX file that the FMUs and `stickslip` read.

Reads the RegressionNeuralNetwork in MODEL.mat (with the pip package mat-io), checks
that it is a network our law computes exactly (standardised or raw inputs, hidden
activations all tanh, relu or sigmoid, a linear output, one output, the identity
response transform; anything else is refused naming it), and writes it as float64
ONNX with our metadata: each predictor's role, unit and training range (from its name,
Fn/F_n/normal_force and vs/v/v_s/sliding_velocity, and the stored training inputs, or
from --feature), the target and the variant.

With --weights-out it then runs `stickslip import-network` on the ONNX file (the
binary: $STICKSLIP_BIN, else cargo's release build) and writes our weights JSON.

Example (the paper authors' network):
  python -m stickslip_checks.import_fitrnet \\
      data/paper-authors/trained_regression_nn_friction_model.mat \\
      --out authors.onnx --weights-out authors.json
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

from . import fitrnet


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m stickslip_checks.import_fitrnet",
                                description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("model", type=Path, metavar="MODEL.mat")
    p.add_argument("--out", type=Path, required=True, metavar="MODEL.onnx",
                   help="the ONNX file to write")
    p.add_argument("--feature", action="append", default=[], type=fitrnet.parse_feature,
                   metavar="NAME:ROLE:UNIT:MIN:MAX",
                   help="describe the predictor NAME (as `stickslip import-network "
                        "--feature`; ROLE sliding_velocity, normal_force or other; UNIT may "
                        "be empty); replaces what its name and the training data say. "
                        "Required for a predictor whose name has no known role")
    p.add_argument("--target-unit", default="N",
                   help="unit of the response (default N)")
    p.add_argument("--variant", choices=("plain", "signed"), default="plain",
                   help="plain: the network maps the signed velocity to the signed force "
                        "(default); signed: it maps |v| to the force's magnitude")
    p.add_argument("--variable", help="the .mat variable holding the network (default: the "
                                      "only fitrnet object in the file)")
    p.add_argument("--weights-out", type=Path, metavar="WEIGHTS.json",
                   help="also run `stickslip import-network` on the ONNX file and write our "
                        "weights file")
    return p


def write_atomically(model, out: Path) -> None:
    """Writes the ONNX model to `out` whole or not at all: into a temporary file beside
    it, renamed into place once written (as the Rust side's outputs are), so that an
    interrupted or failed write never leaves a truncated file under the name."""
    import os
    import tempfile

    import onnx

    handle, staged = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".tmp",
                                      dir=out.parent if str(out.parent) else ".")
    os.close(handle)
    try:
        onnx.save(model, staged)
        os.replace(staged, out)
    except BaseException:
        Path(staged).unlink(missing_ok=True)
        raise


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        network = fitrnet.read_fitrnet(args.model, args.variable)
        features = network.features(args.feature)
        low, high = network.response_range or (0.0, 0.0)
        target = {"name": network.response, "unit": args.target_unit, "min": low, "max": high}
        model = fitrnet.to_onnx(network, features, args.variant, target)
    except (fitrnet.FitrnetError, OSError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    try:
        write_atomically(model, args.out)
    except OSError as error:
        print(f"error: {args.out}: cannot be written: {error}", file=sys.stderr)
        return 1
    sizes = [network.weights[0].shape[1], *(w.shape[0] for w in network.weights)]
    print(f"read {args.model}: fitrnet {'-'.join(map(str, sizes))} {network.activation}, "
          f"inputs {'standardised' if network.standardised else 'raw'}, "
          f"response {network.response}")
    for f in features:
        print(f"  {f.name}: {f.role} [{f.unit}] {f.min:.6g} .. {f.max:.6g}")
    print(f"wrote {args.out}")
    if args.weights_out is None:
        return 0
    from .artifacts import find_binary

    run = subprocess.run([str(find_binary()), "import-network", str(args.out),
                          "--out", str(args.weights_out)], check=False)
    return run.returncode


if __name__ == "__main__":
    sys.exit(main())
