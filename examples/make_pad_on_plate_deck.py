#!/usr/bin/env python3
"""Writes the pad-on-plate contact decks of tests/data (squeal's deck tests and ccx):

  pad_on_plate_mesh.inp   nodes, C3D10 elements, sets, surfaces, materials, sections
  pad_on_plate.inp        *INCLUDE of the mesh, supports, the interaction, the contact pair,
                          a *STATIC step (pressure on the pad) and a *FREQUENCY perturbation
                          step: what CalculiX runs (ccx -i pad_on_plate)
  pad_on_plate_sliding.inp        the same with friction (mu 0.3) and the plate turning under
                          the pad as a disc would (*MOTION, ROTATION about a z axis 99 mm from
                          the pad's centre): *STATIC, *FREQUENCY and *COMPLEX FREQUENCY steps
                          for squeal run
  pad_on_plate_friction.inp       friction mu 0.3 with CalculiX's stick slope 1e11 Pa/m: the
                          pad pressed (*STATIC), the plate then sliding along y under it
                          (*STATIC with *MOTION, TRANSLATION), 12 modes about that (*FREQUENCY)
  pad_on_plate_friction_ccx.inp   what CalculiX runs for the same: the plate's bottom moved
                          2e-5 m along y in the second step (every point slips), and the
                          frequency step's mu lowered by 1e-6 (*CHANGE FRICTION) so that each
                          point left on the Coulomb cone by the static is evaluated as
                          slipping, not as sticking or slipping by round-off

A steel plate [0, 0.04]^2 x [0, 0.01] (4 x 4 x 1 cubes) clamped at its bottom, and a pad
[0.006, 0.032]^2 x [0.01, 0.015] (3 x 3 x 1 cubes, E = 5 GPa) on it, its top held in x and
y and pressed by 1 MPa; frictionless node-to-surface contact, pad bottom on plate top, with
a linear pressure-overclosure law of slope 1e13 Pa/m. The meshes do not match: no pad node
lies above a plate node. Each cube is split into the six Kuhn tetrahedra.

Usage: python3 examples/make_pad_on_plate_deck.py [folder]   (default tests/data)
"""
import os
import sys

EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]  # C3D10 mid nodes 5..10
FACES = [(0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0)]  # Abaqus S1..S4 corners
PERMS = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]


