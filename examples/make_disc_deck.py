#!/usr/bin/env python3
"""Write a CalculiX/Abaqus deck of an annular brake-disc blank meshed with C3D10.

The annulus ri <= r <= ro, 0 <= z <= t is cut into a structured grid of
nr (radial) x nt (circumferential, wrapping around) x nz (thickness) cells in
(r, theta, z).  Every cell is split into 6 tetrahedra by the Kuhn split along
the cell diagonal (i, j, k) -> (i+1, j+1, k+1), the same split in every cell,
so face diagonals of neighbouring cells match (also across the theta seam).

Nodes live on the doubled index grid (I, J, K) = (0..2nr, 0..2nt-1, 0..2nz),
mapped by x = r cos(theta), y = r sin(theta), z.  Odd indices are mid-edge
nodes, so edges along theta have their mid-node on the true arc, and every
mid-edge node is the image of the (r, theta, z) midpoint (elements are the
quadratic images of straight tets in (r, theta, z)).  Node order per element
is Abaqus C3D10: corners 1-4, then edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4.

The inner rim r = ri (all nodes with I = 0) is clamped (*BOUNDARY on NSET
CLAMP).  The step is *FREQUENCY with --nev eigenvalues and the upper
frequency field set to --fmax (CalculiX then only reports modes below fmax and
warns if the nev-th eigenvalue is still below fmax).

Every element is checked: positive corner (straight) volume, and positive
Jacobian determinant of the curved 10-node map at the 4 Gauss points and the
4 corners.

Usage:
    python3 examples/make_disc_deck.py -o disc_c3d10.inp            # 96 x 6 x 3
    python3 examples/make_disc_deck.py --nt 192 --nr 10 --nz 4 -o big.inp
    python3 examples/make_disc_deck.py --storage ...  # *FREQUENCY, STORAGE=YES
                                    # (binary .eig file with full-precision
                                    #  eigenvalues, K, M and modes)
Python 3 standard library only.
"""
import argparse
import math
import sys

# Kuhn split of the unit cube: one tet per permutation of the axes (i, j, k);
# path (0,0,0) -> +e_a -> +e_b -> (1,1,1).
PERMS = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]


def kuhn_tets():
    tets = []
    for p in PERMS:
        v = [0, 0, 0]
        path = [tuple(v)]
        for a in p:
            v[a] += 1
            path.append(tuple(v))
        tets.append(path)
    return tets


def det3(a, b, c):
    return (a[0] * (b[1] * c[2] - b[2] * c[1])
            - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]))


