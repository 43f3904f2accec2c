"""The paper scene through the FMUs with fmpy: validation, every structural fidelity with
both friction laws, embedded and coupled (see scene). Prints the validation problems,
the run table, the major slips, the friction laws and the coupling error; writes
fmu_validation.csv, fmu_slips.csv and three figures to OUT_DIR.

Usage: python -m stickslip_checks.fmu_scene [OUT_DIR]   (or stickslip-fmu-scene;
default <repo>/out). Exits 2 if the FMUs are missing; the checks are pytest's.
"""

from __future__ import annotations

import sys
import time

from . import scene
from .artifacts import Fmus
from .runner import find_fmus, parser


def main(argv: list[str] | None = None) -> int:
    out = parser("stickslip-fmu-scene", __doc__).parse_args(argv).out
    began = time.perf_counter()
    paths = find_fmus("fmu_scene")
    if paths is None:
        return 2
    out.mkdir(parents=True, exist_ok=True)
    print(f"FMUs: {', '.join(str(p) for p in paths.values())}")
    print("== fmpy.validation.validate_fmu")
    for name, problems in scene.validate(paths).items():
        print(f"  {name}.fmu: {len(problems)} problem(s)")
        for p in problems:
            print(f"    {p}")

    fmus = Fmus(paths)
    try:
        result = scene.run_scene(fmus)
    finally:
        fmus.close()
    print()
    print("== Paper scene through the FMUs (0 .. 1.2 s, 1 ms output)")
    print(scene.table(result.runs))
    print()
    print(f"== Major slips, {scene.PLOT_FIDELITY} fidelity (the paper's mesh), both laws")
    print(scene.slips_text(result.runs, scene.PLOT_FIDELITY))
    print()
    normal_force = result.friction.real_start("normal_force")
    print(f"== NeuralFriction.fmu, friction force at F_n = {normal_force:g} N, -0.35 .. 0.35 m/s")
    print("\n".join(scene.law_lines(result)))
    print()
    print(
        "== Coupling error: coupled (Gauss-Seidel, 1 ms) minus embedded run, same law and "
        "fidelity"
    )
    print("\n".join(scene.coupling_lines(result.runs)))
    written = scene.write_outputs(result, out)
    print()
    for p in written:
        print(f"wrote {p}")
    print(f"total wall time {time.perf_counter() - began:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