def kuhn_elements(cells, label, first_element):
    """The C3D10 elements [(label, [10 node labels])] of a grid of `cells`, each cell split
    into the six Kuhn tetrahedra (positively oriented in index space), corners and mid-edge
    nodes named by `label` of their doubled grid index (i, j, k)."""
    elements = []
    e = first_element
    for k in range(cells[2]):
        for j in range(cells[1]):
            for i in range(cells[0]):
                for p in PERMS:
                    v = [[2 * i, 2 * j, 2 * k]]
                    for step in range(3):
                        w = list(v[-1])
                        w[p[step]] += 2
                        v.append(w)
                    d = [[v[a][c] - v[0][c] for c in range(3)] for a in (1, 2, 3)]
                    det = (
                        d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
                        - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
                        + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0])
                    )
                    if det < 0:
                        v[1], v[2] = v[2], v[1]
                    conn = [label(h) for h in v]
                    for a, b in EDGES:
                        conn.append(label([(v[a][c] + v[b][c]) // 2 for c in range(3)]))
                    elements.append((e, conn))
                    e += 1
    return elements


def box(origin, size, cells, first_node, first_element):
    """Nodes {label: (x, y, z)} and elements [(label, [10 node labels])] of a Kuhn-split box."""
    m = [2 * c + 1 for c in cells]

    def label(h):
        return first_node + h[0] + m[0] * (h[1] + m[1] * h[2])

    nodes = {}
    for k in range(m[2]):
        for j in range(m[1]):
            for i in range(m[0]):
                h = (i, j, k)
                nodes[label(h)] = tuple(
                    origin[c] + h[c] * size[c] / (2 * cells[c]) for c in range(3)
                )
    return nodes, kuhn_elements(cells, label, first_element)


def faces_at(nodes, elements, z):
    """(element, 'S#') of every element face whose corners all lie at height z."""
    out = []
    for e, conn in elements:
        for s, face in enumerate(FACES):
            if all(abs(nodes[conn[c]][2] - z) < 1e-12 for c in face):
                out.append((e, f"S{s + 1}"))
    return out


def lines(values, per_line=8):
    values = [str(v) for v in values]
    return "".join(", ".join(values[i : i + per_line]) + "\n" for i in range(0, len(values), per_line))


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "tests/data"
    plate_nodes, plate = box((0.0, 0.0, 0.0), (0.04, 0.04, 0.01), (4, 4, 1), 1, 1)
    pad_nodes, pad = box((0.006, 0.006, 0.01), (0.026, 0.026, 0.005), (3, 3, 1), 1001, 1001)
    mesh = [
        "** Pad on plate, C3D10: written by examples/make_pad_on_plate_deck.py (squeal).\n",
        "*NODE, NSET=NALL\n",
    ]
    for label, x in sorted({**plate_nodes, **pad_nodes}.items()):
        mesh.append(f"{label}, {x[0]:.9f}, {x[1]:.9f}, {x[2]:.9f}\n")
    for name, elements in (("PLATE", plate), ("PAD", pad)):
        mesh.append(f"*ELEMENT, TYPE=C3D10, ELSET={name}\n")
        for e, conn in elements:
            mesh.append(f"{e}, " + ", ".join(map(str, conn)) + "\n")
    mesh.append("*NSET, NSET=PLATEBOTTOM\n")
    mesh.append(lines(sorted(n for n, x in plate_nodes.items() if x[2] == 0.0)))
    mesh.append("*NSET, NSET=PADTOP\n")
    mesh.append(lines(sorted(n for n, x in pad_nodes.items() if abs(x[2] - 0.015) < 1e-12)))
    for name, nodes, elements, z in (
        ("PLATETOP", plate_nodes, plate, 0.01),
        ("PADBOTTOM", pad_nodes, pad, 0.01),
        ("PADTOPFACES", pad_nodes, pad, 0.015),
    ):
        mesh.append(f"*SURFACE, NAME={name}, TYPE=ELEMENT\n")
        mesh.extend(f"{e}, {s}\n" for e, s in faces_at(nodes, elements, z))
    mesh.append(
        "*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n"
        "*MATERIAL, NAME=LINING\n*ELASTIC\n5e9, 0.25\n*DENSITY\n2500.\n"
        "*SOLID SECTION, ELSET=PLATE, MATERIAL=STEEL\n"
        "*SOLID SECTION, ELSET=PAD, MATERIAL=LINING\n"
    )
    deck = (
        "*HEADING\n"
        "Pad on plate, frictionless node-to-surface contact (squeal tests/data)\n"
        "** Written by examples/make_pad_on_plate_deck.py (squeal).\n"
        "*INCLUDE, INPUT=pad_on_plate_mesh.inp\n"
        "*BOUNDARY\nPLATEBOTTOM, 1, 3\nPADTOP, 1, 2\n"
        "*SURFACE INTERACTION, NAME=PADPLATE\n"
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1e13\n"
        "*CONTACT PAIR, INTERACTION=PADPLATE, TYPE=NODE TO SURFACE, SMALL SLIDING\n"
        "PADBOTTOM, PLATETOP\n"
        "*STEP\n*STATIC\n*DSLOAD\nPADTOPFACES, P, 1e6\n*END STEP\n"
        "*STEP, PERTURBATION\n*FREQUENCY\n12\n*NODE FILE\nU\n*END STEP\n"
    )
    head = (
        "*INCLUDE, INPUT=pad_on_plate_mesh.inp\n"
        "*NSET, NSET=PLATENODES, ELSET=PLATE\n"
        "*BOUNDARY\nPLATEBOTTOM, 1, 3\nPADTOP, 1, 2\n"
        "*SURFACE INTERACTION, NAME=PADPLATE\n"
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1e13\n"
        "*FRICTION\n0.3, 1e11\n"
        "*CONTACT PAIR, INTERACTION=PADPLATE, TYPE=NODE TO SURFACE, SMALL SLIDING\n"
        "PADBOTTOM, PLATETOP\n"
    )
    written = "** Written by examples/make_pad_on_plate_deck.py (squeal).\n"
    sliding = (
        "*HEADING\nPad on plate with friction, the plate turning under the pad as a disc "
        "would (squeal tests/data)\n" + written + head +
        "*STEP\n*STATIC\n*DSLOAD\nPADTOPFACES, P, 1e6\n"
        "*MOTION, ROTATION, TYPE=VELOCITY\n"
        "PLATENODES, 10., -0.08, 0.019, 0., -0.08, 0.019, 1.\n*END STEP\n"
        "*STEP, PERTURBATION\n*FREQUENCY\n, 0., 55000.\n*END STEP\n"
        "*STEP, PERTURBATION\n*COMPLEX FREQUENCY\n, 30000., 55000.\n*END STEP\n"
    )
    friction = (
        "*HEADING\nPad on plate with friction, the plate sliding along y under the held "
        "pad (squeal tests/data)\n" + written + head +
        "*STEP\n*STATIC\n*DSLOAD\nPADTOPFACES, P, 1e6\n*END STEP\n"
        "*STEP\n*STATIC\n*MOTION, TRANSLATION, TYPE=VELOCITY\nPLATENODES, 2, 2, 1.\n"
        "*END STEP\n*STEP, PERTURBATION\n*FREQUENCY\n12\n*END STEP\n"
    )
    friction_ccx = (
        "*HEADING\nPad on plate with friction, the plate pushed 2e-5 m along y under the "
        "held pad (CalculiX; squeal tests/data)\n" + written + head.replace(
            "*NSET, NSET=PLATENODES, ELSET=PLATE\n", "") +
        "*STEP\n*STATIC\n*DSLOAD\nPADTOPFACES, P, 1e6\n*END STEP\n"
        "*STEP\n*STATIC\n*BOUNDARY\nPLATEBOTTOM, 2, 2, 2e-5\n*END STEP\n"
        "*STEP, PERTURBATION\n*CHANGE FRICTION, INTERACTION=PADPLATE\n*FRICTION\n"
        "0.2999997, 1e11\n*FREQUENCY\n12\n*END STEP\n"
    )
    for name, text in (
        ("pad_on_plate_sliding.inp", sliding),
        ("pad_on_plate_friction.inp", friction),
        ("pad_on_plate_friction_ccx.inp", friction_ccx),
    ):
        with open(os.path.join(folder, name), "w") as f:
            f.write(text)
    with open(os.path.join(folder, "pad_on_plate_mesh.inp"), "w") as f:
        f.write("".join(mesh))
    with open(os.path.join(folder, "pad_on_plate.inp"), "w") as f:
        f.write(deck)


if __name__ == "__main__":
    main()
