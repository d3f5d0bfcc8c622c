#!/usr/bin/env python3
"""Writes a disc brake as users write its deck: a disc clamped at its hub, and two pads, each a
friction lining bonded by *TIE to a steel backplate across non-matching meshes, pressed on
the disc's two faces with frictional node-to-surface contact while the disc turns
(*MOTION, ROTATION). Issue 34's example of a tied-pad brake for `squeal study`.

  tied_disc_brake.inp            each backplate meshed finer than its lining (6 x 5 cells over
                                 5 x 4): the tie's slave surface is the backplate's face
  tied_disc_brake_matching.inp   the backplates meshed as the linings, tied node on node
  tied_disc_brake_merged.inp     the backplates sharing the linings' interface nodes: one mesh
                                 per pad and no tie (what the matching deck must give exactly)

The disc: an annulus 60-140 mm in radius, 12 mm thick (z -6 to 6 mm), grey cast iron
(E 125 GPa), 40 cells around, 4 across, 2 through, its inner rim held. Each pad: a lining
50 x 40 x 6 mm (E 5 GPa) on the disc face at 75-125 mm along x, a backplate 50 x 40 x 4 mm of
steel behind it, held in x and y on its back and pressed by 1 MPa there. Every cell is split
into the six Kuhn tetrahedra with quadratic (C3D10) elements; the disc's mid-edge nodes lie on
its arcs. Contact: linear pressure-overclosure slope 1e13 Pa/m, mu 0.3, linings the slaves.

tests/data keeps tied_disc_brake.inp (tests/program/deck_contact.rs runs its study); the two
others are the exact check the README gives figures for (the tie node on node is the merge).

Usage: python3 examples/make_tied_disc_brake_deck.py [folder]   (default tests/data)
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_pad_on_plate_deck import box, faces_at, kuhn_elements, lines  # noqa: E402

HEAD = "** Written by examples/make_tied_disc_brake_deck.py (squeal).\n"
RI, RO, HALF = 0.06, 0.14, 0.006
PAD_X, PAD_Y = (0.075, 0.125), (-0.02, 0.02)
LINING, BACKPLATE = 0.006, 0.004


def disc(cells, first_node, first_element):
    """Nodes and C3D10 elements of the annulus RI <= r <= RO, -HALF <= z <= HALF: a structured
    (r, theta, z) grid of `cells`, wrapping around in theta, Kuhn-split in index space (where
    the polar map keeps orientation), mid-edge nodes at the (r, theta, z) midpoints."""
    nr, nt, nz = cells
    m_r, m_t = 2 * nr + 1, 2 * nt

    def label(h):
        return first_node + h[0] + m_r * (h[1] % m_t + m_t * h[2])

    nodes = {}
    for k in range(2 * nz + 1):
        for j in range(m_t):
            for i in range(m_r):
                r = RI + (RO - RI) * i / (2 * nr)
                t = 2 * math.pi * j / m_t
                z = -HALF + 2 * HALF * k / (2 * nz)
                nodes[label((i, j, k))] = (r * math.cos(t), r * math.sin(t), z)
    return nodes, kuhn_elements(cells, label, first_element)


def pad(side, backplate_cells, merged, first):
    """One pad on the disc face z = side * HALF: lining and backplate boxes (labels from
    `first`), the backplate sharing the lining's interface nodes when `merged`."""
    size_x, size_y = PAD_X[1] - PAD_X[0], PAD_Y[1] - PAD_Y[0]
    z_lining = HALF if side > 0 else -HALF - LINING
    z_back = HALF + LINING if side > 0 else -HALF - LINING - BACKPLATE
    lining_nodes, lining = box((PAD_X[0], PAD_Y[0], z_lining), (size_x, size_y, LINING),
                               (5, 4, 1), first, first)
    back_nodes, back = box((PAD_X[0], PAD_Y[0], z_back), (size_x, size_y, BACKPLATE),
                           backplate_cells, first + 1000, first + 1000)
    bond = HALF + LINING if side > 0 else -HALF - LINING
    if merged:
        at = {tuple(round(c, 12) for c in x): n for n, x in lining_nodes.items()
              if abs(x[2] - bond) < 1e-12}
        same = {n: at[tuple(round(c, 12) for c in x)] for n, x in back_nodes.items()
                if abs(x[2] - bond) < 1e-12}
        back = [(e, [same.get(n, n) for n in conn]) for e, conn in back]
        back_nodes = {n: x for n, x in back_nodes.items() if n not in same}
    return lining_nodes, lining, back_nodes, back, bond


