"""Writes the CalculiX deck of a 3D solid for issue 35's 3D example: a block
1 m x 0.1 m x 0.1 m (x along, y and z across), steel (E = 200 GPa, nu = 0.3,
rho = 7800 kg/m3), meshed as `along` x `across` x `across` eight-node bricks (C3D8),
every DOF of the face x = 0 fixed (*BOUNDARY). Nodes are numbered x slowest, then y, then
z: node (i, j, k) is 1 + k + (across + 1) (j + (across + 1) i). The contact node is the
centre of the free end face (x = 1 m, y = z = 0.05 m; `across` even), printed by
`python3 make_deck.py ALONG ACROSS --contact`.

The step `*FREQUENCY, SOLVER=MATRIXSTORAGE` (no data line) makes ccx write JOB.sti
(stiffness), JOB.mas (mass) and JOB.dof (row labels) and stop. Free DOFs:
3 along (across + 1)^2 (20 x 4: 1,500; 40 x 8: 9,720; 80 x 12: 40,560; 100 x 12: 50,700).

Usage: python3 make_deck.py ALONG ACROSS > JOB.inp; then ccx -i JOB (see README.md).
"""

import sys

LENGTH, SIDE = 1.0, 0.1
E, NU, RHO = 200e9, 0.3, 7800.0


def node(i, j, k, across):
    return 1 + k + (across + 1) * (j + (across + 1) * i)


def contact_node(along, across):
    if across % 2:
        raise SystemExit("ACROSS must be even: the contact node is the end face's centre")
    return node(along, across // 2, across // 2, across)


def deck(along, across):
    contact_node(along, across)
    lines = [
        "*HEADING",
        f"A 1 m x 0.1 m x 0.1 m steel block, {along} x {across} x {across} C3D8, clamped at x = 0",
        "*NODE, NSET=NALL",
    ]
    for i in range(along + 1):
        for j in range(across + 1):
            for k in range(across + 1):
                x, y, z = LENGTH * i / along, SIDE * j / across, SIDE * k / across
                lines.append(f"{node(i, j, k, across)}, {x!r}, {y!r}, {z!r}")
    lines.append("*ELEMENT, TYPE=C3D8, ELSET=EALL")
    element = 0
    for i in range(along):
        for j in range(across):
            for k in range(across):
                # CalculiX's C3D8 order: the face z = z_k counter-clockwise seen from +z,
                # then the face z = z_(k+1) in the same order (a positive Jacobian).
                corners = [
                    (i, j, k), (i + 1, j, k), (i + 1, j + 1, k), (i, j + 1, k),
                    (i, j, k + 1), (i + 1, j, k + 1), (i + 1, j + 1, k + 1), (i, j + 1, k + 1),
                ]
                element += 1
                lines.append(f"{element}, " + ", ".join(str(node(*c, across)) for c in corners))
    lines.append("*BOUNDARY")
    for j in range(across + 1):
        for k in range(across + 1):
            lines.append(f"{node(0, j, k, across)}, 1, 3")
    lines += [
        "*MATERIAL, NAME=STEEL",
        "*ELASTIC",
        f"{E!r}, {NU!r}",
        "*DENSITY",
        f"{RHO!r}",
        "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL",
        "*STEP",
        "*FREQUENCY, SOLVER=MATRIXSTORAGE",
        "*END STEP",
    ]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    along, across = int(sys.argv[1]), int(sys.argv[2])
    if sys.argv[3:] == ["--contact"]:
        print(contact_node(along, across))
    else:
        sys.stdout.write(deck(along, across))
