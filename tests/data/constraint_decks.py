#!/usr/bin/env python3
"""Writes the constraint test decks of tests/numerics/deck_constraints.rs (python3 constraint_decks.py,
in tests/data): C3D10 boxes (Kuhn split, 6 tets a cube, nodes on a half-grid) with
*EQUATION, *COUPLING + *DISTRIBUTING, *TRANSFORM and prescribed displacements. The CalculiX
results kept beside them (*.ccx.json) come from running ccx 2.20 on the decks (and on the
.ccx.inp variants, see their headers); CalculiX is not needed to run the tests."""

import math
import sys

# Kuhn split of the unit cube (corner ids 0..7 as bits x + 2y + 4z), one tet per path.
KUHN = [
    (0, 1, 3, 7), (0, 1, 5, 7), (0, 2, 3, 7),
    (0, 2, 6, 7), (0, 4, 5, 7), (0, 4, 6, 7),
]
# C3D10 mid nodes: edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4.
EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
# Abaqus faces S1..S4 by corner positions.
FACES = [(0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0)]


def box(n, size, origin=(0.0, 0.0, 0.0), mapping=None):
    """Nodes (label -> xyz), elements (label -> 10 labels), half-grid index of a label."""
    nx, ny, nz = n
    gx, gy, gz = 2 * nx + 1, 2 * ny + 1, 2 * nz + 1

    def label(i, j, k):
        return 1 + i + gx * (j + gy * k)

    def point(i, j, k):
        p = [origin[0] + size[0] * i / (2 * nx), origin[1] + size[1] * j / (2 * ny),
             origin[2] + size[2] * k / (2 * nz)]
        return mapping(p) if mapping else p

    nodes = {}
    index = {}
    for k in range(gz):
        for j in range(gy):
            for i in range(gx):
                nodes[label(i, j, k)] = point(i, j, k)
                index[label(i, j, k)] = (i, j, k)
    elements = {}
    for cz in range(nz):
        for cy in range(ny):
            for cx in range(nx):
                for tet in KUHN:
                    corners = [(2 * cx + 2 * (c & 1), 2 * cy + 2 * ((c >> 1) & 1),
                                2 * cz + 2 * ((c >> 2) & 1)) for c in tet]
                    a, b, c, d = [nodes[label(*q)] for q in corners]
                    u = [b[m] - a[m] for m in range(3)]
                    v = [c[m] - a[m] for m in range(3)]
                    w = [d[m] - a[m] for m in range(3)]
                    vol = (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                           + u[2] * (v[0] * w[1] - v[1] * w[0]))
                    if vol < 0:
                        corners[1], corners[2] = corners[2], corners[1]
                    mids = [tuple((corners[p][m] + corners[q][m]) // 2 for m in range(3))
                            for p, q in EDGES]
                    elements[len(elements) + 1] = [label(*q) for q in corners + mids]
    return nodes, elements, index


def faces_where(nodes, elements, test):
    out = []
    for e, conn in elements.items():
        for s, (a, b, c) in enumerate(FACES):
            if all(test(nodes[conn[k]]) for k in (a, b, c)):
                out.append((e, s + 1))
    return out


def num(x):
    """The shortest text that reads back as x; CalculiX cuts every field at 20 characters."""
    text = repr(float(x))
    if len(text) > 20:
        text = f"{x:.13e}"
    assert float(text) == x or abs(float(text) - x) <= 1e-13 * abs(x), (x, text)
    return text


def write_nodes(f, nodes, nset="NALL"):
    f.write(f"*NODE, NSET={nset}\n")
    for n, x in nodes.items():
        f.write(f"{n}, {num(x[0])}, {num(x[1])}, {num(x[2])}\n")


def write_elements(f, elements, elset):
    f.write(f"*ELEMENT, TYPE=C3D10, ELSET={elset}\n")
    for e, conn in elements.items():
        f.write(f"{e}, " + ", ".join(str(c) for c in conn[:8]) + ",\n")
        f.write(", ".join(str(c) for c in conn[8:]) + "\n")


def write_set(f, name, labels):
    f.write(f"*NSET, NSET={name}\n")
    labels = sorted(labels)
    for i in range(0, len(labels), 8):
        f.write(", ".join(str(n) for n in labels[i:i + 8]) + "\n")


STEEL = "*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n"


def coupled_block(path, ccx_coupling):
    """A 20 x 20 x 10 mm steel block on soft springs (SPRING1 in x, y, z at every bottom node),
    a 0.5 kg point mass at a reference node 15 mm above the top face's centre, tied to the
    top face by a uniform distributing coupling: the six rigid-body modes of block + mass on
    the springs have a closed form."""
    nodes, elements, _ = box((2, 2, 1), (0.02, 0.02, 0.01))
    with open(path, "w") as f:
        f.write("*HEADING\nCoupled block: 20 x 20 x 10 mm steel block on springs, 0.5 kg on a "
                "distributing coupling 15 mm above its top face\n")
        f.write("** Written by tests/data/constraint_decks.py for tests/numerics/deck_constraints.rs.\n")
        write_nodes(f, nodes)
        write_elements(f, elements, "EBLOCK")
        f.write(STEEL + "*SOLID SECTION, ELSET=EBLOCK, MATERIAL=STEEL\n")
        f.write("*NODE, NSET=NREF\n9001, 0.01, 0.01, 0.025\n")
        f.write("*ELEMENT, TYPE=MASS, ELSET=EMASS\n9001, 9001\n*MASS, ELSET=EMASS\n0.5\n")
        bottom = [n for n, x in nodes.items() if x[2] == 0.0]
        label = 10000
        for d in (1, 2, 3):
            f.write(f"*ELEMENT, TYPE=SPRING1, ELSET=EK{d}\n")
            for n in bottom:
                label += 1
                f.write(f"{label}, {n}\n")
            f.write(f"*SPRING, ELSET=EK{d}\n{d}\n10.\n")
        top = faces_where(nodes, elements, lambda x: x[2] == 0.01)
        f.write("*SURFACE, NAME=TOP, TYPE=ELEMENT\n")
        for e, s in top:
            f.write(f"{e}, S{s}\n")
        if ccx_coupling:
            f.write("*COUPLING, REF NODE=9001, SURFACE=TOP, CONSTRAINT NAME=C1\n"
                    "*DISTRIBUTING\n1, 3\n")
        else:
            f.write("*COUPLING, REF NODE=9001, SURFACE=TOP, CONSTRAINT NAME=C1\n"
                    "*DISTRIBUTING, WEIGHTING METHOD=UNIFORM\n1, 3\n")
        freq = "*FREQUENCY, STORAGE=YES" if ccx_coupling else "*FREQUENCY"
        f.write(f"*STEP\n{freq}\n10\n*NODE FILE\nU\n*END STEP\n")


def bar(path):
    """A 100 x 10 x 10 mm steel bar stretched by a prescribed 0.05 mm at x = 100 mm in a
    *STATIC step, held at x = 0 along x and on its y = 0 and z = 0 faces normal to them:
    uniaxial stress, reaction E A d / L = 10.5 kN."""
    nodes, elements, _ = box((10, 1, 1), (0.1, 0.01, 0.01))
    with open(path, "w") as f:
        f.write("*HEADING\nBar 100 x 10 x 10 mm stretched by a prescribed end displacement\n")
        f.write("** Written by tests/data/constraint_decks.py for tests/numerics/deck_constraints.rs.\n")
        write_nodes(f, nodes)
        write_elements(f, elements, "EBAR")
        f.write(STEEL + "*SOLID SECTION, ELSET=EBAR, MATERIAL=STEEL\n")
        write_set(f, "X0", [n for n, x in nodes.items() if x[0] == 0.0])
        write_set(f, "X1", [n for n, x in nodes.items() if x[0] == 0.1])
        write_set(f, "Y0", [n for n, x in nodes.items() if x[1] == 0.0])
        write_set(f, "Z0", [n for n, x in nodes.items() if x[2] == 0.0])
        f.write("*BOUNDARY\nX0, 1\nY0, 2\nZ0, 3\n")
        f.write("*STEP\n*STATIC\n*BOUNDARY\nX1, 1, 1, 5e-5\n*NODE FILE\nU, RF\n*END STEP\n")


def tube(path):
    """A 60 degree sector of a tube, r 20..30 mm, 10 mm high, its corner nodes on the circles
    (straight-sided elements): in a cylindrical *TRANSFORM about z, u_r = 1e-3 r on the inner
    and outer faces (one *BOUNDARY line per node), u_theta = 0 on the two cut faces, u_z = 0
    at the bottom. The exact solution is the linear field u = 1e-3 (x, y, 0) + (0, 0, w z),
    w = -2 lambda 1e-3 / (lambda + 2 mu): reproduced exactly by quadratic tets."""
    r0, r1, sector, h = 0.02, 0.03, math.pi / 3, 0.01
    n = (2, 6, 1)
    gx, gy, gz = 2 * n[0], 2 * n[1], 2 * n[2]
    # Map the half-grid: corners on the circles, mid nodes midway (straight edges).
    corners = {}

    def polar(i, j):
        r = r0 + (r1 - r0) * i / gx
        t = sector * j / gy
        return [r * math.cos(t), r * math.sin(t)]

    nodes, elements, index = box(n, (1.0, 1.0, h))
    for lab, (i, j, k) in index.items():
        z = h * k / gz
        if i % 2 == 0 and j % 2 == 0:
            p = polar(i, j)
        else:
            # A mid node: midway between the corners of its edge (i, j odd means a face
            # diagonal of the Kuhn split, also straight).
            ia, ib = (i - 1, i + 1) if i % 2 else (i, i)
            ja, jb = (j - 1, j + 1) if j % 2 else (j, j)
            pa, pb = polar(ia, ja), polar(ib, jb)
            p = [(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2]
        nodes[lab] = [p[0], p[1], z]
    eps = 1e-3
    with open(path, "w") as f:
        f.write("*HEADING\nTube sector expanded by prescribed radial displacements in a "
                "cylindrical *TRANSFORM\n")
        f.write("** Written by tests/data/constraint_decks.py for tests/numerics/deck_constraints.rs.\n")
        write_nodes(f, nodes)
        write_elements(f, elements, "ETUBE")
        f.write(STEEL + "*SOLID SECTION, ELSET=ETUBE, MATERIAL=STEEL\n")
        inner = [lab for lab, (i, j, k) in index.items() if i == 0]
        outer = [lab for lab, (i, j, k) in index.items() if i == gx]
        cuts = [lab for lab, (i, j, k) in index.items() if j in (0, gy)]
        bottom = [lab for lab, (i, j, k) in index.items() if k == 0]
        write_set(f, "NCYL", set(inner) | set(outer) | set(cuts))
        write_set(f, "BOTTOM", bottom)
        f.write("*TRANSFORM, NSET=NCYL, TYPE=C\n0., 0., 0., 0., 0., 1.\n")
        f.write("*BOUNDARY\nBOTTOM, 3\n")
        write_set(f, "CUTS", cuts)
        f.write("*BOUNDARY\nCUTS, 2\n")
        f.write("*STEP\n*STATIC\n*BOUNDARY\n")
        for lab in sorted(set(inner) | set(outer)):
            x = nodes[lab]
            f.write(f"{lab}, 1, 1, {num(eps * math.hypot(x[0], x[1]))}\n")
        f.write("*NODE FILE\nU\n*END STEP\n")


def tributary_areas(nodes, elements, faces):
    """squeal's tributary areas of a surface's nodes: each 6-node face split into its four
    3-node sub-triangles, a third of each one's area to each of its nodes."""
    area = {}
    for e, s in faces:
        conn = elements[e]
        a, b, c = FACES[s - 1]
        mid = {frozenset(p): conn[4 + k] for k, p in enumerate(EDGES)}
        ab, bc, ca = mid[frozenset((a, b))], mid[frozenset((b, c))], mid[frozenset((c, a))]
        for tri in ((conn[a], ab, ca), (conn[b], bc, ab), (conn[c], ca, bc), (ab, bc, ca)):
            x = [nodes[n] for n in tri]
            u = [x[1][m] - x[0][m] for m in range(3)]
            v = [x[2][m] - x[0][m] for m in range(3)]
            cr = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            t = 0.5 * math.sqrt(sum(q * q for q in cr))
            for n in tri:
                area[n] = area.get(n, 0.0) + t / 3
    return area


def reference_blocks(nodes, weights, ref):
    """Abaqus's distributing coupling: u_ref = sum_i B_i u_i (see src/fem/distributing.rs),
    written again here so the CalculiX variant checks squeal's own coefficients."""
    total = sum(weights.values())
    w = {n: v / total for n, v in weights.items()}
    c = [sum(w[n] * nodes[n][m] for n in w) for m in range(3)]
    t = [[0.0] * 3 for _ in range(3)]
    for n, wn in w.items():
        r = [nodes[n][m] - c[m] for m in range(3)]
        rr = sum(q * q for q in r)
        for i in range(3):
            for j in range(3):
                t[i][j] += wn * ((rr if i == j else 0.0) - r[i] * r[j])
    det = (t[0][0] * (t[1][1] * t[2][2] - t[1][2] * t[2][1])
           - t[0][1] * (t[1][0] * t[2][2] - t[1][2] * t[2][0])
           + t[0][2] * (t[1][0] * t[2][1] - t[1][1] * t[2][0]))
    inv = [[0.0] * 3 for _ in range(3)]
    for i in range(3):
        for j in range(3):
            r0, r1 = (j + 1) % 3, (j + 2) % 3
            c0, c1 = (i + 1) % 3, (i + 2) % 3
            inv[i][j] = (t[r0][c0] * t[r1][c1] - t[r0][c1] * t[r1][c0]) / det

    def skew(a):
        return [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]]

    so = skew([ref[m] - c[m] for m in range(3)])
    so_t = [[sum(so[i][k] * inv[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    blocks = {}
    for n, wn in w.items():
        sr = skew([nodes[n][m] - c[m] for m in range(3)])
        blocks[n] = [[wn * ((1.0 if i == j else 0.0) - sum(so_t[i][k] * sr[k][j] for k in range(3)))
                      for j in range(3)] for i in range(3)]
    return blocks


def write_equation(f, terms):
    f.write(f"{len(terms)}\n")
    for i in range(0, len(terms), 4):
        f.write(", ".join(f"{n}, {d}, {num(a)}" for n, d, a in terms[i:i + 4]) + "\n")


def cantilever(path, ccx_variant):
    """The cantilever of discrete_c3d10.inp (its springs and point masses) with three
    *EQUATIONs (two terms, three terms, and one over two node sets: three equations) and a
    10 g point mass on a reference node 10 mm beyond the free end, tied to the end face by a
    uniform distributing coupling. The CalculiX variant writes the node-set equation node by
    node and the coupling as its three *EQUATIONs, with the coefficients computed here."""
    text = open("discrete_c3d10.inp").read()
    nodes = {}
    elements = {}
    block = None
    etype = ""
    for line in text.splitlines():
        if line.startswith("*"):
            block = line.upper().split(",")[0]
            etype = line.upper().replace(" ", "")
            continue
        if block == "*NODE":
            f = [q.strip() for q in line.split(",")]
            nodes[int(f[0])] = [float(q) for q in f[1:4]]
        if block == "*ELEMENT" and "TYPE=C3D10" in etype:
            f = [int(q) for q in line.split(",") if q.strip()]
            elements[f[0]] = f[1:]

    def at(x, y, z):
        return next(n for n, p in nodes.items() if abs(p[0] - x) < 1e-9 and abs(p[1] - y) < 1e-9
                    and abs(p[2] - z) < 1e-9)

    tip = faces_where(nodes, elements, lambda x: abs(x[0] - 0.1) < 1e-12)
    ref = [0.11, 0.005, 0.005]
    extra = ["** Constraints (tests/data/constraint_decks.py).\n",
             "*NODE, NSET=NREF\n3000, 0.11, 0.005, 0.005\n",
             "*ELEMENT, TYPE=MASS, ELSET=EREFMASS\n3000, 3000\n*MASS, ELSET=EREFMASS\n0.01\n"]
    eqa = [at(0.03, 0.0, z) for z in (0.0, 0.0025, 0.005)]
    eqb = [at(0.03, 0.01, z) for z in (0.0, 0.0025, 0.005)]
    eqs = [
        [(at(0.05, 0.0, 0.01), 3, 1.0), (at(0.05, 0.01, 0.01), 3, -1.0)],
        [(at(0.07, 0.005, 0.0), 2, 1.0), (at(0.065, 0.005, 0.0), 2, -0.6),
         (at(0.075, 0.005, 0.0), 2, -0.4)],
    ]
    out = []
    out.extend(extra)
    if ccx_variant:
        out.append("*EQUATION\n")
        for eq in eqs + [[(a, 1, 1.0), (b, 1, -1.0)] for a, b in zip(eqa, eqb)]:
            import io
            buf = io.StringIO()
            write_equation(buf, eq)
            out.append(buf.getvalue())
        areas = tributary_areas(nodes, elements, tip)
        blocks = reference_blocks(nodes, areas, ref)
        corner = at(0.1, 0.0, 0.0)
        out.append("** The coupling of reference node 3000 to the end face, as squeal makes it.\n")
        out.append("*EQUATION\n")
        for comp in range(3):
            terms = [(3000, comp + 1, 1.0)]
            largest = max(abs(b[comp][j]) for b in blocks.values() for j in range(3))
            for n in sorted(blocks):
                for j in range(3):
                    # squeal drops the substitutions' round-off the same way.
                    if abs(blocks[n][comp][j]) > 1e-13 * largest:
                        terms.append((n, j + 1, -blocks[n][comp][j]))
            # CalculiX stops ("add_sm_ei: coefficient should be 0") on a point mass at a
            # dependent DOF: the same equation, with an end-face corner's DOF dependent.
            first = next(t for t in terms if t[0] == corner and t[1] == comp + 1)
            terms.remove(first)
            terms.insert(0, first)
            import io
            buf = io.StringIO()
            write_equation(buf, terms)
            out.append(buf.getvalue())
    else:
        out.append("*NSET, NSET=EQA\n" + ", ".join(map(str, eqa)) + "\n")
        out.append("*NSET, NSET=EQB\n" + ", ".join(map(str, eqb)) + "\n")
        out.append("*EQUATION\n")
        import io
        for eq in eqs:
            buf = io.StringIO()
            write_equation(buf, eq)
            out.append(buf.getvalue())
        out.append("2\nEQA, 1, 1., EQB, 1, -1.\n")
        out.append("*SURFACE, NAME=TIP, TYPE=ELEMENT\n")
        out.extend(f"{e}, S{s}\n" for e, s in tip)
        out.append("*COUPLING, REF NODE=3000, SURFACE=TIP, CONSTRAINT NAME=TIPMASS\n"
                   "*DISTRIBUTING\n1, 3\n")
    cut = text.index("\n*BOUNDARY\n") + 1
    head = text[:cut].replace(
        "** Written for tests/numerics/deck_discrete.rs (squeal); frequencies from CalculiX 2.20 in "
        "discrete_c3d10.ccx.json.",
        "** discrete_c3d10.inp with constraints, written by tests/data/constraint_decks.py for "
        "tests/numerics/deck_constraints.rs; frequencies from CalculiX 2.20 (on constraints_c3d10.ccx.inp) "
        "in constraints_c3d10.ccx.json.")
    tail = text[cut:]
    if ccx_variant:
        # STORAGE=YES: the eigenvalues to full precision in the binary .eig file.
        tail = tail.replace("*FREQUENCY\n", "*FREQUENCY, STORAGE=YES\n")
    with open(path, "w") as f:
        f.write(head + "".join(out) + tail)


PAD = "*MATERIAL, NAME=PAD\n*ELASTIC\n20e9, 0.25\n*DENSITY\n2500.\n"


def face_weights(x, corners):
    """The six quadratic face shape functions (corners, then mid-edge nodes ab, bc, ca) at the
    point of the flat straight-sided triangle `corners` under x (in-plane barycentrics)."""
    (ax, ay), (bx, by), (cx, cy) = [(c[0], c[1]) for c in corners]
    det = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay)
    lb = ((x[0] - ax) * (cy - ay) - (cx - ax) * (x[1] - ay)) / det
    lc = ((bx - ax) * (x[1] - ay) - (x[0] - ax) * (by - ay)) / det
    la = 1.0 - lb - lc
    l = (la, lb, lc)
    return [q * (2 * q - 1) for q in l] + [4 * la * lb, 4 * lb * lc, 4 * lc * la], min(l)


def tied_pads(path, clamped, variant, lift=0.0, adjust=True):
    """Two pads (20 x 30 x 5 mm, E 20 GPa) on a steel plate (60 x 40 x 5 mm) across
    non-matching meshes: the pads' half-grid is 3.33 x 3.75 mm, the plate's 5 x 5 mm, and the
    pads sit 1 mm (the second 2 mm) off the plate's grid lines in x and 0.5 mm in y; no tied
    face reaches the held end. variant "tie": two *TIEs (each pad's bottom to the plate's
    top; the finer pads are the slaves); "equations": the same
    constraints as *EQUATIONs whose coefficients are the quadratic face shape functions at
    each slave node, computed here; "ccx": the tie deck with *FREQUENCY, STORAGE=YES.
    clamped: the plate's end face x = 0 held (a cantilever); else free-free (six rigid-body
    modes). lift: the pads raised that far above the plate (ties with POSITION TOLERANCE=
    1e-4; adjust=False writes ADJUST=NO, else CalculiX's default, which moves the slave
    nodes onto the master surface and knows no ADJUST=YES)."""
    plate_nodes, plate_elements, _ = box((6, 4, 1), (0.06, 0.04, 0.005))
    out_nodes = dict(plate_nodes)
    out_elements = {}
    pads = []
    for k, x0 in enumerate((0.011, 0.037)):
        nodes, elements, _ = box((3, 4, 1), (0.02, 0.03, 0.005),
                                 origin=(x0, 0.0055, 0.005 + lift))
        shift_n, shift_e = 1000 * (k + 1), 1000 * (k + 1)
        nodes = {n + shift_n: x for n, x in nodes.items()}
        elements = {e + shift_e: [c + shift_n for c in conn] for e, conn in elements.items()}
        out_nodes.update(nodes)
        pads.append((nodes, elements))
    top = faces_where(plate_nodes, plate_elements, lambda x: x[2] == 0.005)
    with open(path, "w") as f:
        kind = "clamped" if clamped else "free-free"
        f.write(f"*HEADING\nTwo pads tied to a plate across non-matching meshes ({kind}, {variant})\n")
        f.write("** Written by tests/data/constraint_decks.py for tests/program/modes_cli.rs.\n")
        write_nodes(f, out_nodes)
        write_elements(f, plate_elements, "EPLATE")
        for k, (nodes, elements) in enumerate(pads):
            write_elements(f, elements, f"EPAD{k + 1}")
        f.write("*ELSET, ELSET=EPADS\nEPAD1, EPAD2\n")
        f.write(STEEL + PAD)
        f.write("*SOLID SECTION, ELSET=EPLATE, MATERIAL=STEEL\n")
        f.write("*SOLID SECTION, ELSET=EPADS, MATERIAL=PAD\n")
        f.write("*SURFACE, NAME=PLATETOP, TYPE=ELEMENT\n")
        for e, s in top:
            f.write(f"{e}, S{s}\n")
        for k, (nodes, elements) in enumerate(pads):
            bottom = faces_where(nodes, elements, lambda x: x[2] == 0.005 + lift)
            f.write(f"*SURFACE, NAME=PAD{k + 1}BOTTOM, TYPE=ELEMENT\n")
            for e, s in bottom:
                f.write(f"{e}, S{s}\n")
        if variant in ("tie", "ccx"):
            params = ""
            if lift:
                params = ", POSITION TOLERANCE=1e-4" + ("" if adjust else ", ADJUST=NO")
            for k in range(2):
                f.write(f"*TIE, NAME=GLUE{k + 1}{params}\nPAD{k + 1}BOTTOM, PLATETOP\n")
        else:
            f.write("*EQUATION\n")
            for nodes, elements in pads:
                slaves = sorted(n for n, x in nodes.items() if x[2] == 0.005)
                for n in slaves:
                    x = nodes[n]
                    best = None
                    for e, s in top:
                        conn = plate_elements[e]
                        a, b, c = FACES[s - 1]
                        mid = {frozenset(p): conn[4 + q] for q, p in enumerate(EDGES)}
                        face = [conn[a], conn[b], conn[c], mid[frozenset((a, b))],
                                mid[frozenset((b, c))], mid[frozenset((c, a))]]
                        w, inside = face_weights(x, [plate_nodes[conn[i]] for i in (a, b, c)])
                        if best is None or inside > best[0]:
                            best = (inside, face, w)
                    inside, face, w = best
                    assert inside > -1e-12, (n, x)
                    for d in (1, 2, 3):
                        write_equation(f, [(n, d, 1.0)] + [(m, d, -q) for m, q in zip(face, w)
                                                           if abs(q) > 1e-14])
        if clamped:
            write_set(f, "END", [n for n, x in plate_nodes.items() if x[0] == 0.0])
            f.write("*BOUNDARY\nEND, 1, 3\n")
        freq = "*FREQUENCY, STORAGE=YES" if variant == "ccx" else "*FREQUENCY"
        f.write(f"*STEP\n{freq}\n16\n*NODE FILE\nU\n*END STEP\n")


if __name__ == "__main__":
    here = sys.argv[1] if len(sys.argv) > 1 else "."
    coupled_block(f"{here}/coupled_block.inp", False)
    coupled_block(f"{here}/coupled_block.ccx.inp", True)
    bar(f"{here}/prescribed_bar.inp")
    tube(f"{here}/prescribed_tube.inp")
    cantilever(f"{here}/constraints_c3d10.inp", False)
    cantilever(f"{here}/constraints_c3d10.ccx.inp", True)
    for clamped, name in ((True, "clamped"), (False, "free")):
        tied_pads(f"{here}/tied_pads_{name}.inp", clamped, "tie")
        tied_pads(f"{here}/tied_pads_{name}.eqn.inp", clamped, "equations")
        tied_pads(f"{here}/tied_pads_{name}.ccx.inp", clamped, "ccx")
    # squeal reads these CalculiX decks as they are (STORAGE=YES changes nothing for it).
    tied_pads(f"{here}/tied_pads_lifted.ccx.inp", True, "ccx", lift=1e-5)
    tied_pads(f"{here}/tied_pads_lifted_noadjust.ccx.inp", True, "ccx", lift=1e-5, adjust=False)
