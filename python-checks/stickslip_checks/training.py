"""The network: retraining with `stickslip train` (paper Sec. 3), NeuralFriction.fmu on
the test set and the scikit-learn peer on the same split (see retraining). Prints the
trainer's report, whether the weights equal the shipped ones, the FMU's test MSE against
the trainer's and both fits side by side; writes OUT_DIR/training/ (the trainer's
outputs), sklearn_peer.json and three figures.

Usage: python -m stickslip_checks.training [OUT_DIR]   (or stickslip-training; default
<repo>/out). Exits 2 if the FMUs are missing; the checks are pytest's
(tests/test_training.py).
"""

from __future__ import annotations

import sys

from . import retraining, sklearn_peer
from .artifacts import REPO, SHIPPED_WEIGHTS, Fmus, find_binary
from .runner import find_fmus, parser


def main(argv: list[str] | None = None) -> int:
    out = parser("stickslip-training", __doc__).parse_args(argv).out
    workdir = out / "training"
    paths = find_fmus("training")
    if paths is None:
        return 2
    binary = find_binary()
    print(f"== stickslip train, the paper's settings -> {workdir}")
    report = retraining.train(binary, workdir)
    print(
        f"  {report['iterations']} iterations in {report['seconds']:.2f} s: MSE test "
        f"{report['mse_test']:.4f} N^2, R2 test {report['r2_test']:.5f} (paper: 4.52, 0.9974)"
    )
    fmus = Fmus(paths)
    try:
        result = retraining.evaluate(fmus, workdir, report)
        print(
            f"  weights equal the shipped {SHIPPED_WEIGHTS.relative_to(REPO)} byte for byte: "
            f"{result.weights_equal}"
        )
        print(
            f"\n== NeuralFriction.fmu on the {len(result.predicted)} test samples "
            f"({result.fmu_seconds:.2f} s): MSE {result.mse:.4f} N^2, R2 {result.r2:.5f}; "
            f"relative difference to the trainer's MSE {result.relative:.1e} "
            f"(must be < {retraining.FMU_AGREEMENT:g})"
        )
        print("\n== scikit-learn peer on the same split")
        peer = retraining.fit_peer(workdir, report)
        print(sklearn_peer.table(peer))
        written = retraining.write_outputs(fmus, result, peer, out)
    finally:
        fmus.close()
    print()
    for p in written:
        print(f"wrote {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
