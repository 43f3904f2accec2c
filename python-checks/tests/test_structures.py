"""The CalculiX paper beam's frequencies by scipy (issue 35: the structure's modes checked
against scipy's eigsh).

tests/physics/calculix_beam.rs holds scipy's f1..f3 of the committed CalculiX matrices
(examples/calculix-beam/beam.sti, .mas, .dof) and checks the Rust reader and shift-invert
Lanczos against them within 1e-6 (the spread of independent solvers on this K, whose
condition number is near 7e10). This test recomputes those numbers with scipy from the
same files, so that the constants in the Rust test stay scipy's: within 1e-8 relative,
ten times the spread of ARPACK's random start vector on this K (measured over 30 runs:
3.9e-11, 1.1e-9, 6.3e-10 on f1, f2, f3), far below the Rust test's 1e-6.
"""

import pathlib
import re

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "calculix-beam"


# How closely scipy's eigsh reproduces the constants the Rust tests hold for the paper
# beam's frequencies, on any CPU. Its K has a condition number near 7e10, so a
# backward-stable factorisation perturbs omega_1^2 by up to eps cond(K) ~ 1e-5; SuperLU and
# BLAS sum in an order that depends on the CPU's vector units. Measured: ARPACK's random
# start moves f1 by 4e-10 on one CPU, an AVX-512 machine gives f1 2.0e-7 away from the
# constants (computed on an AVX2 one). 1e-6 is the Rust tests' own tolerance against the
# constants: within it, they stay scipy's to what those tests resolve.
SCIPY_ON_THIS_K = 1e-6


def calculix_matrix(path, rows):
    """A ccx .sti/.mas file (1-based `i j value`, upper triangle) as a full CSC matrix."""
    data = np.loadtxt(path)
    i = data[:, 0].astype(int) - 1
    j = data[:, 1].astype(int) - 1
    assert np.all(i <= j), "CalculiX writes the upper triangle"
    upper = sp.coo_matrix((data[:, 2], (i, j)), shape=(rows, rows)).tocsc()
    return upper + sp.triu(upper, 1).T


def test_the_rust_tests_scipy_frequencies_are_scipys():
    rows = len((EXAMPLE / "beam.dof").read_text().split())
    k = calculix_matrix(EXAMPLE / "beam.sti", rows)
    m = calculix_matrix(EXAMPLE / "beam.mas", rows)
    omega2 = np.sort(sla.eigsh(k, 3, m, sigma=0, which="LM", return_eigenvectors=False))
    frequencies = np.sqrt(omega2) / (2 * np.pi)
    rust = (ROOT / "tests" / "physics" / "calculix_beam.rs").read_text()
    held = re.search(r"let eigsh = \[([^\]]*)\]", rust)
    assert held, "tests/physics/calculix_beam.rs no longer holds `let eigsh = [...]`"
    constants = [float(x) for x in held.group(1).split(",")]
    print("scipy eigsh f1..f3 (Hz):", [f"{f:.10e}" for f in frequencies])
    np.testing.assert_allclose(frequencies, constants, rtol=SCIPY_ON_THIS_K)


def test_the_reduced_structures_scipy_frequencies_are_scipys():
    """tests/physics/structure_modal.rs holds scipy's 20 lowest frequencies of the same
    files and checks the modal fidelity's reduced model against them (1e-6); they must
    stay scipy's, to SCIPY_ON_THIS_K."""
    rows = len((EXAMPLE / "beam.dof").read_text().split())
    k = calculix_matrix(EXAMPLE / "beam.sti", rows)
    m = calculix_matrix(EXAMPLE / "beam.mas", rows)
    omega2 = np.sort(sla.eigsh(k, 20, m, sigma=0, which="LM", return_eigenvectors=False))
    frequencies = np.sqrt(omega2) / (2 * np.pi)
    rust = (ROOT / "tests" / "physics" / "structure_modal.rs").read_text()
    held = re.search(r"let eigsh_20 = \[([^\]]*)\]", rust)
    assert held, "tests/physics/structure_modal.rs no longer holds `let eigsh_20 = [...]`"
    constants = [float(x) for x in held.group(1).split(",") if x.strip()]
    assert len(constants) == 20
    np.testing.assert_allclose(frequencies, constants, rtol=SCIPY_ON_THIS_K)


BLOCK = ROOT / "examples" / "calculix-block"


def test_the_block_tests_scipy_frequencies_are_scipys():
    """The 3D block (examples/calculix-block, 1,500 DOFs of C3D8): scipy's six lowest
    frequencies against the constants tests/physics/calculix_block.rs checks the sparse
    factorisation's Lanczos against. Its modes come in pairs (the square section bends
    alike in y and z) that the files split by 1e-11; eigsh finds both of each pair. The
    tolerance 1e-9 is the Rust test's: scipy's dense eigh moves f1 by 3.1e-11 from eigsh
    (and gives the pairs equal), ARPACK's random start moves it by about 1e-13."""
    rows = len((BLOCK / "block.dof").read_text().split())
    k = calculix_matrix(BLOCK / "block.sti", rows)
    m = calculix_matrix(BLOCK / "block.mas", rows)
    omega2 = np.sort(sla.eigsh(k, 6, m, sigma=0, which="LM", return_eigenvectors=False))
    frequencies = np.sqrt(omega2) / (2 * np.pi)
    rust = (ROOT / "tests" / "physics" / "calculix_block.rs").read_text()
    held = re.search(r"let eigsh = \[([^\]]*)\]", rust)
    assert held, "tests/physics/calculix_block.rs no longer holds `let eigsh = [...]`"
    constants = [float(x) for x in held.group(1).split(",") if x.strip()]
    print("scipy eigsh f1..f6 (Hz):", [f"{f:.12e}" for f in frequencies])
    np.testing.assert_allclose(frequencies, constants, rtol=1e-9)
