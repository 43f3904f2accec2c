"""Writes the CalculiX deck of the paper beam (2 m x 0.01 m, 1 m wide, steel-like:
E = 200 GPa, nu = 0.3, rho = 1000 kg/m3) meshed as stickslip's built-in plane-stress
model meshes it (stickslip::mesh::StripMesh): `along` x `through` eight-node quadrilaterals,
nodes column by column along x without the element centres, CalculiX node k = StripMesh
node k - 1. The clamp is the scene's default `neutral-axis` one: u_x = 0 on the end face
x = 0, u_y = 0 at its middle node.

CalculiX's CPS8 is not 2D plane stress (ccx expands it into a 3D slab whose out-of-plane
motion is free), so the deck uses CPE8 (plane strain) with the constants that turn the
plane-strain law into the plane-stress one exactly:
    E* = E (1 + 2 nu) / (1 + nu)^2,   nu* = nu / (1 + nu).
The step `*FREQUENCY, SOLVER=MATRIXSTORAGE` (no data line) makes ccx write JOB.sti
(stiffness), JOB.mas (mass) and JOB.dof (row labels) and stop.

Usage: python3 make_deck.py ALONG THROUGH > JOB.inp; then ccx -i JOB (see README.md).
"""

import sys

LENGTH, HEIGHT, WIDTH = 2.0, 0.01, 1.0
E, NU, RHO = 200e9, 0.3, 1000.0


def deck(along, through):
    gx, gy = 2 * along + 1, 2 * through + 1
    number = {}
    nodes = []
    for i in range(gx):
        for j in range(gy):
            if i % 2 == 1 and j % 2 == 1:
                continue  # no node at an element centre (serendipity Q8)
            number[(i, j)] = len(nodes) + 1
            nodes.append((LENGTH * i / (gx - 1), HEIGHT * j / (gy - 1)))
    lines = [
        "*HEADING",
        f"The paper beam, {along} x {through} CPE8, plane-stress equivalent constants",
        "*NODE, NSET=NALL",
    ]
    lines += [f"{k + 1}, {x!r}, {y!r}" for k, (x, y) in enumerate(nodes)]
    lines.append("*ELEMENT, TYPE=CPE8, ELSET=EALL")
    element = 0
    for ex in range(along):
        for ey in range(through):
            i, j = 2 * ex, 2 * ey
            corners_then_midsides = [
                (i, j), (i + 2, j), (i + 2, j + 2), (i, j + 2),
                (i + 1, j), (i + 2, j + 1), (i + 1, j + 2), (i, j + 1),
            ]
            element += 1
            lines.append(f"{element}, " + ", ".join(str(number[p]) for p in corners_then_midsides))
    lines.append("*BOUNDARY")
    lines += [f"{number[(0, j)]}, 1, 1" for j in range(gy)]
    lines.append(f"{number[(0, through)]}, 2, 2")
    lines += [
        "*MATERIAL, NAME=PLANE_STRESS_EQUIVALENT",
        "*ELASTIC",
        f"{E * (1 + 2 * NU) / (1 + NU) ** 2!r}, {NU / (1 + NU)!r}",
        "*DENSITY",
        f"{RHO!r}",
        "*SOLID SECTION, ELSET=EALL, MATERIAL=PLANE_STRESS_EQUIVALENT",
        f"{WIDTH!r}",
        "*STEP",
        "*FREQUENCY, SOLVER=MATRIXSTORAGE",
        "*END STEP",
    ]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    sys.stdout.write(deck(int(sys.argv[1]), int(sys.argv[2])))