def c3d10_jacobian(xl, l1, l2, l3):
    """det J of the 10-node tet map at volume coordinates (1-l1-l2-l3, l1, l2, l3)."""
    l0 = 1.0 - l1 - l2 - l3
    lam = (l0, l1, l2, l3)
    # dN/dL_a for the quadratic tet in terms of the 4 volume coordinates
    # then chain rule with L0 = 1 - L1 - L2 - L3.
    dN = [[0.0] * 4 for _ in range(10)]
    for a in range(4):
        dN[a][a] = 4.0 * lam[a] - 1.0
    for e, (a, b) in enumerate(EDGES):
        dN[4 + e][a] += 4.0 * lam[b]
        dN[4 + e][b] += 4.0 * lam[a]
    cols = []
    for d in (1, 2, 3):
        g = [0.0, 0.0, 0.0]
        for n in range(10):
            w = dN[n][d] - dN[n][0]
            g[0] += w * xl[n][0]
            g[1] += w * xl[n][1]
            g[2] += w * xl[n][2]
        cols.append(g)
    return det3(cols[0], cols[1], cols[2])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--nt", type=int, default=96, help="circumferential cells (default 96)")
    ap.add_argument("--nr", type=int, default=6, help="radial cells (default 6)")
    ap.add_argument("--nz", type=int, default=3, help="cells through the thickness (default 3)")
    ap.add_argument("--ro", type=float, default=0.14, help="outer radius [m]")
    ap.add_argument("--ri", type=float, default=0.075, help="inner (clamped) radius [m]")
    ap.add_argument("--t", type=float, default=0.022, help="thickness [m]")
    ap.add_argument("--E", type=float, default=125e9, help="Young's modulus [Pa]")
    ap.add_argument("--nu", type=float, default=0.25, help="Poisson ratio")
    ap.add_argument("--rho", type=float, default=7200.0, help="density [kg/m^3]")
    ap.add_argument("--nev", type=int, default=60, help="eigenvalues requested")
    ap.add_argument("--fmax", type=float, default=10000.0, help="upper frequency [Hz]")
    ap.add_argument("--storage", action="store_true",
                    help="*FREQUENCY, STORAGE=YES (writes the binary .eig file)")
    ap.add_argument("--node-file", action="store_true",
                    help="request *NODE FILE U (mode shapes in the .frd)")
    ap.add_argument("-o", "--output", default="-", help="output deck (default stdout)")
    a = ap.parse_args(argv)
    if a.nt < 3 or a.nr < 1 or a.nz < 1:
        ap.error("need nt >= 3, nr >= 1, nz >= 1")

    NI, NJ, NK = 2 * a.nr + 1, 2 * a.nt, 2 * a.nz + 1

    def nid(I, J, K):
        return 1 + I + NI * (K + NK * (J % NJ))

    def xyz(I, J, K):
        r = a.ri + (a.ro - a.ri) * I / (2 * a.nr)
        th = 2.0 * math.pi * (J % NJ) / NJ
        c, s = math.cos(th), math.sin(th)
        c = 0.0 if abs(c) < 1e-15 else c  # exact zeros at theta = k pi / 2
        s = 0.0 if abs(s) < 1e-15 else s
        return (r * c, r * s, a.t * K / (2 * a.nz))

    coords = {}
    for J in range(NJ):
        for K in range(NK):
            for I in range(NI):
                coords[nid(I, J, K)] = xyz(I, J, K)

    tets = kuhn_tets()
    elements = []
    vmin = math.inf
    jmin = math.inf
    g_a, g_b = 0.138196601125011, 0.585410196624968
    check_pts = [(g_a, g_a, g_a), (g_b, g_a, g_a), (g_a, g_b, g_a), (g_a, g_a, g_b),
                 (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)]
    for j in range(a.nt):
        for k in range(a.nz):
            for i in range(a.nr):
                for tet in tets:
                    # doubled (unwrapped) indices of the 4 corners
                    cs = [(2 * (i + d[0]), 2 * (j + d[1]), 2 * (k + d[2])) for d in tet]
                    x = [xyz(*c) for c in cs]
                    e1 = [x[1][m] - x[0][m] for m in range(3)]
                    e2 = [x[2][m] - x[0][m] for m in range(3)]
                    e3 = [x[3][m] - x[0][m] for m in range(3)]
                    v6 = det3(e1, e2, e3)
                    if v6 < 0.0:  # odd permutation: swap corners 2 and 3
                        cs[1], cs[2] = cs[2], cs[1]
                        x[1], x[2] = x[2], x[1]
                        v6 = -v6
                    mids = [tuple((cs[p][m] + cs[q][m]) // 2 for m in range(3)) for p, q in EDGES]
                    nodes = [nid(*c) for c in cs] + [nid(*c) for c in mids]
                    vol = v6 / 6.0
                    if not vol > 0.0:
                        sys.exit("element %d: non-positive corner volume %g" % (len(elements) + 1, vol))
                    vmin = min(vmin, vol)
                    xl = [coords[n] for n in nodes]
                    for p in check_pts:
                        dj = c3d10_jacobian(xl, *p)
                        if not dj > 0.0:
                            sys.exit("element %d: non-positive Jacobian %g" % (len(elements) + 1, dj))
                        jmin = min(jmin, dj / v6)
                    elements.append(nodes)

    clamp = [nid(0, J, K) for J in range(NJ) for K in range(NK)]
    clamp.sort()

    out = sys.stdout if a.output == "-" else open(a.output, "w")
    w = out.write
    args = "--nt %d --nr %d --nz %d" % (a.nt, a.nr, a.nz)
    w("*HEADING\n")
    w("Annular disc ro=%g ri=%g t=%g m, C3D10 %s, clamped at r=ri\n" % (a.ro, a.ri, a.t, args))
    w("** Written by examples/make_disc_deck.py %s (squeal)\n" % args)
    w("** nodes %d, elements %d, min corner volume %.6g m^3, min detJ/(6V) %.4g\n"
      % (len(coords), len(elements), vmin, jmin))
    w("*NODE, NSET=NALL\n")
    for n in sorted(coords):
        c = coords[n]
        w("%d, %.12g, %.12g, %.12g\n" % (n, c[0], c[1], c[2]))
    w("*ELEMENT, TYPE=C3D10, ELSET=EDISC\n")
    for e, nodes in enumerate(elements, 1):
        w("%d, %s\n" % (e, ", ".join(str(n) for n in nodes)))
    w("*NSET, NSET=CLAMP\n")
    for s in range(0, len(clamp), 16):
        w(", ".join(str(n) for n in clamp[s:s + 16]) + "\n")
    w("*MATERIAL, NAME=CASTIRON\n*ELASTIC\n%.12g, %.12g\n*DENSITY\n%.12g\n"
      % (a.E, a.nu, a.rho))
    w("*SOLID SECTION, ELSET=EDISC, MATERIAL=CASTIRON\n")
    w("*BOUNDARY\nCLAMP, 1, 3\n")
    w("*STEP\n*FREQUENCY%s\n%d, , %.12g\n" % (", STORAGE=YES" if a.storage else "", a.nev, a.fmax))
    if a.node_file:
        w("*NODE FILE\nU\n")
    w("*END STEP\n")
    if out is not sys.stdout:
        out.close()
    sys.stderr.write("make_disc_deck: %d nodes, %d elements, %d clamped nodes, "
                     "min corner volume %.6g, min detJ/(6V) %.4g\n"
                     % (len(coords), len(elements), len(clamp), vmin, jmin))


if __name__ == "__main__":
    main()