def deck(title, backplate_cells, merged, tied):
    disc_nodes, disc_elements = disc((4, 40, 2), 1, 1)
    out = ["*HEADING\n", title + "\n", HEAD]
    parts = [("DISC", disc_nodes, disc_elements)]
    surfaces = [
        ("DISC_TOP", disc_nodes, disc_elements, HALF),
        ("DISC_BOTTOM", disc_nodes, disc_elements, -HALF),
    ]
    backs = []
    for side, name, first in ((1, "OUT", 100001), (-1, "IN", 200001)):
        lining_nodes, lining, back_nodes, back, bond = pad(side, backplate_cells, merged, first)
        parts += [(f"LINING_{name}", lining_nodes, lining), (f"BACKPLATE_{name}", back_nodes, back)]
        all_back = {**back_nodes, **lining_nodes} if merged else back_nodes
        face = HALF if side > 0 else -HALF
        rear = bond + side * BACKPLATE
        surfaces += [
            (f"LINING_{name}_FACE", lining_nodes, lining, face),
            (f"LINING_{name}_BOND", lining_nodes, lining, bond),
            (f"BACKPLATE_{name}_BOND", all_back, back, bond),
            (f"BACKPLATE_{name}_REAR", all_back, back, rear),
        ]
        backs.append((name, back_nodes, rear))
    out.append("*NODE, NSET=NALL\n")
    every = {}
    for _, nodes, _ in parts:
        every.update(nodes)
    for label, x in sorted(every.items()):
        out.append(f"{label}, {x[0]:.9f}, {x[1]:.9f}, {x[2]:.9f}\n")
    for name, _, elements in parts:
        out.append(f"*ELEMENT, TYPE=C3D10, ELSET={name}\n")
        for e, conn in elements:
            out.append(f"{e}, " + ", ".join(map(str, conn)) + "\n")
    out.append("*NSET, NSET=HUB\n")
    out.append(lines(sorted(n for n, x in disc_nodes.items()
                            if abs(math.hypot(x[0], x[1]) - RI) < 1e-9)))
    for name, back_nodes, rear in backs:
        out.append(f"*NSET, NSET=BACKPLATE_{name}_HELD\n")
        out.append(lines(sorted(n for n, x in back_nodes.items() if abs(x[2] - rear) < 1e-12)))
    for name, nodes, elements, z in surfaces:
        out.append(f"*SURFACE, NAME={name}, TYPE=ELEMENT\n")
        out.extend(f"{e}, {s}\n" for e, s in faces_at(nodes, elements, z))
    out.append(
        "*MATERIAL, NAME=CAST_IRON\n*ELASTIC\n125e9, 0.25\n*DENSITY\n7200.\n"
        "*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n"
        "*MATERIAL, NAME=LINING\n*ELASTIC\n5e9, 0.25\n*DENSITY\n2500.\n"
        "*SOLID SECTION, ELSET=DISC, MATERIAL=CAST_IRON\n"
    )
    for name in ("OUT", "IN"):
        out.append(f"*SOLID SECTION, ELSET=LINING_{name}, MATERIAL=LINING\n"
                   f"*SOLID SECTION, ELSET=BACKPLATE_{name}, MATERIAL=STEEL\n")
        if tied:
            out.append(f"*TIE, NAME=BOND_{name}\nBACKPLATE_{name}_BOND, LINING_{name}_BOND\n")
    out.append(
        "*NSET, NSET=DISCNODES, ELSET=DISC\n"
        "*BOUNDARY\nHUB, 1, 3\nBACKPLATE_OUT_HELD, 1, 2\nBACKPLATE_IN_HELD, 1, 2\n"
        "*SURFACE INTERACTION, NAME=LINING_DISC\n"
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1e13\n"
        "*FRICTION\n0.3, 1e11\n"
        "*CONTACT PAIR, INTERACTION=LINING_DISC, TYPE=NODE TO SURFACE, SMALL SLIDING\n"
        "LINING_OUT_FACE, DISC_TOP\n"
        "*CONTACT PAIR, INTERACTION=LINING_DISC, TYPE=NODE TO SURFACE, SMALL SLIDING\n"
        "LINING_IN_FACE, DISC_BOTTOM\n"
        "*STEP\n*STATIC\n*DSLOAD\nBACKPLATE_OUT_REAR, P, 1e6\nBACKPLATE_IN_REAR, P, 1e6\n"
        "*MOTION, ROTATION, TYPE=VELOCITY\n"
        "DISCNODES, 10., 0., 0., 0., 0., 0., 1.\n*END STEP\n"
        "*STEP, PERTURBATION\n*COMPLEX FREQUENCY\n, 0., 8000.\n*END STEP\n"
    )
    return "".join(out)


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "tests/data"
    for name, cells, merged, tied, what in (
        ("tied_disc_brake.inp", (6, 5, 1), False, True,
         "linings and backplates tied across non-matching meshes"),
        ("tied_disc_brake_matching.inp", (5, 4, 1), False, True,
         "linings and backplates tied node on node"),
        ("tied_disc_brake_merged.inp", (5, 4, 1), True, False,
         "linings and backplates sharing their interface nodes"),
    ):
        title = f"Disc brake, pads of {what} (squeal tests/data)"
        with open(os.path.join(folder, name), "w") as f:
            f.write(deck(title, cells, merged, tied))


if __name__ == "__main__":
    main()
