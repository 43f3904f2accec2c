"""StickSlipBeam's outputs of the friction law's state (bristle_deflection, state_theta,
state_psi) under fmpy: FMI 2.0 and 3.0 give the same values bit for bit, the run's law
fills its own and leaves the others 0, and `stickslip simulate --out` writes the same
values in its state column.

Needs the FMUs built by `cargo run --release -p fmu-build` and the `stickslip` binary.
"""

from __future__ import annotations

import subprocess

import numpy as np
import pytest
from fmpy import simulate_fmu

from stickslip_checks.artifacts import BEAM, Model, find_binary

STOP = 0.8  # s: past the breakaway at about 0.4 s, so the state both loads and slips
STATE = ("bristle_deflection", "state_theta", "state_psi")
OWN = {"lugre": "bristle_deflection", "rate-and-state": "state_theta"}


@pytest.mark.parametrize("law", sorted(OWN))
def test_state_outputs_in_both_versions_and_the_command_line(fmu_versions, law, tmp_path):
    paths = fmu_versions
    model = Model.read(paths["2.0"][BEAM])
    start = {
        "fidelity.level": model.code("fidelity.level", "modal"),
        "friction.law": model.code("friction.law", law),
    }
    r2, r3 = (
        simulate_fmu(str(paths[v][BEAM]), stop_time=STOP, output_interval=1e-3,
                     start_values=start, output=list(STATE))
        for v in ("2.0", "3.0")
    )
    for name in STATE:
        assert np.array_equal(r2[name], r3[name]), name
        if name != OWN[law]:
            assert not r2[name].any(), name
    own = r2[OWN[law]]
    assert np.ptp(own) > 0.0

    csv_path = tmp_path / f"{law}.csv"
    subprocess.run(
        [str(find_binary()), "simulate", "--fidelity", "modal", "--friction", law,
         "--t-end", str(STOP), "--every", "10", "--out", str(csv_path)],
        check=True, capture_output=True, text=True,
    )
    cli = np.genfromtxt(csv_path, delimiter=",", names=True)
    assert cli.dtype.names[-1] == OWN[law]
    assert not set(STATE) - {OWN[law]} & set(cli.dtype.names)
    # The same 1 ms grid (0.1 ms steps, every 10th written), and the CSV's 11 significant
    # digits (`{:.10e}`: rounding up to 5e-11 of the value; measured 4.5e-11): equal to
    # 1e-10 of the value (plus 1e-300 for exact zeros).
    assert len(cli) == len(r2)
    np.testing.assert_allclose(r2["time"], cli["t"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(own, cli[OWN[law]], rtol=1e-10, atol=1e-300)
