#!/usr/bin/env python3
"""Writes the tied-pad decks of tests/data: a pad made of a lining and a steel backplate bonded
by *TIE, pressed on a plate that turns under it as a disc would (the sliding deck of
make_pad_on_plate_deck.py with its pad split in two).

  tied_pad_on_plate.inp           the backplate meshed finer than the lining (4 x 4 cubes over
                                  3 x 3): non-matching meshes, the backplate's bottom the
                                  tie's slave surface, the lining's top its master
  tied_pad_on_plate_matching.inp  the backplate meshed as the lining (3 x 3), its own nodes on
                                  the interface, tied node on node
  tied_pad_on_plate_merged.inp    the same backplate sharing the lining's top nodes: one mesh,
                                  no tie (what the matching tie must give exactly)

The steel plate [0, 0.04]^2 x [0, 0.01] (4 x 4 x 1 cubes) is clamped at its bottom; the lining
[0.006, 0.032]^2 x [0.01, 0.015] (E = 5 GPa) sits on it with frictional node-to-surface contact
(mu 0.3, linear pressure-overclosure slope 1e13 Pa/m); the backplate [0.006, 0.032]^2 x
[0.015, 0.018] (steel) is pressed by 1 MPa and held in x and y on its top. The plate turns
about an axis 99 mm from the pad's centre (*MOTION, ROTATION). `squeal study` on any of them
compares the full model with reduced contact interfaces (tests/program/deck_contact.rs).

Usage: python3 examples/make_tied_pad_deck.py [folder]   (default tests/data)
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_pad_on_plate_deck import box, faces_at, lines  # noqa: E402

HEAD = "** Written by examples/make_tied_pad_deck.py (squeal).\n"


def deck(title, backplate_cells, merged, tied):
    plate_nodes, plate = box((0.0, 0.0, 0.0), (0.04, 0.04, 0.01), (4, 4, 1), 1, 1)
    lining_nodes, lining = box((0.006, 0.006, 0.01), (0.026, 0.026, 0.005), (3, 3, 1), 1001, 1001)
    back_nodes, back = box((0.006, 0.006, 0.015), (0.026, 0.026, 0.003), backplate_cells, 2001,
                           2001)
    if merged:
        # The backplate's bottom nodes are the lining's top nodes (same half-grid positions).
        at = {tuple(round(c, 12) for c in x): n for n, x in lining_nodes.items()
              if abs(x[2] - 0.015) < 1e-12}
        same = {n: at[tuple(round(c, 12) for c in x)] for n, x in back_nodes.items()
                if abs(x[2] - 0.015) < 1e-12}
        back = [(e, [same.get(n, n) for n in conn]) for e, conn in back]
        back_nodes = {n: x for n, x in back_nodes.items() if n not in same}
    out = ["*HEADING\n", title + "\n", HEAD, "*NODE, NSET=NALL\n"]
    for label, x in sorted({**plate_nodes, **lining_nodes, **back_nodes}.items()):
        out.append(f"{label}, {x[0]:.9f}, {x[1]:.9f}, {x[2]:.9f}\n")
    for name, elements in (("PLATE", plate), ("LINING", lining), ("BACKPLATE", back)):
        out.append(f"*ELEMENT, TYPE=C3D10, ELSET={name}\n")
        for e, conn in elements:
            out.append(f"{e}, " + ", ".join(map(str, conn)) + "\n")
    out.append("*NSET, NSET=PLATEBOTTOM\n")
    out.append(lines(sorted(n for n, x in plate_nodes.items() if x[2] == 0.0)))
    out.append("*NSET, NSET=BACKPLATETOP\n")
    out.append(lines(sorted(n for n, x in back_nodes.items() if abs(x[2] - 0.018) < 1e-12)))
    all_back = {**back_nodes, **lining_nodes} if merged else back_nodes
    surfaces = [
        ("PLATETOP", plate_nodes, plate, 0.01),
        ("LININGBOTTOM", lining_nodes, lining, 0.01),
        ("LININGTOP", lining_nodes, lining, 0.015),
        ("BACKPLATEBOTTOM", all_back, back, 0.015),
        ("BACKPLATETOPFACES", all_back, back, 0.018),
    ]
    for name, nodes, elements, z in surfaces:
        out.append(f"*SURFACE, NAME={name}, TYPE=ELEMENT\n")
        out.extend(f"{e}, {s}\n" for e, s in faces_at(nodes, elements, z))
    out.append(
        "*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n"
        "*MATERIAL, NAME=LINING\n*ELASTIC\n5e9, 0.25\n*DENSITY\n2500.\n"
        "*SOLID SECTION, ELSET=PLATE, MATERIAL=STEEL\n"
        "*SOLID SECTION, ELSET=LINING, MATERIAL=LINING\n"
        "*SOLID SECTION, ELSET=BACKPLATE, MATERIAL=STEEL\n"
    )
    if tied:
        out.append("*TIE, NAME=BOND\nBACKPLATEBOTTOM, LININGTOP\n")
    out.append(
        "*NSET, NSET=PLATENODES, ELSET=PLATE\n"
        "*BOUNDARY\nPLATEBOTTOM, 1, 3\nBACKPLATETOP, 1, 2\n"
        "*SURFACE INTERACTION, NAME=PADPLATE\n"
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1e13\n"
        "*FRICTION\n0.3, 1e11\n"
        "*CONTACT PAIR, INTERACTION=PADPLATE, TYPE=NODE TO SURFACE, SMALL SLIDING\n"
        "LININGBOTTOM, PLATETOP\n"
        "*STEP\n*STATIC\n*DSLOAD\nBACKPLATETOPFACES, P, 1e6\n"
        "*MOTION, ROTATION, TYPE=VELOCITY\n"
        "PLATENODES, 10., -0.08, 0.019, 0., -0.08, 0.019, 1.\n*END STEP\n"
        "*STEP, PERTURBATION\n*COMPLEX FREQUENCY\n, 0., 60000.\n*END STEP\n"
    )
    return "".join(out)


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "tests/data"
    for name, cells, merged, tied, what in (
        ("tied_pad_on_plate.inp", (4, 4, 1), False, True,
         "lining and backplate tied across non-matching meshes"),
        ("tied_pad_on_plate_matching.inp", (3, 3, 1), False, True,
         "lining and backplate tied node on node"),
        ("tied_pad_on_plate_merged.inp", (3, 3, 1), True, False,
         "lining and backplate sharing their interface nodes"),
    ):
        title = f"Pad ({what}) on a plate turning under it (squeal tests/data)"
        with open(os.path.join(folder, name), "w") as f:
            f.write(deck(title, cells, merged, tied))


if __name__ == "__main__":
    main()
